// Console progress of a run. On a terminal one status line is rewritten in place ('\r'); when
// stdout is a file or a pipe (CI logs, `tee`) every report is a plain line, so logs stay readable.
#pragma once

#include <cstdint>

#include <chrono>
#include <iosfwd>
#include <string>

namespace anticrack
{
  struct ProgressState
  {
    std::int64_t step = 0;
    std::int64_t total_steps = 0;
    double time = 0;         ///< [s]
    double dt = 0;           ///< [s]
    std::int64_t intact_bonds = 0;
    std::int64_t bonds = 0;
    double kinetic_energy = 0; ///< [J]
  };

  class ProgressReporter
  {
  public:
    /// `first_step` is where this invocation starts (nonzero when resuming), for the rate and ETA.
    ProgressReporter(std::ostream &out, bool interactive, std::int64_t first_step);

    void report(const ProgressState &state);
    /// Ends a pending in-place line so that further output starts on a fresh line.
    void finish();

    /// Whether stdout is a terminal.
    static bool stdout_is_terminal();

  private:
    std::ostream &out_;
    bool interactive_;
    std::int64_t first_step_;
    std::chrono::steady_clock::time_point start_;
    std::size_t last_length_ = 0;
    bool line_pending_ = false;
  };

  /// "1:02:03" / "2:03" / "4.5 s".
  std::string format_duration(double seconds);
} // namespace anticrack
