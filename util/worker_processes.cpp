#include "util/worker_processes.h"

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
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

    extern "C" void forward_to_workers(int signal)
    {
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

    WorkerExit wait_for(pid_t pid)
    {
      int status = 0;
      while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
          return {1, 0};
      if (WIFSIGNALED(status))
        return {128 + WTERMSIG(status), WTERMSIG(status)};
      return {WEXITSTATUS(status), 0};
    }
  } // namespace

  std::vector<WorkerExit> run_in_worker_processes(int members,
                                                  const std::function<int(int member, std::string &report)> &job)
  {
    if (members < 1 || members > max_workers)
      throw std::invalid_argument("run_in_worker_processes: " + std::to_string(members) + " workers (1 to " +
                                  std::to_string(max_workers) + ")");
    flush_streams();
    std::vector<pid_t> pids;
    std::string fork_error;
    worker_count = 0;
    void (*previous_int)(int) = std::signal(SIGINT, forward_to_workers);
    void (*previous_term)(int) = std::signal(SIGTERM, forward_to_workers);
    std::vector<int> report_pipes;
    for (int member = 0; member < members; ++member)
    {
      int channel[2];
      if (pipe(channel) != 0)
      {
        fork_error = std::string("pipe: ") + std::strerror(errno);
        break;
      }
      const pid_t pid = fork();
      if (pid < 0)
      {
        fork_error = std::strerror(errno);
        close(channel[0]), close(channel[1]);
        break;
      }
      if (pid == 0)
      {
        // The worker's own signals: the parent's (it stops its run between chunks of steps).
        worker_count = 0;
        std::signal(SIGINT, previous_int);
        std::signal(SIGTERM, previous_term);
        close(channel[0]);
        for (const int earlier : report_pipes)
          close(earlier);
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
      report_pipes.push_back(channel[0]);
      pids.push_back(pid);
      worker_pids[member] = pid;
      worker_count = member + 1;
    }
    std::vector<WorkerExit> exits;
    for (std::size_t k = 0; k < pids.size(); ++k)
    {
      exits.push_back(wait_for(pids[k]));
      char buffer[max_worker_report];
      ssize_t n;
      while ((n = read(report_pipes[k], buffer, sizeof buffer)) > 0 || (n < 0 && errno == EINTR))
        if (n > 0)
          exits.back().report.append(buffer, static_cast<std::size_t>(n));
      close(report_pipes[k]);
    }
    std::signal(SIGINT, previous_int);
    std::signal(SIGTERM, previous_term);
    worker_count = 0;
    if (!fork_error.empty())
      throw std::runtime_error("could not start worker process " + std::to_string(pids.size()) + " of " +
                               std::to_string(members) + ": " + fork_error);
    return exits;
  }

  std::string describe_worker_exit(int member, const WorkerExit &exit)
  {
    if (exit.signal != 0)
      return "worker " + std::to_string(member) + " ended by signal " + std::to_string(exit.signal) + " (" +
             strsignal(exit.signal) + ")";
    return "worker " + std::to_string(member) + " exited with code " + std::to_string(exit.exit_code);
  }
} // namespace anticrack
