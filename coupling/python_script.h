// The project's Python scripts (plots and reports, scripts/), run on a run's output directory by
// the interpreter CMake found (ANTICRACK_PYTHON, with matplotlib, h5py and numpy).
#pragma once

#include <string>

namespace anticrack::coupling
{
  /// Runs scripts/`script` with `directory` as its argument; returns true if it succeeded. On
  /// failure prints to stderr what failed and that `outputs` are complete without it.
  bool run_python_script(const std::string &script, const std::string &directory, const std::string &outputs);
} // namespace anticrack::coupling
