// Regular packings used by the benchmark, tests and simple scenes.
#pragma once

#include "dem/core/system.h"

#include <array>
#include <cstdint>

namespace anticrack::dem
{
  struct LatticeSpec
  {
    std::array<Index, 3> cells = {10, 10, 10}; ///< spheres along x, y, z
    double radius = 1e-3;                      ///< [m]
    double spacing = 2e-3;                     ///< centre distance [m]
    Vec3 origin = Vec3::Zero();                ///< lower corner of the lattice's bounding cells
    int material = 0;
    double velocity_amplitude = 0;             ///< uniform random velocity in [-a, a] per component [m/s]
    std::uint64_t seed = 1;
  };

  /// Appends a simple-cubic lattice: centres at origin + (k + 1/2) spacing. Returns the first id.
  Index add_simple_cubic_lattice(DemSystem &system, const LatticeSpec &spec);
} // namespace anticrack::dem
