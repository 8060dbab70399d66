#include "dem/sample/bedding.h"

#include <cmath>

namespace anticrack::dem
{
  Index apply_bedding(DemSystem &system, const BeddingSpec &spec)
  {
    if (!(spec.normal.norm() > 0))
      throw SetupError("bedding: the plane normal must not be zero");
    if (!(spec.spacing > 0))
      throw SetupError("bedding: spacing " + std::to_string(spec.spacing) + " m must be positive");
    if (!(spec.thickness >= 0))
      throw SetupError("bedding: thickness " + std::to_string(spec.thickness) + " m must be >= 0");
    const Vec3 n = spec.normal.normalized();
    const double half = 0.5 * spec.thickness;
    BondList &bonds = system.bonds;
    const auto &x = system.particles.position;
    Index bedded = 0;
    for (Index b = 0; b < bonds.size(); ++b)
    {
      // Positions along the normal of the two ends, relative to plane 0, in units of the spacing.
      const Vec3 xj = x[bonds.j[b]] + system.domain.minimum_image_shift(x[bonds.i[b]], x[bonds.j[b]]);
      const double a = (n.dot(x[bonds.i[b]]) - spec.offset) / spec.spacing;
      const double c = (n.dot(xj) - spec.offset) / spec.spacing;
      const double low = std::min(a, c) - half / spec.spacing, high = std::max(a, c) + half / spec.spacing;
      // The segment, widened by half a band on each side, contains a plane k iff ceil(low) <= high.
      if (std::ceil(low) > high)
        continue;
      bonds.tensile_strength[b] = spec.tensile_strength;
      bonds.cohesion[b] = spec.cohesion;
      bonds.tan_friction[b] = std::tan(spec.friction_angle);
      ++bedded;
    }
    return bedded;
  }
} // namespace anticrack::dem
