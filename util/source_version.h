// The version of the source tree the executable was built from: `git describe --always --dirty`
// at build time ("unknown" outside a git tree), for summary.json and `anticrack --version`.
#pragma once

namespace anticrack
{
  const char *source_version();

  /// The SHA-256 of the code that calibrates a material from the DEM (the files the calibration
  /// driver reaches through its includes) and of the compiler and flags that built it
  /// (cmake/write_source_version.cmake): equal for two builds of the same calibrating code, whatever
  /// else changed. The material cache's key.
  const char *calibration_code_sha256();
} // namespace anticrack
