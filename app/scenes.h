// The scene kinds of `anticrack run`, `check` and `params`: one row per kind in a plain table
// (name, what it is, how to declare, check and run it). A scene file is matched to its kind
// here; everything a kind does lives in its module.
#pragma once

#include "util/parameter_files.h"
#include "util/run_options.h"

#include <iosfwd>
#include <string>

namespace anticrack::app
{
  /// Runs a scene of any kind; returns the exit code; throws InputError before writing anything.
  int run_scene(const RunOptions &options);

  /// Validates a scene of any kind and prints what a run would do; returns the exit code.
  int check_scene(const std::string &scene_file, int threads);

  /// Prints every entry a scene can set: one of kind `kind` with the default variants (itself a
  /// valid scene), or with `every_variant` the entries of every variant (DEM/Sample/Type,
  /// DEM/Loading/Test, Analysis/Type), or those of `scene_file` (its kind and variants). Throws
  /// InputError for an unknown kind.
  void print_scene_parameters(std::ostream &out, ParameterFormat format, const std::string &kind,
                              const std::string &scene_file = "", bool every_variant = false);

  /// The names of the kinds, for the command line's help and choices.
  std::string scene_kind_names();
} // namespace anticrack::app
