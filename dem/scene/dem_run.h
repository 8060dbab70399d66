// The run of a DEM scene (one virtual-laboratory test or a free simulation).
//
// A run is validated completely before it touches the disk: the scene is parsed and checked, the
// model is built and initialised, and (with --resume) the checkpoint is matched against the scene
// and loaded. Only then is the output directory created. A numerical failure after that point
// still leaves a complete summary.json ("status": "failed") and the history up to the failure.
#pragma once

#include "dem/scene/failure_analysis.h"
#include "util/run_options.h"
#include "util/run_summary.h"

#include <memory>
#include <optional>
#include <string>

namespace anticrack::dem
{
  struct SceneParameters;
  struct DemModel;

  /// What a run hands to its caller in memory, beside the files it wrote.
  struct DemRunRecord
  {
    int exit_code = 0;
    Json summary;    ///< what summary.json holds (null if it could not be written)
    std::optional<TestFailureAnalysis> failure_analysis; ///< of a clump-driven test (summary.json dem.failure_analysis)
  };

  /// Runs a model built from `scene` into options.output_directory: prepare (directory checks,
  /// --resume), then the time loop and every output. Throws InputError.
  DemRunRecord run_dem_model(const SceneParameters &scene, std::unique_ptr<DemModel> model, const RunOptions &options);

  /// `anticrack run` of a DEM scene without a campaign: builds the model, then run_dem_model.
  int run_dem_scene(const SceneParameters &scene, const RunOptions &options);

  /// `anticrack check` of a DEM scene: builds the model and prints what a run would do (for a campaign
  /// whose first realization has no load path, a note: the campaign records such tests and goes on).
  void check_dem_scene(const SceneParameters &scene, int threads);
} // namespace anticrack::dem
