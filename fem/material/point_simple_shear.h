// One weak-layer point driven along the DEM's simple shear at constant normal stress (Mede et al.
// 2018; dem/lab/simple_shear.h), with exactly the law the PSTs use (fem/material/layer_point.h):
// the continuum's answer to the same laboratory test, to set beside the DEM's curve.
//
// The specimen of the DEM is periodic in x and y between a fixed base and a platen, so the point
// keeps ε_xx = ε_yy = ε_xy = ε_yz = 0. Stage 1 (consolidation) raises the normal stress σ_n to its
// value in `consolidation_steps` equal steps with no shear; stage 2 shears by γ = 2 ε_xz in
// `shear_steps` equal steps to `final_shear_strain`, with ε_zz at each step the one that keeps
// −σ_zz = σ_n (the platen is free along z under a constant normal force). Under a constant force a
// softening layer can have no neighbouring equilibrium: ε_zz then jumps to the next one in
// compaction (the DEM's platen falls until the grains carry the load), which the solve finds by
// stepping towards compaction before bisecting.
#pragma once

#include "fem/material/layer_point.h"

#include <vector>

namespace anticrack::fem
{
  struct PointSimpleShearSettings
  {
    double normal_stress = 0;           ///< σ_n, compressive, > 0 [Pa]
    double final_shear_strain = 0;      ///< γ at the end of stage 2, > 0
    unsigned int consolidation_steps = 50;
    unsigned int shear_steps = 1000;
  };

  /// The point after one step of either stage.
  struct PointSimpleShearSample
  {
    double shear_strain = 0;  ///< γ = 2 ε_xz
    double normal_strain = 0; ///< −ε_zz, compaction positive
    double shear_stress = 0;  ///< σ_xz [Pa]
    double normal_stress = 0; ///< −σ_zz [Pa] (σ_n to the solve's tolerance)
    double p0 = 0;            ///< the skeleton's p0 [Pa]
    bool failed = false;      ///< the point has switched to the friction (failed_point())
  };

  /// Both stages' samples (consolidation first; the last consolidation sample has γ = 0). Throws
  /// std::invalid_argument for settings out of range (named), ReturnMappingError from the law, and
  /// std::runtime_error when no ε_zz within −1 < ε_zz < 1 carries σ_n.
  std::vector<PointSimpleShearSample> point_simple_shear(const LayerLaw &law, const PointSimpleShearSettings &settings);
} // namespace anticrack::fem
