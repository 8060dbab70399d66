// The continuum material as the FE solver reads it: `subsection Material` of a material file written
// by a calibration (params/calibration_output.h), or the same entries inline in a layer of a
// snowpack scene (fem/scene/snowpack_scene.h). One declaration serves both, so a layer can be given
// either way with the same names, units and ranges. `anticrack calibrate` reads every material file
// back with read_material_file() before it keeps it (a file the solver could not read is never left
// behind).
#pragma once

#include <string>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::fem
{
  /// A continuum material (SI units): elasticity, the cohesive Cam-Clay surface and its softening.
  struct ContinuumMaterial
  {
    std::string name;
    double density = 0;             ///< [kg/m³]
    double youngs_modulus = 0;      ///< E [Pa]
    double poisson_ratio = 0;       ///< ν
    double p0 = 0;                  ///< compressive tip of the cohesive Cam-Clay surface [Pa]
    double beta = 0;                ///< tensile tip at −β p0
    double M = 0;                   ///< critical-state slope
    std::string hardening_law;      ///< collapse | signed (docs/physics.md §2)
    double hardening_factor = 0;    ///< ξ of p0 = K sinh(ξ max(−α, 0))
    double residual_strength_ratio = 0; ///< floor of p0 over its initial value
    /// [m] thickness of the calibrated specimen: the length over which the measured softening
    /// strain acts (Bobillier et al.'s (2020) thickness scaling; the FE's crack band scales ξ with it).
    double reference_thickness = 0;
  };

  /// Declares the entries of a ContinuumMaterial in the current subsection of `prm`.
  void declare_material_entries(dealii::ParameterHandler &prm);

  /// Reads what declare_material_entries() declared, from the current subsection.
  ContinuumMaterial parse_material_entries(dealii::ParameterHandler &prm);

  /// Parses `file` (a material file or a scene containing subsection Material); throws
  /// anticrack::InputError naming the file and the entry for unknown entries, bad values or values
  /// out of range.
  ContinuumMaterial read_material_file(const std::string &file);

  /// The same for the text of a material file; `name` is used in messages.
  ContinuumMaterial read_material_text(const std::string &text, const std::string &name);
} // namespace anticrack::fem
