// Pieces of every run's summary.json: the versions of everything that produced a result, and an
// atomic JSON writer (a reader never sees half a summary). Knows no module: the scene's own
// provenance is added by the scene kind that read it.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace anticrack
{
  using Json = nlohmann::ordered_json;

  /// anticrack (git describe), deal.II, Eigen, HDF5, compiler, OpenMP threads.
  Json version_info();

  /// Writes `json` (indented) to `file` via file.tmp and a rename; non-finite numbers become null.
  void write_json_atomically(const std::string &file, const Json &json);

  /// The JSON of `file` (a summary, a checkpoint's info); throws std::runtime_error naming the file if
  /// it cannot be read or parsed.
  Json read_json_file(const std::string &file);
} // namespace anticrack
