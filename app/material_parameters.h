// The material file a calibration writes (params/calibration_output.h) as the FE solver reads it:
// subsection Material of a deal.II parameter file. Declared here, next to the scene parameters,
// so that `anticrack calibrate` reads every material file back before it keeps it (a file the
// solver could not read is never left behind).
#pragma once

#include <string>

namespace anticrack::app
{
  /// The continuum material of a material file (SI units).
  struct ContinuumMaterial
  {
    std::string name;
    double density = 0;             ///< [kg/m³]
    double youngs_modulus = 0;      ///< E [Pa]
    double poisson_ratio = 0;       ///< ν
    double p0 = 0;                  ///< compressive tip of the cohesive Cam-Clay surface [Pa]
    double beta = 0;                ///< tensile tip at −β p0
    double M = 0;                   ///< critical-state slope
    std::string hardening_law;      ///< collapse | signed (PHYSICS.md §2)
    double hardening_factor = 0;    ///< ξ of p0 = K sinh(ξ max(−α, 0))
    double residual_strength_ratio = 0;
    double reference_thickness = 0; ///< [m] of the calibrated specimen (seed 000 thickness scaling)
  };

  /// Parses `file` (a material file or a scene containing subsection Material); throws InputError
  /// naming the file and the entry for unknown entries, bad values or values out of range.
  ContinuumMaterial read_material_file(const std::string &file);

  /// The same for the text of a material file; `name` is used in messages.
  ContinuumMaterial read_material_text(const std::string &text, const std::string &name);
} // namespace anticrack::app
