// SHA-256 (FIPS 180-4) of a byte string, as lowercase hex. Used to identify scene files and their
// canonical parameter sets in summaries and checkpoints; not for anything security-related.
#pragma once

#include <string>

namespace anticrack::app
{
  std::string sha256_hex(const std::string &bytes);
} // namespace anticrack::app
