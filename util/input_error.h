// Errors a user can fix by editing an input file or the command line (a scene, a material file, a
// campaign), and the exit codes of the `anticrack` executable. Input errors are raised before any
// output is written; app/main.cpp holds the one table that maps every error type of the modules to
// its exit code and the title of its message.
#pragma once

#include <stdexcept>
#include <string>

namespace anticrack
{
  class InputError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// A file that an earlier run left in the output directory, and that this run (a --resume) would
  /// read as a result, but cannot use: torn, empty, not JSON or HDF5, or of another kind or version.
  /// Exit 2 like bad input; the message names the file, says what is wrong with it and what to do
  /// (--overwrite, or delete the part of the run that the file belongs to, which then runs again).
  /// A run never writes such a file itself (util/atomic_file.h): it comes from a full disk, another
  /// program, or a copy cut short.
  class UnusableOutputFile : public std::runtime_error
  {
  public:
    /// `problem`: what is wrong ("is not valid JSON ..."); `remedy`: what to do, or empty for the
    /// generic advice (--overwrite, or delete the file so that its part runs again).
    UnusableOutputFile(const std::string &file, const std::string &problem, const std::string &remedy = "")
      : std::runtime_error(
          file + " " + problem + ".\nIt was left by an earlier run in the output directory and cannot be used. " +
          (remedy.empty() ? "Run again with --overwrite to start afresh, or delete " + file +
                              ": the part of the run it belongs to then runs again." :
                            remedy))
      , file_(file), problem_(problem)
    {}
    const std::string &file() const { return file_; }
    const std::string &problem() const { return problem_; }

  private:
    std::string file_, problem_;
  };

  /// Exit codes of the `anticrack` executable.
  enum ExitCode : int
  {
    exit_success = 0,
    exit_numerical_failure = 1, ///< a run that had started failed, or a snowpack collapsed under gravity (summary.json says where and when)
    exit_bad_input = 2,         ///< nothing was written
    exit_interrupted = 130      ///< SIGINT or SIGTERM; a checkpoint was written where the run kind has them
  };
} // namespace anticrack
