// What `anticrack run` hands to every scene kind: the scene, where its outputs go, and how the
// run is started. Campaigns fill in the last three for each of their tests.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace anticrack
{
  struct RunOptions
  {
    std::string scene_file;
    std::string output_directory;
    bool resume = false;
    bool overwrite = false;   ///< replace the outputs of an earlier run in the directory
    int threads = -1;         ///< OpenMP threads of a DEM run; < 0: DEM/Threads of the scene
    std::string command_line; ///< for the summary
    bool quiet = false;       ///< no start, progress and end lines (campaign tests)
    std::string progress_label; ///< quiet runs with a label print "<label>: step ..." once a minute
    nlohmann::ordered_json labels; ///< copied into summary.json as "labels" (a campaign test's identity)
    /// Pipelines: the folder of calibrated weak layers shared between runs ("": none;
    /// coupling/material_cache.h).
    std::string material_cache;
  };
} // namespace anticrack
