// Scenes of kind `pipeline` (`set Scene = pipeline`): the chain from a DEM weak layer to the FE
// answers, by reference to the scenes of its stages, so that each stage stays a scene a user can
// run alone:
//
//   subsection Pipeline
//     set Weak layer scene = weak_layer.prm          # kind calibration: DEM sample, campaign, fit
//     set Snowpack scenes  = pst_flat.prm, pst_slope.prm   # kind snowpack: their weak layer gets
//   end                                                    # the calibrated material
//   subsection Snow units                                  # coupling/snow_units.h
//     set Bond tensile strength [Pa] = 3e5
//     set Bond modulus [Pa]          = 3e8
//     set Grain diameter [m]         = 1e-3
//     set Particle density [kg/m^3]  = 917
//   end
//
// Paths are relative to the pipeline scene's directory. What the stages do, their outputs and
// their resumption: coupling/pipeline.h.
#pragma once

#include "coupling/calibrate.h"
#include "coupling/profile_specimen.h"
#include "coupling/snow_units.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::coupling
{
  /// A weak layer the pipeline calibrates: the weak layer scene's own specimen, or that scene with
  /// the specimen of one class of the pits' weak layers (Pipeline/Weak layer specimen = profile,
  /// coupling/profile_specimen.h).
  struct WeakLayerVariant
  {
    std::string name;      ///< its stage: "weak layer", or "weak layer 150 kg/m^3, 10 grains" of several
    std::string directory; ///< its folder in the pipeline's: weak_layer, or weak_layer_150kgm3_10grains of several
    std::optional<ProfileSpecimen> specimen;
    /// coupling::specimen_changes of the specimen, set after the user's Weak layer scene changes.
    std::vector<std::pair<std::string, std::string>> specimen_changes;
  };

  /// The weak layer of one snowpack scene.
  struct SnowpackWeakLayer
  {
    std::size_t variant = 0;   ///< into PipelineScene::weak_layers
    double grain_diameter = 0; ///< the pit's grain size [m]; 0: Snow units/Grain diameter [m]
    nlohmann::ordered_json record; ///< coupling::specimen_record, or null
  };

  struct PipelineScene
  {
    std::string file;                         ///< the pipeline scene itself
    std::string weak_layer_scene;             ///< a calibration scene (absolute, normalised)
    std::vector<std::string> snowpack_scenes; ///< snowpack scenes (absolute, normalised)
    SnowUnits snow;
    bool uncertainty = true;                  ///< carry the calibration's intervals to the answers
    /// Pipeline/Snowpack scene changes: (path, value) applied to every snowpack scene, e.g.
    /// ("Mesh/Weak layer elements", "2").
    std::vector<std::pair<std::string, std::string>> snowpack_changes;
    /// Pipeline/Weak layer scene changes: (path, value) applied to the weak layer's scene, e.g.
    /// ("Campaign/Compaction strain rate [1/s]", "5") to add the compaction tests to a campaign.
    std::vector<std::pair<std::string, std::string>> weak_layer_changes;
    /// The entries that run the weak layer's DEM at the snow's bond modulus over strength
    /// (coupling::snow_ratio_changes), set after weak_layer_changes; empty at the DEM's own ratio.
    std::vector<std::pair<std::string, std::string>> snow_ratio_changes;
    /// Pipeline/Weak layer specimen = profile: each snowpack scene's weak layer is sampled at its
    /// pit's density and thickness in grains, one calibration per class (specimen_rules).
    bool specimen_from_profile = false;
    SpecimenRules specimen_rules;
    std::vector<WeakLayerVariant> weak_layers;           ///< one, or one per class of the pits'
    std::vector<SnowpackWeakLayer> snowpack_weak_layers; ///< per snowpack scene

    /// Whether weak layer k's stage runs a copy of its scene (with changes of any kind).
    [[nodiscard]] bool weak_layer_changed(std::size_t k) const
    {
      return !weak_layer_changes.empty() || !snow_ratio_changes.empty() || !weak_layers[k].specimen_changes.empty();
    }
  };

  /// The options of the weak layer's calibration: those of the calibration scene `file` (the
  /// weak layer's scene, or the copy the pipeline runs), or the defaults for a campaign scene, read
  /// and checked with `changes` set after the file's own entries; throws InputError.
  CalibrateOptions weak_layer_calibration(const PipelineScene &scene, const std::string &file,
                                          const std::vector<std::pair<std::string, std::string>> &changes = {});

  /// The text of weak layer k's scene as the pipeline runs it: the file, then a block setting each
  /// of scene.weak_layer_changes, then one of its specimen's changes, then one of
  /// scene.snow_ratio_changes (the last setting of an entry wins).
  std::string weak_layer_scene_text(const PipelineScene &scene, std::size_t k);

  /// What decides weak layer k's material, and nothing of where it is asked for: its scene text
  /// with the pipeline's changes (the blocks' comments naming no pipeline) and the snow units. The
  /// material cache's key hashes it (coupling/material_cache.h).
  std::string weak_layer_material_inputs(const PipelineScene &scene, std::size_t k);

  /// The snow units as the pipeline's stage hashes record them.
  std::string snow_units_text(const SnowUnits &snow);

  /// The text of snowpack scene `file` as the pipeline runs it: the file, then a block setting each
  /// of scene.snowpack_changes (the last setting of an entry wins), then, if `material_file` is not
  /// empty, the weak layer's Material file.
  std::string snowpack_scene_text(const PipelineScene &scene, const std::string &file, const std::string &material_file);

  /// Declares the entries of a pipeline scene.
  void declare_pipeline_scene(dealii::ParameterHandler &prm);

  /// Reads and checks `file` and every scene it names (each by its own reader); throws InputError
  /// naming the file and the entry (a missing entry, a scene of another kind, a file that does not
  /// exist, a snowpack scene whose weak layer is not a cohesive Cam-Clay layer).
  PipelineScene read_pipeline_scene(const std::string &file);
} // namespace anticrack::coupling
