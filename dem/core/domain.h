// The simulation box: an axis-aligned cuboid, periodic along any subset of x, y, z.
// Along a periodic axis the branch vector between two particles carries an image shift that is a
// multiple of the box length; positions are wrapped back into the box only when the neighbour
// list is rebuilt, so that the shifts stored with contacts and bonds stay valid in between.
#pragma once

#include "dem/common/types.h"

#include <array>
#include <cmath>

namespace anticrack::dem
{
  struct Domain
  {
    Vec3 lower = Vec3::Zero();
    Vec3 upper = Vec3::Ones();
    std::array<bool, 3> periodic = {false, false, false};

    [[nodiscard]] Vec3 length() const { return upper - lower; }

    /// Shift to add to x_j so that x_j + shift - x_i is the minimum image of the branch vector.
    [[nodiscard]] Vec3 minimum_image_shift(const Vec3 &xi, const Vec3 &xj) const
    {
      Vec3 shift = Vec3::Zero();
      const Vec3 L = length();
      for (int a = 0; a < 3; ++a)
        if (periodic[a])
          shift[a] = -L[a] * std::nearbyint((xj[a] - xi[a]) / L[a]);
      return shift;
    }

    /// Map x into [lower, upper) along periodic axes.
    [[nodiscard]] Vec3 wrap(Vec3 x) const
    {
      const Vec3 L = length();
      for (int a = 0; a < 3; ++a)
        if (periodic[a])
        {
          x[a] -= L[a] * std::floor((x[a] - lower[a]) / L[a]);
          if (x[a] >= upper[a]) // round-off at the upper face
            x[a] = lower[a];
        }
      return x;
    }
  };
} // namespace anticrack::dem
