// Ctrl-C and SIGTERM end a long run between two of its steps, with a checkpoint where the run
// kind writes them, instead of killing it with half-written files (exit code 130, input_error.h).
// The handler only sets a flag; the run polls it where it can stop cleanly. Under mpirun each rank
// gets the signal, not necessarily in the same step: MPI runs agree on the stop collectively.
#pragma once

namespace anticrack
{
  /// Installs the SIGINT / SIGTERM handler for the lifetime of the object (the previous handlers
  /// come back after it) and clears the flag.
  class StopSignals
  {
  public:
    StopSignals();
    ~StopSignals();
    StopSignals(const StopSignals &) = delete;
    StopSignals &operator=(const StopSignals &) = delete;

    /// True once a stop signal has arrived (on this process).
    static bool requested();

  private:
    void (*previous_int_)(int);
    void (*previous_term_)(int);
  };
} // namespace anticrack
