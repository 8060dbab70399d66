// Independent jobs side by side on every core without mpirun: the process forks one worker per
// member, each runs its share and exits; the parent waits for all of them. Under mpirun the ranks
// are the team instead (MpiSession). A worker is a copy of the parent at the fork, so it needs no
// arguments, scene re-reading or launcher, and its results are those of the same job run in the
// parent.
//
// Why processes and not threads: the jobs write HDF5, and the HDF5 library Debian builds for Open
// MPI is not thread-safe; a process has its own library state. Why fork before anything else
// runs: a fork copies only the calling thread, so the parent must not have started an OpenMP team
// or MPI yet (the callers fork before their first parallel region; a serial run never
// initialises MPI, util/mpi_session.h), and the workers use one thread each.
//
// Signals: SIGINT and SIGTERM to the parent are passed on to the workers (which stop between
// chunks of steps, dem/scene/dem_run.cpp); the parent keeps waiting until every worker has exited.
#pragma once

#include <functional>
#include <memory>
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

namespace anticrack
{
  /// How one worker ended.
  struct WorkerExit
  {
    int exit_code = 0; ///< its return value, or 128 + signal if a signal ended it
    int signal = 0;    ///< the signal that ended it (0: it returned)
    std::string report; ///< what the job put in its `report` (empty if it did not return)
    double wall_s = 0;  ///< from its fork to its end, as the parent saw it [s]
    bool started = true; ///< false: a stop signal came before its turn (run_jobs_in_worker_processes)
  };

  /// The largest report a worker can send back [bytes] (a pipe's atomic write; longer ones are cut).
  inline constexpr std::size_t max_worker_report = 4096;

  /// Runs `job(member, report)` for member = 0 .. members − 1, each in a forked worker process, and
  /// returns how each ended with the report it left (a short text, e.g. its phase times, passed
  /// back through a pipe). In a worker, an exception from `job` is printed to stderr with the
  /// member's label and ends it with exit code 1; standard streams are flushed before the fork and
  /// before a worker exits. Throws std::runtime_error if a fork fails (the workers already started
  /// are waited for first). Precondition: 1 <= members <= 1024; no OpenMP team and no MPI in the
  /// caller yet.
  std::vector<WorkerExit> run_in_worker_processes(int members,
                                                  const std::function<int(int member, std::string &report)> &job);

  /// The same for `jobs` jobs of which at most `concurrent` run at a time: a worker is forked for
  /// the next job whenever one ends (each job its own process, e.g. an FE analysis, which
  /// initialises MPI and can do so once per process). `on_exit(job, exit)` is called in the parent
  /// as each ends, in the order they end. After SIGINT or SIGTERM (passed on to the running workers)
  /// no further job is started: those left have `started` false.
  std::vector<WorkerExit> run_jobs_in_worker_processes(int jobs, int concurrent,
                                                       const std::function<int(int job, std::string &report)> &job,
                                                       const std::function<void(int job, const WorkerExit &exit)> &on_exit = {});

  /// Prefixes every line written to a stream with a label while it lives (e.g. "[pst_flat] " on a
  /// worker's std::cout, so that the lines of workers side by side can be told apart).
  class LineLabel
  {
  public:
    LineLabel(std::ostream &stream, std::string label);
    ~LineLabel();
    LineLabel(const LineLabel &) = delete;
    LineLabel &operator=(const LineLabel &) = delete;

  private:
    class Buffer;
    std::ostream &stream_;
    std::streambuf *original_;
    std::unique_ptr<Buffer> buffer_;
  };

  /// A counter that the workers forked after it share (anonymous shared memory): next() hands out
  /// 0, 1, 2, ... once each across all of them, so that workers pull jobs from one queue as they
  /// become free instead of running fixed shares.
  class SharedCounter
  {
  public:
    SharedCounter();
    ~SharedCounter();
    SharedCounter(const SharedCounter &) = delete;
    SharedCounter &operator=(const SharedCounter &) = delete;
    /// The next value (atomic across processes).
    long next();

  private:
    void *memory_;
  };

  /// "worker 1 ended by signal 9 (Killed)" or "worker 1 exited with code 2", for messages.
  std::string describe_worker_exit(int member, const WorkerExit &exit);
} // namespace anticrack
