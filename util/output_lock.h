// One process writes into an output directory at a time. Two runs started into the same directory
// (two terminals, two jobs of a batch script with the same -o) would otherwise interleave their
// files: each one's summary.json, checkpoints and HDF5 files overwritten by the other's, and
// neither says so. The lock is flock(2) on the directory itself: the kernel releases it when the
// process ends, however it ends, so there is no stale lock file to clean up, and forked workers
// (util/worker_processes.h) share their parent's.
//
// The directory is created if it does not exist (mkdir(2) is atomic: of two runs starting together,
// one creates it and both then contend for the lock); a directory this lock created and that is
// still empty when the lock goes (a scene refused as bad input) is removed again, so that bad input
// leaves nothing behind.
#pragma once

#include <filesystem>
#include <string>

namespace anticrack
{
  class OutputDirectoryLock
  {
  public:
    /// Takes the lock, or throws InputError naming the directory when another process holds it
    /// (or when the directory cannot be created or opened).
    explicit OutputDirectoryLock(const std::string &directory);
    ~OutputDirectoryLock();
    OutputDirectoryLock(const OutputDirectoryLock &) = delete;
    OutputDirectoryLock &operator=(const OutputDirectoryLock &) = delete;

  private:
    std::string directory_;
    int descriptor_ = -1;
    /// The first of the directory's ancestors (or itself) this lock created; empty if it created
    /// none. Removed again, down from the directory, while they are empty.
    std::filesystem::path created_;
  };
} // namespace anticrack
