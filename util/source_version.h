// The version of the source tree the executable was built from: `git describe --always --dirty`
// at build time ("unknown" outside a git tree), for summary.json and `anticrack --version`.
#pragma once

namespace anticrack
{
  const char *source_version();
} // namespace anticrack
