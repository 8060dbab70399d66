// Console progress of a run. On a terminal one status line is rewritten in place ('\r'); when
// stdout is a file or a pipe (CI logs, `tee`) every report is a plain line, so logs stay readable.
#pragma once

#include "dem/types.h"

#include <chrono>
#include <iosfwd>
#include <string>

namespace anticrack::app
{
  struct ProgressState
  {
    dem::Index step = 0;
    dem::Index total_steps = 0;
    double time = 0;         ///< [s]
    double dt = 0;           ///< [s]
    dem::Index intact_bonds = 0;
    dem::Index bonds = 0;
    double kinetic_energy = 0; ///< [J]
  };

  class ProgressReporter
  {
  public:
    /// `first_step` is where this invocation starts (nonzero when resuming), for the rate and ETA.
    ProgressReporter(std::ostream &out, bool interactive, dem::Index first_step);

    void report(const ProgressState &state);
    /// Ends a pending in-place line so that further output starts on a fresh line.
    void finish();

    /// Whether stdout is a terminal.
    static bool stdout_is_terminal();

  private:
    std::ostream &out_;
    bool interactive_;
    dem::Index first_step_;
    std::chrono::steady_clock::time_point start_;
    std::size_t last_length_ = 0;
    bool line_pending_ = false;
  };

  /// "1:02:03" / "2:03" / "4.5 s".
  std::string format_duration(double seconds);
} // namespace anticrack::app
