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

  /// A run that started and stopped without results: summary.json gets `status` and, as its
  /// "failure", `details` with the message; anticrack prints `heading` + message and exits 1.
  class RunStopped : public std::runtime_error
  {
  public:
    RunStopped(const std::string &message, Json details, std::string status, std::string heading)
      : std::runtime_error(message)
      , details_(std::move(details))
      , status_(std::move(status))
      , heading_(std::move(heading))
    {}
    const Json &details() const { return details_; }
    const std::string &status() const { return status_; }
    const std::string &heading() const { return heading_; }

  private:
    Json details_;
    std::string status_, heading_;
  };

  /// Thrown when the numerics fail after the run has started (failed return mapping, Newton that
  /// cannot converge, non-finite values, unstable step); the message says what, where and when.
  /// `details`: what failed, where (cell, layer, position) and when (step, time, cut length, load
  /// factor), as far as the thrower knows. Status "failed".
  class NumericalFailure : public RunStopped
  {
  public:
    explicit NumericalFailure(const std::string &message, Json details = Json::object())
      : RunStopped(message, std::move(details), "failed", "numerical failure: ")
    {}
  };

  /// Thrown before the gravity ramp of a PST when the weak layer cannot carry the layers above it
  /// (docs/fem_closed_forms.md §5.2): the snowpack collapses under gravity alone, before any cut.
  /// A physical answer, not a numerical failure: status "collapsed under gravity", `details` with
  /// what, where and the strength needed.
  class CollapseUnderGravity : public RunStopped
  {
  public:
    CollapseUnderGravity(const std::string &message, Json details)
      : RunStopped(message, std::move(details), "collapsed under gravity", "")
    {}
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
