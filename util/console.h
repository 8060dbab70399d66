// Console output that one rank prints and the others swallow: the role of deal.II's
// ConditionalOStream, without deal.II, for every run kind (DEM runs, campaigns, calibrations and
// the FE analyses). Progress lines, banners and error notes of a run go through it, so that under
// mpirun a line appears once, not once per rank.
//
//   ConditionalStream console = root_console();
//   console << "anticrack campaign: " << tests << " tests\n";
//   console.line("[fem] step ", step, ", t = ", t, " s");   // one line, flushed
#pragma once

#include <iostream>
#include <ostream>

namespace anticrack
{
  class ConditionalStream
  {
  public:
    /// Writes to `*out` when `active` and `out` is not null; otherwise writes nothing.
    ConditionalStream(std::ostream *out, bool active) : out_(active ? out : nullptr) {}

    [[nodiscard]] bool active() const { return out_ != nullptr; }

    template <typename T>
    ConditionalStream &operator<<(const T &value)
    {
      if (out_)
        *out_ << value;
      return *this;
    }

    ConditionalStream &operator<<(std::ostream &(*manipulator)(std::ostream &))
    {
      if (out_)
        *out_ << manipulator;
      return *this;
    }

    /// The parts, then a newline, flushed (progress lines of long runs show at once).
    template <typename... T>
    void line(const T &...parts)
    {
      if (!out_)
        return;
      (*out_ << ... << parts) << std::endl;
    }

  private:
    std::ostream *out_;
  };

  /// `out` (std::cout by default) on rank 0, silent on the other ranks. The rank is MPI's when MPI
  /// is initialised, otherwise the launcher's (util/mpi_session.h): correct before MPI starts too.
  ConditionalStream root_console(std::ostream &out = std::cout);

  /// Whether this process is rank 0 in the sense of root_console().
  bool is_root_process();
} // namespace anticrack
