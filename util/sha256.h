// SHA-256 (FIPS 180-4) of a byte string or a file, as lowercase hex. Used to identify scene files,
// their canonical parameter sets and campaign files in summaries, checkpoints and material files;
// not for anything security-related.
#pragma once

#include <string>

namespace anticrack::util
{
  std::string sha256_hex(const std::string &bytes);

  /// SHA-256 of the bytes of `file`; throws std::runtime_error naming the file if it cannot be read.
  std::string sha256_of_file(const std::string &file);
} // namespace anticrack::util
