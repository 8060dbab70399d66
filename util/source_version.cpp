#include "util/source_version.h"

// Written at every build by cmake/write_source_version.cmake (util/CMakeLists.txt); only this file
// recompiles when the version changes.
#include "anticrack_source_version.h"

namespace anticrack
{
  const char *source_version() { return ANTICRACK_GIT_VERSION; }
} // namespace anticrack
