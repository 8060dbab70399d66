#include "util/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace anticrack
{
  std::string format_duration(const double seconds)
  {
    if (!std::isfinite(seconds) || seconds < 0)
      return "?";
    if (seconds < 60)
    {
      std::ostringstream s;
      s << std::fixed << std::setprecision(1) << seconds << " s";
      return s.str();
    }
    const long total = std::lround(seconds);
    char text[32];
    if (total >= 3600)
      std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", total / 3600, (total / 60) % 60, total % 60);
    else
      std::snprintf(text, sizeof text, "%ld:%02ld", total / 60, total % 60);
    return text;
  }

  bool ProgressReporter::stdout_is_terminal() { return isatty(fileno(stdout)) != 0; }

  ProgressReporter::ProgressReporter(std::ostream &out, const bool interactive, const std::int64_t first_step)
    : out_(out), interactive_(interactive), first_step_(first_step), start_(std::chrono::steady_clock::now())
  {}

  void ProgressReporter::report(const ProgressState &s)
  {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const double done = static_cast<double>(s.step - first_step_);
    const double rate = elapsed > 0 ? done / elapsed : 0;
    const double eta = rate > 0 ? (s.total_steps - s.step) / rate : NAN;
    const int width = static_cast<int>(std::to_string(s.total_steps).size());

    std::ostringstream line;
    line << "step " << std::setw(width) << s.step << "/" << s.total_steps << " (" << std::fixed
         << std::setprecision(1) << std::setw(5) << 100.0 * s.step / std::max<std::int64_t>(s.total_steps, 1)
         << "%)" << std::defaultfloat << std::setprecision(4) << "  t = " << s.time << " s  dt = " << s.dt
         << " s  bonds " << s.intact_bonds << "/" << s.bonds << "  E_kin = " << s.kinetic_energy << " J  "
         << std::setprecision(3) << rate << " steps/s  ETA " << format_duration(eta);
    std::string text = line.str();
    if (interactive_)
    {
      // Pad over the remainder of a longer previous line.
      const std::size_t length = text.size();
      if (length < last_length_)
        text.append(last_length_ - length, ' ');
      last_length_ = length;
      out_ << '\r' << text << std::flush;
      line_pending_ = true;
    }
    else
      out_ << text << '\n' << std::flush;
  }

  void ProgressReporter::finish()
  {
    if (line_pending_)
      out_ << '\n' << std::flush;
    line_pending_ = false;
    last_length_ = 0;
  }
} // namespace anticrack
