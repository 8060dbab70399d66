#include "util/atomic_file.h"

#include <cerrno>
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
