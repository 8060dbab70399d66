// `anticrack run` and `anticrack check` for scenes with the DEM component.
//
// A run is validated completely before it touches the disk: the scene is parsed and checked, the
// model is built and initialised, and (with --resume) the checkpoint is matched against the scene
// and loaded. Only then is the output directory created. A numerical failure after that point
// still leaves a complete summary.json ("status": "failed") and the history up to the failure.
#pragma once

#include <nlohmann/json.hpp>

#include <memory>
#include <string>

namespace anticrack::app
{
  struct RunOptions
  {
    std::string scene_file;
    std::string output_directory;
    bool resume = false;
    bool overwrite = false;   ///< replace the outputs of an earlier run in the directory
    int threads = -1;         ///< < 0: DEM/Threads of the scene
    std::string command_line; ///< for the summary
    bool quiet = false;       ///< no start, progress and end lines (campaign tests)
    std::string progress_label; ///< quiet runs with a label print "<label>: step ..." once a minute
    nlohmann::ordered_json labels; ///< copied into summary.json as "labels" (a campaign test's identity)
  };

  struct SceneParameters;
  struct DemModel;

  /// Returns the exit code (ExitCode); throws InputError for problems found before writing.
  /// A scene with a campaign (Campaign/Loading angles) runs it (app/campaign.h).
  int run_scene(const RunOptions &options);

  /// Runs a model built from `scene` into options.output_directory: prepare (directory checks,
  /// --resume), then the time loop and every output. Returns the exit code; throws InputError.
  int run_dem_model(const SceneParameters &scene, std::unique_ptr<DemModel> model, const RunOptions &options);

  /// Validates a scene and builds its model; prints what a run would do. Returns the exit code.
  int check_scene(const std::string &scene_file, int threads);
} // namespace anticrack::app
