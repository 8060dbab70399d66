// Reading a text file whole, and writing a file atomically: the content goes to `file + ".tmp"`, which is then renamed over `file`
// (a rename within one file system is atomic), so readers (ParaView, a resumed run, a campaign
// merging results) and crashes never leave a partial `file`. On failure the temporary is removed
// and the exception passes on. For text, JSON and HDF5 files alike.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace anticrack
{
  /// `write(temporary)` creates and fills the file at path `temporary` (in any format); it is then
  /// renamed to `file`. `durable`: the temporary is flushed to disk (fsync) before the rename, so
  /// that after a crash `file` is either the old or the complete new content (checkpoints).
  void write_atomically(const std::string &file, const std::function<void(const std::string &temporary)> &write,
                        bool durable = false);

  /// Text files: `write(out)` fills a stream on the temporary (classic "C" locale: no digit grouping
  /// whatever the global locale); write errors are reported naming the temporary.
  void write_text_atomically(const std::string &file, const std::function<void(std::ostream &out)> &write,
                             bool durable = false);

  /// The whole content of text file `file`; throws std::runtime_error naming it if it cannot be read.
  std::string read_text_file(const std::string &file);
} // namespace anticrack
