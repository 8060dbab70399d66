#include "util/output_lock.h"

#include "util/input_error.h"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace anticrack
{
  OutputDirectoryLock::OutputDirectoryLock(const std::string &directory) : directory_(directory)
  {
    namespace fs = std::filesystem;
    // The first missing ancestor: what this lock creates, and removes again if it stays empty.
    fs::path missing = fs::absolute(directory);
    for (fs::path p = missing; !p.empty() && p != p.root_path() && !fs::exists(p); p = p.parent_path())
      missing = p;
    std::error_code error;
    fs::create_directories(fs::absolute(directory).parent_path(), error);
    if (::mkdir(directory.c_str(), 0777) == 0)
      created_ = missing;
    else if (errno != EEXIST)
      throw InputError("output directory " + directory + ": cannot be created (" + std::strerror(errno) + ")");
    descriptor_ = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (descriptor_ < 0)
      throw InputError("output directory " + directory + ": cannot be opened as a directory (" +
                       std::strerror(errno) + ")");
    if (::flock(descriptor_, LOCK_EX | LOCK_NB) != 0)
    {
      const int why = errno;
      ::close(descriptor_);
      descriptor_ = -1;
      throw InputError("output directory " + directory + ": " +
                       (why == EWOULDBLOCK ? std::string("another anticrack process is writing into it; wait for it "
                                                         "to end, or give this run another -o directory")
                                           : "cannot be locked (" + std::string(std::strerror(why)) + ")"));
    }
  }

  OutputDirectoryLock::~OutputDirectoryLock()
  {
    if (descriptor_ >= 0)
      ::close(descriptor_); // releases the lock
    if (created_.empty())
      return;
    namespace fs = std::filesystem;
    std::error_code error;
    for (fs::path p = fs::absolute(directory_); fs::is_empty(p, error) && !error; p = p.parent_path())
    {
      fs::remove(p, error);
      if (error || p == created_)
        break;
    }
  }
} // namespace anticrack
