// The material hand-off: a calibration (params/calibration.h) becomes the FE solver's material file
// (fem/material/material_file.h), one per microstructure: the cohesive Cam-Clay surface of the
// calibration's FE plane, elasticity, density and collapse softening, with their intervals, the
// provenance (campaign and scene hashes) and a comment that says how every value was measured.
#pragma once

#include "fem/material/material_file.h"
#include "params/calibration.h"

#include <string>

namespace anticrack::coupling
{
  /// The material file of microstructure `m` of `calibration`; `tool_version` goes into the comment.
  fem::MaterialFile material_handoff(const params::Calibration &calibration, std::size_t m,
                                     const std::string &tool_version);
} // namespace anticrack::coupling
