#include "util/atomic_file.h"

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <iterator>
#include <locale>
#include <stdexcept>
#include <unistd.h>

namespace anticrack
{
  namespace
  {
    /// Makes `file` durable before it is renamed (the rename itself is atomic, the data is not).
    void flush_to_disk(const std::string &file)
    {
      const int descriptor = ::open(file.c_str(), O_RDONLY);
      if (descriptor < 0 || ::fsync(descriptor) != 0)
      {
        const std::string reason = std::strerror(errno);
        if (descriptor >= 0)
          ::close(descriptor);
        throw std::runtime_error("cannot flush " + file + " to disk (" + reason + ")");
      }
      ::close(descriptor);
    }

    /// The fault-injection hook of the resume tests (tests/faults, docs/resume.md): with
    /// ANTICRACK_KILL_WHILE_WRITING set to a path's end (`campaign.h5`, `weak_layer/summary.json`),
    /// the process group is killed by SIGKILL, as `kill -9 -- -PGID` would, the first time such a
    /// file has been written under its temporary name and not yet renamed: the moment a power cut
    /// would leave a torn file if the writes were not atomic. Unset, it costs one getenv per file.
    void kill_if_injected_fault(const std::string &file)
    {
      const char *target = std::getenv("ANTICRACK_KILL_WHILE_WRITING");
      if (target == nullptr || *target == '\0')
        return;
      const std::string end(target);
      if (file.size() >= end.size() && file.compare(file.size() - end.size(), end.size(), end) == 0)
        ::kill(0, SIGKILL);
    }
  } // namespace

  void write_atomically(const std::string &file, const std::function<void(const std::string &temporary)> &write,
                        const bool durable)
  {
    const std::string temporary = file + ".tmp";
    try
    {
      write(temporary);
      if (durable)
        flush_to_disk(temporary);
      kill_if_injected_fault(file);
      if (std::rename(temporary.c_str(), file.c_str()) != 0)
      {
        const std::string reason = std::strerror(errno);
        throw std::runtime_error("cannot rename " + temporary + " to " + file + " (" + reason + ")");
      }
    }
    catch (...)
    {
      std::remove(temporary.c_str());
      throw;
    }
  }

  void write_text_atomically(const std::string &file, const std::function<void(std::ostream &out)> &write,
                             const bool durable)
  {
    write_atomically(
      file,
      [&](const std::string &temporary) {
        std::ofstream out(temporary);
        if (!out)
          throw std::runtime_error("cannot open " + temporary + " for writing");
        out.imbue(std::locale::classic());
        write(out);
        out.close();
        if (!out)
          throw std::runtime_error("cannot write " + temporary);
      },
      durable);
  }
  std::string read_text_file(const std::string &file)
  {
    std::ifstream in(file, std::ios::binary);
    if (!in)
      throw std::runtime_error("cannot read " + file);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad())
      throw std::runtime_error("error reading " + file);
    return text;
  }
} // namespace anticrack
