// Runs a snowpack scene (fem/scene/snowpack_scene.h) into an output directory with the analysis its
// Analysis/Type names (fem/scene/analysis_type.h; one file of fem/analysis/ each: the energy release
// rate of an elastic snowpack, the quasi-static PST, the explicit dynamic PST). Writes the
// time series (series.h5 or energy_release_rate.h5) and the fields (fields/*.pvtu with a .pvd
// record) and returns the results that summary.json reports; the caller adds provenance and
// writes it. Collective over the communicator; files are written by rank 0 (fields by all ranks).
#pragma once

#include "fem/scene/snowpack_scene.h"
#include "util/phase_timer.h"

#include <mpi.h>
#include <nlohmann/json.hpp>

#include <iosfwd>
#include <string>

namespace anticrack::fem
{
  struct SnowpackRunOptions
  {
    std::string output_directory; ///< exists; outputs go directly into it
    std::ostream *log = nullptr;  ///< progress lines (rank 0), nullptr: quiet
    /// Continue a dynamic PST from DIR/checkpoint.json (same scene but for the end time and the
    /// output, same number of ranks); throws anticrack::InputError if that is not possible.
    bool resume = false;
    /// Gets the run's phases (mesh and dofs, assembly, linear solves, output; util/phase_timer.h);
    /// may be null.
    PhaseTimer *timer = nullptr;
  };

  /// Thrown when the numerics fail after the run has started (failed return mapping, Newton that
  /// cannot converge, non-finite values, unstable step); the message says what, where and when.
  /// `details` is written with the message into summary.json's "failure": what failed, where (cell,
  /// layer, position) and when (step, time, cut length, load factor), as far as the thrower knows.
  class NumericalFailure : public std::runtime_error
  {
  public:
    explicit NumericalFailure(const std::string &message, Json details = Json::object())
      : std::runtime_error(message)
      , details_(std::move(details))
    {}
    const Json &details() const { return details_; }

  private:
    Json details_;
  };

  /// Thrown when a stop signal (Ctrl-C, SIGTERM; util/stop_signals.h) ended the run after a
  /// checkpoint; the message says where it stopped. anticrack exits with 130.
  class RunInterrupted : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// Runs the scene; returns the "results" of summary.json (every number with its unit in its name).
  Json run_snowpack(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm communicator);
} // namespace anticrack::fem
