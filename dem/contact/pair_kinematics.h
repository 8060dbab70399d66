// Relative kinematics of a pair of spheres, shared by every contact law and the parallel bond.
// The pair acts at a single point c on the line of centres, halfway across the gap (or overlap):
//   c = x_i + (R_i + (d - R_i - R_j)/2) n.
// Using one point for both particles makes the relative velocity of a rigid-body motion vanish
// exactly, whatever the gap, which is what keeps the incremental laws objective.
#pragma once

#include "dem/common/types.h"

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
    k.normal = branch * (1.0 / k.distance);
    const double to_point = ri + 0.5 * (k.distance - ri - rj);
    k.arm_i = to_point * k.normal;
    k.arm_j = k.arm_i - branch;
    k.relative_velocity = (vj + wj.cross(k.arm_j)) - (vi + wi.cross(k.arm_i));
    k.relative_spin = wj - wi;
    k.mean_spin = 0.5 * (wi + wj);
    return k;
  }

  /// The rotation of the contact plane over one step: first the rotation taking the old normal to
  /// the new one about their common perpendicular t = n_old x n_new (Rodrigues' formula in the
  /// division-only form v' = c v + t x v + t (t.v)/(1 + c), c = n_old.n_new), then the spin of the
  /// pair about the new normal by psi = dt (omega_mean . n), applied as a Cayley rotation
  /// ((1 - h^2) v + 2 h n x v)/(1 + h^2), h = psi/2, whose angle 2 atan(h) differs from psi by
  /// psi^3/12. Both are exact rotations, so lengths are preserved and a pre-loaded bond keeps its
  /// load under rigid rotation; the final projection only removes round-off.
  struct ContactPlaneRotation
  {
    Vec3 tilt;            ///< n_old x n_new
    double tilt_cos;      ///< n_old . n_new
    double tilt_factor;   ///< 1 / (1 + n_old . n_new)
    Vec3 normal;          ///< n_new
    double spin_cos;      ///< (1 - h^2) / (1 + h^2)
    double spin_sin;      ///< 2 h / (1 + h^2)

    ContactPlaneRotation(const Vec3 &old_normal, const Vec3 &new_normal, const Vec3 &mean_spin, double dt)
      : tilt(old_normal.cross(new_normal))
      , tilt_cos(old_normal.dot(new_normal))
      , tilt_factor(1.0 / (1.0 + tilt_cos))
      , normal(new_normal)
    {
      const double h = 0.5 * dt * mean_spin.dot(new_normal);
      const double scale = 1.0 / (1.0 + h * h);
      spin_cos = (1 - h * h) * scale;
      spin_sin = 2 * h * scale;
    }

    void apply(Vec3 &v) const
    {
      v = tilt_cos * v + tilt.cross(v) + (tilt.dot(v) * tilt_factor) * tilt;
      v = spin_cos * v + spin_sin * normal.cross(v);
      v -= v.dot(normal) * normal;
    }
  };

  /// Convenience form for a single vector.
  inline void rotate_with_contact_plane(Vec3 &v, const Vec3 &old_normal, const Vec3 &new_normal,
                                        const Vec3 &mean_spin, double dt)
  {
    ContactPlaneRotation(old_normal, new_normal, mean_spin, dt).apply(v);
  }
} // namespace anticrack::dem
