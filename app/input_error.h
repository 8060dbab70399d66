// Errors a user can fix by editing the scene or the command line. They are raised before any
// output is written, and main() turns them into exit code 2 (numerical failures of a run that has
// started give exit code 1).
#pragma once

#include "util/input_error.h"

namespace anticrack::app
{
  using anticrack::InputError;

  /// Exit codes of the `anticrack` executable.
  enum ExitCode : int
  {
    exit_success = 0,
    exit_numerical_failure = 1,
    exit_bad_input = 2,
    exit_interrupted = 130
  };
} // namespace anticrack::app
