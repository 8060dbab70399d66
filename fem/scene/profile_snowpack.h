// The snowpack of a real pit (subsection Snowpack/Profile of a snowpack scene): the slab is the
// profile's layers above its weak layer, each elastic with its density measured or inferred and E,
// nu and sigma_t by the laws named (profile/layer_properties.h, docs/profile.md); the weak layer's
// thickness is the profile's, its material the scene's (Snowpack/Weak layer: a calibrated material
// file, inline entries); the substratum is the scene's. Where the profile holds propagation saw
// tests, the scene can take the slope angle and the column length from one of them, and the test's
// observation is recorded beside the prediction.
#pragma once

#include "fem/scene/snowpack_scene.h"

#include <nlohmann/json.hpp>

#include <set>
#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::fem
{
  /// Declares the entries of subsection Profile (the caller has entered Snowpack).
  void declare_profile_entries(dealii::ParameterHandler &prm);

  /// Reads subsection Profile (entered by the caller within Snowpack) and, when it names a file,
  /// replaces the scene's slab by the profile's, sets the weak layer's thickness and (if asked) the
  /// slope and column length from the profile's saw test; records in `scene.profile_record` every
  /// layer with each value and its source, and the observed test. `given`: the entries the scene
  /// text sets ("Snowpack/Slab layer 1/Thickness [m]"), of which those the profile replaces are
  /// refused. Throws InputError naming the scene, the entry or the profile file, layer and field.
  void apply_profile(dealii::ParameterHandler &prm, SnowpackScene &scene, const std::set<std::string> &given,
                     const std::string &scene_file);
} // namespace anticrack::fem
