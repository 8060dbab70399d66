#include "util/worker_processes.h"

#include <sys/mman.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <stdexcept>

namespace anticrack
{
  namespace
  {
    // The workers' pids for the signal handler (async-signal-safe: it only reads these and calls kill).
    constexpr int max_workers = 1024;
    volatile pid_t worker_pids[max_workers];
    volatile std::sig_atomic_t worker_count = 0;
    // Set by a stop signal: run_jobs_in_worker_processes starts no further job after it.
    volatile std::sig_atomic_t stop_forwarded = 0;

    extern "C" void forward_to_workers(int signal)
    {
      stop_forwarded = 1;
      for (int k = 0; k < worker_count; ++k)
        if (worker_pids[k] > 0)
          kill(worker_pids[k], signal);
    }

    void flush_streams()
    {
      std::cout.flush();
      std::cerr.flush();
      std::fflush(nullptr);
    }

    struct Started
    {
      pid_t pid = -1;
      int report_pipe = -1;
      std::chrono::steady_clock::time_point at;
    };

    /// Forks the worker of `member`; returns pid -1 (and sets `error`) if the pipe or the fork fails.
    Started start_worker(int member, const std::function<int(int, std::string &)> &job,
                         const std::vector<int> &open_pipes, void (*worker_int)(int), void (*worker_term)(int),
                         std::string &error)
    {
      int channel[2];
      if (pipe(channel) != 0)
      {
        error = std::string("pipe: ") + std::strerror(errno);
        return {};
      }
      const pid_t pid = fork();
      if (pid < 0)
      {
        error = std::strerror(errno);
        close(channel[0]), close(channel[1]);
        return {};
      }
      if (pid == 0)
      {
        // The worker's own signals: the parent's (it stops its run between chunks of steps).
        worker_count = 0;
        std::signal(SIGINT, worker_int);
        std::signal(SIGTERM, worker_term);
        close(channel[0]);
        for (const int other : open_pipes)
          close(other);
        int code = 1;
        std::string report;
        try
        {
          code = job(member, report);
        }
        catch (const std::exception &e)
        {
          std::cerr << "worker " << member << ": " << e.what() << "\n";
          report.clear();
        }
        flush_streams();
        // At most one pipe buffer, written at once: the parent reads it after the worker has exited.
        if (report.size() > max_worker_report)
          report.resize(max_worker_report);
        if (!report.empty() && write(channel[1], report.data(), report.size()) < 0)
          code = code == 0 ? 1 : code;
        close(channel[1]);
        std::_Exit(code); // not exit(): the parent's atexit handlers and static objects are the parent's
      }
      close(channel[1]);
      return {pid, channel[0], std::chrono::steady_clock::now()};
    }

