#include "util/source_version.h"

// Written at every build by cmake/write_source_version.cmake (util/CMakeLists.txt); only this file
// recompiles when the version or the calibrating code's hash changes.
#include "anticrack_source_version.h"

namespace anticrack
{
  const char *source_version() { return ANTICRACK_GIT_VERSION; }
  const char *calibration_code_sha256() { return ANTICRACK_CALIBRATION_CODE_SHA256; }
} // namespace anticrack
