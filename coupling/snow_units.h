// From the DEM's model units to snow. A DEM weak layer is run in units chosen for speed (heavy
// grains, e.g. 10 000 kg/m³, for a large time step); the FE layer needs the snow's. The snow gives
// four numbers (subsection Snow units of a pipeline scene): its bonds' tensile strength σ̄_c and
// modulus Ē, its grains' diameter d and their density ρ. The conversion is dimensional analysis,
// exact for the campaign's tests as far as they are quasi-static:
//   - the ratio Ē/σ̄_c is not a unit: the DEM's response depends on it (a bond of larger ratio breaks
//     at a smaller strain, before its neighbours touch; docs/pipeline.md measures how much). So the
//     DEM is run at the snow's ratio: the pipeline sets the weak layer's bond modulus to σ̄_c,DEM
//     (Ē/σ̄_c)_snow and scales its contact modulus and its grains' density by the same factor k
//     (snow_ratio_changes), which leaves every wave speed and the time step as they were, so the
//     scene's loading rates stay as quasi-static as its check measured them; its stop strain
//     grows by 1/k, the failure strains' factor;
//   - stresses: the tests have no gravity and rate-independent (local, non-viscous) damping, and
//     every contact and bond law is linear in its modulus and strength, so scaling every modulus and
//     every strength of the DEM by S scales every force by S and leaves every displacement as it was
//     at equilibrium. The continuum's moduli and strengths (E, p0 and their intervals) scale by S
//     too, and every ratio (ν, β, M, ξ, the residual ratio, strains) is unchanged. S = σ̄_c,snow /
//     σ̄_c,DEM (the DEM ran at the snow's ratio, so its moduli scale to the snow's bond modulus too);
//   - lengths: scaling every length by L (positions, radii, bond radii) leaves every stress and
//     strain as it was (forces scale by L², areas too): the grains' size is a unit. L = d_snow /
//     d_DEM. The continuum's only length, the softening's reference thickness h_ref (the DEM layer's
//     thickness), scales by L; the FE's crack band scales ξ from it to its own element rows
//     (fem/scene/crack_band.h), so the energy dissipated per unit area scales by L too;
//   - density: the grains' density sets only the time scale of a quasi-static test, so the layer's
//     density is φ ρ_snow with the campaign's solid fraction φ and the snow's grain density.
// What is not exact: the tests are quasi-static to within the campaign's quasi-static check (the
// failure points of the 4x slower tests, e.g. 1.3 % on the SHS campaign).
#pragma once

#include "fem/material/material_file.h"
#include "params/calibration.h"

#include <string>
#include <utility>
#include <vector>

namespace anticrack::dem
{
  struct SceneParameters;
}

namespace anticrack::coupling
{
  /// What the DEM's units are converted to (subsection Snow units of a pipeline scene).
  struct SnowUnits
  {
    double bond_tensile_strength = 0; ///< σ̄_c of the snow's bonds [Pa]: S = this / the DEM's
    double bond_modulus = 0;          ///< Ē of the snow's bonds [Pa]: the DEM runs at Ē/σ̄_c
    double grain_diameter = 0;        ///< d of the snow's grains [m]: L = this / the DEM's
    double particle_density = 0;      ///< ρ of the snow's grains [kg/m³] (ice: 917)

    /// Ē/σ̄_c, the ratio the DEM is run at.
    [[nodiscard]] double stiffness_to_strength() const { return bond_modulus / bond_tensile_strength; }
  };

  /// The entries of the weak layer's DEM scene `dem` (its file's values with the pipeline's other
  /// changes) that run it at the snow's Ē/σ̄_c: with k = (Ē/σ̄_c)_snow / (Ē/σ̄_c)_DEM, the bond
  /// modulus, the contact modulus and the grains' density times k (wave speeds and the time step
  /// unchanged), the stop strain over k. Empty when k = 1 to 1e-12. Throws InputError (naming
  /// `where`) for a scene without bonds, with a contact law other than the linear one, or with
  /// Campaign/Microstructures (their own bonds would need their own factor).
  std::vector<std::pair<std::string, std::string>> snow_ratio_changes(const dem::SceneParameters &dem,
                                                                      const SnowUnits &snow, const std::string &where);

  /// S = σ̄_c,snow / σ̄_c,DEM of microstructure calibration `c`; throws InputError (naming the
  /// campaign's bond strength) if the DEM has no bonds or either strength is not positive.
  double stress_scale(const params::MicrostructureCalibration &c, const SnowUnits &snow);

  /// L = d_snow / d_DEM of microstructure calibration `c`; throws InputError if the campaign does
  /// not record its grains' diameter (format 3 and older: run it again) or either is not positive.
  double length_scale(const params::MicrostructureCalibration &c, const SnowUnits &snow);

  /// The material file `dem_units` (coupling::material_handoff of `c`) in snow units: E, p0 and
  /// their intervals times S, the reference thickness times L, density φ ρ_snow, the rest
  /// unchanged; the comment says what was converted, by how much and why. Throws InputError if the
  /// campaign was not run at the snow's Ē/σ̄_c (to 1e-9): its response would not be the snow's.
  fem::MaterialFile in_snow_units(const fem::MaterialFile &dem_units, const params::MicrostructureCalibration &c,
                                  const SnowUnits &snow);

  /// `snow_units` (a material file in snow units for grains of diameter `from` [m]) for grains of
  /// diameter `to`: its only length, the reference thickness, times to / from (the grains' size is a
  /// unit, above), the rest unchanged; the comment says so. A pit's own grain size under a weak
  /// layer calibrated once per class (coupling/profile_specimen.h).
  fem::MaterialFile with_grain_diameter(const fem::MaterialFile &snow_units, double from, double to,
                                        const std::string &why);
} // namespace anticrack::coupling