    WorkerExit collect(const Started &worker, int status)
    {
      WorkerExit exit;
      if (WIFSIGNALED(status))
        exit = {128 + WTERMSIG(status), WTERMSIG(status), "", 0};
      else
        exit = {WEXITSTATUS(status), 0, "", 0};
      exit.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - worker.at).count();
      char buffer[max_worker_report];
      ssize_t n;
      while ((n = read(worker.report_pipe, buffer, sizeof buffer)) > 0 || (n < 0 && errno == EINTR))
        if (n > 0)
          exit.report.append(buffer, static_cast<std::size_t>(n));
      close(worker.report_pipe);
      return exit;
    }
  } // namespace

  std::vector<WorkerExit> run_jobs_in_worker_processes(int jobs, int concurrent,
                                                       const std::function<int(int, std::string &)> &job,
                                                       const std::function<void(int, const WorkerExit &)> &on_exit)
  {
    if (jobs < 1 || concurrent < 1 || concurrent > max_workers)
      throw std::invalid_argument("run_jobs_in_worker_processes: " + std::to_string(jobs) + " jobs, " +
                                  std::to_string(concurrent) + " at a time (1 to " + std::to_string(max_workers) + ")");
    flush_streams();
    stop_forwarded = 0;
    void (*previous_int)(int) = std::signal(SIGINT, forward_to_workers);
    void (*previous_term)(int) = std::signal(SIGTERM, forward_to_workers);
    std::vector<WorkerExit> exits(static_cast<std::size_t>(jobs));
    for (WorkerExit &exit : exits)
      exit.started = false;
    std::vector<Started> running(static_cast<std::size_t>(jobs));
    std::vector<int> open_pipes;
    std::string fork_error;
    int next = 0, active = 0;
    const auto refresh_handler_list = [&] {
      worker_count = 0;
      int k = 0;
      for (const Started &w : running)
        if (w.pid > 0)
          worker_pids[k++] = w.pid;
      worker_count = k;
    };
    while (next < jobs || active > 0)
    {
      while (fork_error.empty() && stop_forwarded == 0 && next < jobs && active < concurrent)
      {
        const Started w = start_worker(next, job, open_pipes, previous_int, previous_term, fork_error);
        if (w.pid < 0)
          break;
        running[static_cast<std::size_t>(next)] = w;
        open_pipes.push_back(w.report_pipe);
        ++next, ++active;
        refresh_handler_list();
      }
      if (active == 0)
        break; // a fork failed and nothing is left to wait for
      int status = 0;
      const pid_t ended = waitpid(-1, &status, 0);
      if (ended < 0)
      {
        if (errno == EINTR)
          continue;
        break;
      }
      for (std::size_t k = 0; k < running.size(); ++k)
        if (running[k].pid == ended)
        {
          exits[k] = collect(running[k], status);
          open_pipes.erase(std::find(open_pipes.begin(), open_pipes.end(), running[k].report_pipe));
          running[k].pid = -1;
          --active;
          refresh_handler_list();
          if (on_exit)
            on_exit(static_cast<int>(k), exits[k]);
        }
    }
    std::signal(SIGINT, previous_int);
    std::signal(SIGTERM, previous_term);
    worker_count = 0;
    if (!fork_error.empty())
      throw std::runtime_error("could not start worker process " + std::to_string(next) + " of " +
                               std::to_string(jobs) + ": " + fork_error);
    return exits;
  }

  std::vector<WorkerExit> run_in_worker_processes(int members,
                                                  const std::function<int(int member, std::string &report)> &job)
  {
    return run_jobs_in_worker_processes(members, members, job);
  }

  class LineLabel::Buffer : public std::streambuf
  {
  public:
    Buffer(std::streambuf *target, std::string label) : target_(target), label_(std::move(label)) {}

  protected:
    int overflow(int c) override
    {
      if (c == traits_type::eof())
        return traits_type::not_eof(c);
      if (at_line_start_ && target_->sputn(label_.data(), static_cast<std::streamsize>(label_.size())) !=
                              static_cast<std::streamsize>(label_.size()))
        return traits_type::eof();
      at_line_start_ = c == '\n';
      return target_->sputc(static_cast<char>(c));
    }
    int sync() override { return target_->pubsync(); }

  private:
    std::streambuf *target_;
    std::string label_;
    bool at_line_start_ = true;
  };

  LineLabel::LineLabel(std::ostream &stream, std::string label)
    : stream_(stream), original_(stream.rdbuf()), buffer_(std::make_unique<Buffer>(original_, std::move(label)))
  {
    stream_.rdbuf(buffer_.get());
  }

  LineLabel::~LineLabel()
  {
    stream_.flush();
    stream_.rdbuf(original_);
  }

  std::string describe_worker_exit(int member, const WorkerExit &exit)
  {
    if (exit.signal != 0)
      return "worker " + std::to_string(member) + " ended by signal " + std::to_string(exit.signal) + " (" +
             strsignal(exit.signal) + ")";
    return "worker " + std::to_string(member) + " exited with code " + std::to_string(exit.exit_code);
  }
  SharedCounter::SharedCounter()
    : memory_(mmap(nullptr, sizeof(std::atomic<long>), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0))
  {
    if (memory_ == MAP_FAILED)
      throw std::runtime_error(std::string("SharedCounter: mmap failed: ") + std::strerror(errno));
    static_assert(std::atomic<long>::is_always_lock_free, "a counter shared across processes must be lock-free");
    new (memory_) std::atomic<long>(0);
  }

  SharedCounter::~SharedCounter() { munmap(memory_, sizeof(std::atomic<long>)); }

  long SharedCounter::next() { return static_cast<std::atomic<long> *>(memory_)->fetch_add(1); }
} // namespace anticrack
