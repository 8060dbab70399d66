// Pieces of every run's summary.json: the versions of everything that produced a result, and an
// atomic JSON writer (a reader never sees half a summary). Knows no module: the scene's own
// provenance is added by the scene kind that read it.
#pragma once

#include "util/input_error.h"

#include <nlohmann/json.hpp>

#include <string>

namespace anticrack
{
  using Json = nlohmann::ordered_json;

  /// anticrack (git describe), deal.II, Eigen, HDF5, compiler, OpenMP threads.
  Json version_info();

  /// Writes `json` (indented) to `file` via file.tmp and a rename; non-finite numbers become null.
  void write_json_atomically(const std::string &file, const Json &json);

  /// The JSON of `file` (a summary, a checkpoint's info, written by an earlier run); throws
  /// std::runtime_error naming the file if it cannot be read, UnusableOutputFile
  /// (util/input_error.h) if it is not one JSON object (torn, empty, foreign).
  Json read_json_file(const std::string &file);

  /// Whether the run that wrote `summary_file` (its summary.json) completed from a scene file whose
  /// sha256 is `scene_sha256` and from the material files it recorded as they are now
  /// ("status", "scene/file_sha256", "scene/material_files/<layer>/{file, sha256}"): a pipeline or a
  /// study resumed after a kill does not run it again. False if the file does not exist; an
  /// unusable file throws UnusableOutputFile.
  bool completed_from_scene(const std::string &summary_file, const std::string &scene_sha256);

  /// `read(json)` on the JSON object of an earlier run's `file`: a JSON key or type error in `read`
  /// (a file of another kind or an older version: a summary of a DEM run where a pipeline's is
  /// expected) becomes UnusableOutputFile naming the file and what it should be (`kind`, "a
  /// pipeline's summary"), with `remedy` (empty: the generic advice). Never a library's bare text.
  template <class Read>
  auto interpret_json_file(const std::string &file, const std::string &kind, Read &&read,
                           const std::string &remedy = "")
  {
    Json json;
    try
    {
      json = read_json_file(file);
    }
    catch (const UnusableOutputFile &e)
    {
      throw UnusableOutputFile(file, e.problem(), remedy); // with this reader's advice
    }
    try
    {
      return read(json);
    }
    catch (const nlohmann::json::exception &e)
    {
      // "[json.exception.out_of_range.403] key 'stages' not found": the library's words without its code.
      const std::string what = e.what();
      const auto code_end = what.find("] ");
      throw UnusableOutputFile(file, "is not " + kind + " (" + (code_end == std::string::npos ? what : what.substr(code_end + 2)) + ")",
                               remedy);
    }
  }
} // namespace anticrack
