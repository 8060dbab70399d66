// `anticrack run` and `anticrack check` for scenes with the DEM component.
//
// A run is validated completely before it touches the disk: the scene is parsed and checked, the
// model is built and initialised, and (with --resume) the checkpoint is matched against the scene
// and loaded. Only then is the output directory created. A numerical failure after that point
// still leaves a complete summary.json ("status": "failed") and the history up to the failure.
#pragma once

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
  };

  /// Returns the exit code (ExitCode); throws InputError for problems found before writing.
  int run_scene(const RunOptions &options);

  /// Validates a scene and builds its model; prints what a run would do. Returns the exit code.
  int check_scene(const std::string &scene_file, int threads);
} // namespace anticrack::app
