// The values of DEM/Sample/Type: one SampleType per sample generator, each in its own file of
// dem/scene/samples/ (its name, documentation, entries, parsing, checks, how it builds the sample
// and what `anticrack check` says of it), gathered in the table of dem/scene/sample_types.cpp.
// dem/scene/parameters.cpp and dem/scene/model.cpp only iterate over the table.
#pragma once

#include "dem/common/types.h"
#include "dem/scene/variant.h"

#include <nlohmann/json_fwd.hpp>

#include <iosfwd>
#include <string>
#include <vector>

namespace anticrack::dem
{
  class DemSystem;
  namespace parameters
  {
    struct Sample;
    struct Integration;
  }

  struct SampleType : Variant
  {
    /// Reads its own entries into `sample` (Sample::parse_parameters reads the shared ones).
    void (*parse_parameters)(dealii::ParameterHandler &prm, parameters::Sample &sample);
    /// What it needs of its entries and of the rest of `dem` (the DEM/ `sample` belongs to).
    void (*check)(const parameters::Sample &sample, const parameters::Dem &dem, Problems &problems);
    /// Adds its spheres to model.system, whose domain and material 0 are set.
    void (*build)(const SceneParameters &scene, DemModel &model);
    /// What `anticrack check` prints after "sample".
    void (*describe)(std::ostream &out, const SceneParameters &scene, const DemModel &model);
    /// Adds the generator's report to dem.sample of summary.json (which has "type"), or null.
    void (*summarize)(nlohmann::ordered_json &sample, const SceneParameters &scene, const DemModel &model);
  };

  /// Every sample type; the first is the default.
  const std::vector<SampleType> &sample_types();
  /// The documentation of DEM/Sample/Type: every type's paragraph.
  std::string sample_type_documentation();
  /// The entries of DEM/Sample that several types read (their declare_parameters name them).
  const std::vector<SharedEntry> &shared_sample_entries();
  /// Reads the entries of shared_sample_entries() that `sample.type` has.
  void parse_shared_sample_entries(dealii::ParameterHandler &prm, parameters::Sample &sample);

  // ----------------------------------------------------- what the types' files have in common
  /// " for DEM/Sample/Type = <type>": the end of a message that holds for this type only.
  std::string for_sample_type(const parameters::Sample &sample);
  /// The Verlet skin the run will use (DemSystem::choose_skin): the scene's, or 0.1 x the mean radius.
  double verlet_skin(const parameters::Integration &integration, double mean_radius);
  /// Reports a radius that is not positive; whether it is.
  bool check_radius(const parameters::Sample &sample, Problems &problems);
  /// Mean radius R and half width w of the generators' uniform radius distribution: 0 <= w < R.
  void check_radius_distribution(const parameters::Sample &sample, Problems &problems);

  /// Initial velocity amplitude for the generated samples (the generators leave them at rest).
  void add_random_velocities(const parameters::Dem &d, DemSystem &system, Index first);
  /// The generators sample in a periodic box; the specimen is periodic only along the axes the
  /// scene lists. Opening an axis before the bonding pass means that no bond crosses its faces
  /// (the spheres keep their wrapped positions inside the box).
  void open_axes_the_scene_does_not_wrap(const parameters::Dem &d, DemSystem &system);
} // namespace anticrack::dem
