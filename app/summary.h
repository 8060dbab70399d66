// Pieces of summary.json shared by the commands: provenance of the scene, versions of everything
// that produced a result, and an atomic JSON writer (a reader never sees half a summary).
#pragma once

#include "app/scene_parameters.h"

#include <nlohmann/json.hpp>

#include <string>

namespace anticrack::app
{
  using Json = nlohmann::ordered_json;

  /// anticrack (git describe), deal.II, Eigen, HDF5, compiler, OpenMP threads.
  Json version_info();

  /// Scene file (as given and absolute), its SHA-256 and that of the canonical parameters.
  Json scene_info(const SceneParameters &scene);

  /// Writes `json` (indented) to `file` via file.tmp and a rename.
  void write_json_atomically(const std::string &file, const Json &json);

  /// deal.II's package version; defined in scene_parameters.cpp, the only deal.II unit.
  std::string deal_ii_version();
} // namespace anticrack::app
