// Errors a user can fix by editing an input file or the command line (a scene, a material file, a
// campaign), and the exit codes of the `anticrack` executable. Input errors are raised before any
// output is written; app/main.cpp holds the one table that maps every error type of the modules to
// its exit code and the title of its message.
#pragma once

#include <stdexcept>

namespace anticrack
{
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// Exit codes of the `anticrack` executable.
  enum ExitCode : int
  {
    exit_success = 0,
    exit_numerical_failure = 1, ///< a run that had started failed, or a snowpack collapsed under gravity (summary.json says where and when)
    exit_bad_input = 2,         ///< nothing was written
    exit_interrupted = 130      ///< SIGINT or SIGTERM; a checkpoint was written where the run kind has them
  };
} // namespace anticrack
