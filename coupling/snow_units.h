// From the DEM's model units to snow. A DEM weak layer is run in units chosen for speed (a stiff,
// strong bond, e.g. 1 GPa and 1 MPa, and heavy grains, e.g. 10 000 kg/m³, for a large time step);
// the FE layer needs the snow's. The conversion is dimensional analysis, exact for the campaign's
// tests as far as they are quasi-static:
//   - stresses: the tests have no gravity and rate-independent (local, non-viscous) damping, and
//     every contact and bond law is linear in its modulus and strength, so scaling every modulus and
//     every strength of the DEM by S scales every force by S and leaves every displacement as it was
//     at equilibrium. The continuum's moduli and strengths (E, p0 and their intervals) scale by S
//     too, and every ratio (ν, β, M, ξ, the residual ratio, strains) is unchanged. S is fixed by the
//     snow's bond tensile strength: S = σ̄_c,snow / σ̄_c,DEM (the snow's bond modulus is then
//     S times the DEM's, reported).
//   - density: the grains' density sets only the time scale of a quasi-static test, so the layer's
//     density is φ ρ_snow with the campaign's solid fraction φ and the snow's grain density.
//   - lengths: the continuum has no length but the one its softening is measured over, the
//     reference thickness h_ref of the DEM layer; the FE's crack band scales ξ from it to its own
//     element rows (fem/model/crack_band.h), so a weak layer of any thickness uses the same file.
// What is not exact: the tests are quasi-static to within the campaign's quasi-static check (the
// failure points of the 4x slower tests, e.g. 1.3 % on the SHS campaign), and the DEM's strengths
// scale linearly with the bond strength only in this joint scaling (Bobillier et al. 2020, Eqs. 5–8,
// give the lines when one micro property changes alone; their intercepts are why a single property
// cannot be scaled by itself).
#pragma once

#include "fem/material/material_file.h"
#include "params/calibration.h"

namespace anticrack::coupling
{
  /// What the DEM's units are converted to (subsection Snow units of a pipeline scene).
  struct SnowUnits
  {
    double bond_tensile_strength = 0; ///< σ̄_c of the snow's bonds [Pa]: S = this / the DEM's
    double particle_density = 0;      ///< ρ of the snow's grains [kg/m³] (ice: 917)
  };

  /// S = σ̄_c,snow / σ̄_c,DEM of microstructure calibration `c`; throws InputError (naming the
  /// campaign's bond strength) if the DEM has no bonds or either strength is not positive.
  double stress_scale(const params::MicrostructureCalibration &c, const SnowUnits &snow);

  /// The material file `dem_units` (coupling::material_handoff of `c`) in snow units: E, p0 and
  /// their intervals times S, density φ ρ_snow, the rest unchanged; the comment says what was
  /// converted, by how much and why.
  fem::MaterialFile in_snow_units(const fem::MaterialFile &dem_units, const params::MicrostructureCalibration &c,
                                  const SnowUnits &snow);
} // namespace anticrack::coupling
