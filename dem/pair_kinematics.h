// Relative kinematics of a pair of spheres, shared by every contact law and the parallel bond.
// The pair acts at a single point c on the line of centres, halfway across the gap (or overlap):
//   c = x_i + (R_i + (d - R_i - R_j)/2) n.
// Using one point for both particles makes the relative velocity of a rigid-body motion vanish
// exactly, whatever the gap, which is what keeps the incremental laws objective.
#pragma once

#include "dem/types.h"

#include <cmath>

namespace anticrack::dem
{
  struct PairKinematics
  {
    Vec3 normal;            ///< unit vector i -> j
    double distance;        ///< centre distance d
    Vec3 arm_i, arm_j;      ///< c - x_i, c - x_j
    Vec3 relative_velocity; ///< velocity of j's material point at c relative to i's
    Vec3 relative_spin;     ///< omega_j - omega_i
    Vec3 mean_spin;         ///< (omega_i + omega_j) / 2
  };

  inline PairKinematics pair_kinematics(const Vec3 &xi, const Vec3 &xj_shifted, double ri, double rj,
                                        const Vec3 &vi, const Vec3 &vj, const Vec3 &wi,
                                        const Vec3 &wj)
  {
    PairKinematics k;
    const Vec3 branch = xj_shifted - xi;
    k.distance = branch.norm();
    k.normal = branch / k.distance;
    const double to_point = ri + 0.5 * (k.distance - ri - rj);
    k.arm_i = to_point * k.normal;
    k.arm_j = k.arm_i - branch;
    k.relative_velocity = (vj + wj.cross(k.arm_j)) - (vi + wi.cross(k.arm_i));
    k.relative_spin = wj - wi;
    k.mean_spin = 0.5 * (wi + wj);
    return k;
  }

  /// Small rotation of the contact plane over one step: the rotation taking the old normal to the
  /// new one, plus the spin of the pair about the normal.
  inline Vec3 contact_plane_rotation(const Vec3 &old_normal, const Vec3 &new_normal, const Vec3 &mean_spin,
                                     double dt)
  {
    return old_normal.cross(new_normal) + new_normal * (dt * mean_spin.dot(new_normal));
  }

  /// Carries a vector that lives in the contact plane (shear force, bending moment) along with the
  /// plane's small rotation; the result is projected back onto the plane and keeps its length
  /// (a rotation does not stretch).
  inline void rotate_with_contact_plane(Vec3 &v, const Vec3 &rotation, const Vec3 &new_normal)
  {
    const double length2 = v.squaredNorm();
    if (length2 == 0)
      return;
    v += rotation.cross(v);
    v -= v.dot(new_normal) * new_normal;
    const double new_length2 = v.squaredNorm();
    if (new_length2 <= 0)
      return;
    // Restore the length: sqrt(ratio) with one Newton step from 1 when the per-step rotation is
    // small (error (ratio - 1)^2 / 8), the exact root otherwise.
    const double ratio = length2 / new_length2;
    v *= std::abs(ratio - 1) < 1e-4 ? 0.5 * (1 + ratio) : std::sqrt(ratio);
  }

  inline void rotate_with_contact_plane(Vec3 &v, const Vec3 &old_normal, const Vec3 &new_normal,
                                        const Vec3 &mean_spin, double dt)
  {
    rotate_with_contact_plane(v, contact_plane_rotation(old_normal, new_normal, mean_spin, dt), new_normal);
  }
} // namespace anticrack::dem
