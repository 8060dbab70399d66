// Bedding (Zhao & Feng 2022, layered slate): a family of parallel planes n.x = offset + k spacing, each the
// middle of a band of the given thickness; bonds whose centre-to-centre segment meets a band get the
// band's strengths (weaker cement along the bedding), the others keep theirs.
#pragma once

#include "dem/core/system.h"

namespace anticrack::dem
{
  struct BeddingSpec
  {
    Vec3 normal = Vec3::UnitZ();  ///< plane normal (normalised internally); inclination = its angle to z
    double spacing = 1e-2;        ///< distance between planes [m]
    double offset = 0;            ///< n.x of the plane k = 0 [m]
    double thickness = 0;         ///< band thickness [m]; 0: the planes themselves
    double tensile_strength = 1e5;///< sigma_bar_c of bedding bonds [Pa]
    double cohesion = 1e5;        ///< c_bar of bedding bonds [Pa]
    double friction_angle = 0;    ///< phi_bar of bedding bonds [rad]
  };

  /// Gives the bedding strengths to every bond that meets a band; returns how many. Throws
  /// SetupError for a zero normal, a non-positive spacing or a negative thickness.
  Index apply_bedding(DemSystem &system, const BeddingSpec &spec);
} // namespace anticrack::dem
