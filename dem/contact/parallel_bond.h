// The parallel bond of Potyondy & Cundall (2004, Int. J. Rock Mech. Min. Sci. 41:1329), docs/physics.md
// §1.2: a cemented cylinder of radius R_bar between two spheres, acting in parallel with their
// contact. Incremental law with Delta u = v_rel dt and Delta theta = (omega_j - omega_i) dt:
//   F_n += -k_n A du_n          (compression positive)
//   F_s += -k_s A du_s          (carried with the contact plane first)
//   M_t += -k_s J dtheta_n      (twist, a scalar along n)
//   M_b += -k_n I dtheta_s      (bending, carried with the contact plane first)
// Rim stresses sigma = -F_n/A + beta |M_b| R/I (tension positive), tau = |F_s|/A + beta |M_t| R/J.
// The bond breaks for good when sigma >= sigma_c or tau >= c - sigma tan(phi).
#pragma once

#include "dem/common/interactions.h"
#include "dem/contact/pair_kinematics.h"

#include <cmath>

namespace anticrack::dem
{
  /// 1/2 F(n-1).F(n)/k for a spring whose load went from F(n-1) = load + increment to `load`.
  inline double energy_between_steps(double load, double increment, double stiffness)
  {
    return 0.5 * (load + increment) * load / stiffness;
  }
  inline double energy_between_steps(const Vec3 &load, const Vec3 &increment, double stiffness)
  {
    return 0.5 * (load + increment).dot(load) / stiffness;
  }

  /// Advances bond b by one step and writes its load on the pair into `load`. `rotation` carries the
  /// bond's plane from its previous normal to k.normal. Returns the elastic energy released if the
  /// bond broke during this step (0 otherwise).
  inline double update_parallel_bond(BondList &bonds, Index b, const PairKinematics &k,
                                     const ContactPlaneRotation &rotation, double dt, PairLoad &load)
  {
    if (bonds.state[b] != BondState::intact)
    {
      load = PairLoad{};
      return 0;
    }
    rotation.apply(bonds.shear_force[b]);
    rotation.apply(bonds.bending_moment[b]);
    bonds.normal[b] = k.normal;

    const double du_n = k.relative_velocity.dot(k.normal) * dt;
    const Vec3 du_s = k.relative_velocity * dt - du_n * k.normal;
    const Vec3 dtheta = k.relative_spin * dt;
    const double dtheta_n = dtheta.dot(k.normal);
    const Vec3 dtheta_s = dtheta - dtheta_n * k.normal;

    bonds.normal_force[b] -= bonds.normal_stiffness[b] * du_n;
    bonds.shear_force[b] -= bonds.shear_stiffness[b] * du_s;
    bonds.twist_moment[b] -= bonds.twist_stiffness[b] * dtheta_n;
    bonds.bending_moment[b] -= bonds.bending_stiffness[b] * dtheta_s;

    if (bonds.may_fail(b))
    {
      const auto [sigma, tau] = bonds.rim_stresses(b);
      const bool tensile_failure = sigma >= bonds.tensile_strength[b];
      const bool shear_failure = tau >= bonds.cohesion[b] - sigma * bonds.tan_friction[b];
      if (tensile_failure || shear_failure)
      {
        // The load of this step is not applied. For a linear spring that stops acting between two
        // steps, the leapfrog's energy invariant loses 1/2 F(n-1).F(n)/k, with F(n-1) = F(n) + k du
        // the load before this step's increment; booking 1/2 F(n)^2/k instead would leave an O(dt)
        // error in the energy balance at every break.
        const double released =
          energy_between_steps(bonds.normal_force[b], bonds.normal_stiffness[b] * du_n, bonds.normal_stiffness[b]) +
          energy_between_steps(bonds.shear_force[b], bonds.shear_stiffness[b] * du_s, bonds.shear_stiffness[b]) +
          energy_between_steps(bonds.twist_moment[b], bonds.twist_stiffness[b] * dtheta_n, bonds.twist_stiffness[b]) +
          energy_between_steps(bonds.bending_moment[b], bonds.bending_stiffness[b] * dtheta_s, bonds.bending_stiffness[b]);
        bonds.state[b] = tensile_failure ? BondState::broken_tension : BondState::broken_shear;
        bonds.normal_force[b] = 0;
        bonds.shear_force[b].setZero();
        bonds.twist_moment[b] = 0;
        bonds.bending_moment[b].setZero();
        load = PairLoad{};
        return released;
      }
    }

    // Loads on j; i gets the reaction. Moments act as pure couples.
    const Vec3 moment = bonds.twist_moment[b] * k.normal + bonds.bending_moment[b];
    load.force_on_j = bonds.normal_force[b] * k.normal + bonds.shear_force[b];
    load.torque_on_j = k.arm_j.cross(load.force_on_j) + moment;
    load.torque_on_i = -k.arm_i.cross(load.force_on_j) - moment;
    return 0;
  }
} // namespace anticrack::dem
