// Planar walls. A wall is the plane {x : (x - point) . normal = 0}; spheres on the side the normal
// points to are pushed away by the wall's contact law. The wall either stays put, moves at a
// prescribed velocity, or is servo-controlled to hold a target normal stress on a given area.
#pragma once

#include "dem/core/materials.h"

#include <string>
#include <vector>

namespace anticrack::dem
{
  enum class WallControl
  {
    fixed,
    velocity, ///< moves with `velocity` (any direction)
    servo     ///< normal velocity = gain (sigma_target area - F_n), capped at max_speed
  };

  struct Wall
  {
    std::string name;
    Vec3 normal = Vec3::UnitZ();  ///< unit, pointing into the particle side
    Vec3 point = Vec3::Zero();
    Vec3 velocity = Vec3::Zero(); ///< current wall velocity [m/s]
    WallControl control = WallControl::fixed;
    ContactParameters contact;    ///< sphere-wall contact law (L = R, A = pi R^2 for the linear law)
    double target_stress = 0;     ///< compressive target stress [Pa] (servo)
    double area = 1;              ///< area the stress acts on [m^2] (servo, reported stress)
    double servo_gain = 0;        ///< [m/(s N)]
    double max_speed = 0;         ///< cap on the servo speed [m/s]
    Vec3 force = Vec3::Zero();    ///< total force the particles exert on the wall [N]

    /// Compressive normal force on the wall from the last force evaluation [N] (the particles push
    /// it against its normal).
    [[nodiscard]] double normal_force() const { return -force.dot(normal); }
    /// Compressive normal stress on the wall from the last force evaluation [Pa].
    [[nodiscard]] double normal_stress() const { return normal_force() / area; }
  };
} // namespace anticrack::dem
