// The part of a contact step common to every law (docs/physics.md §1.1): the incremental tangential
// spring carried with the contact plane and capped by Coulomb's law |F_s| <= mu F_n, the normal and
// shear dashpots, and the energy they dissipate. The law (a kernel of dem/contact/contact_law.h)
// supplies the elastic normal force and the tangent stiffnesses. The normal force is repulsive only.
#pragma once

#include "dem/contact/contact_parameters.h"
#include "dem/contact/pair_kinematics.h"
#include "dem/common/types.h"

#include <algorithm>
#include <cmath>

namespace anticrack::dem
{
  struct ContactDissipation
  {
    double friction = 0; ///< energy dissipated by sliding this step [J]
    double viscous = 0;  ///< energy dissipated by the dashpots this step [J]
  };

  /// Books the dashpots' dissipation and stores the new dashpot force. The leapfrog applies the
  /// force of step n over the half steps on both sides of it, so the work over the half step just
  /// completed pairs the relative velocity v(n-1/2) with the mean of the previous and the current
  /// dashpot force (trapezoidal, as the kinetic energy 1/2 m v(n-1/2).v(n+1/2) sees it); booking
  /// F(n).v(n-1/2) instead leaves an O(dt) error. A contact that opens books its last half step
  /// with a zero current force.
  inline void book_dashpot_work(Vec3 &stored_force, const Vec3 &current_force, const Vec3 &relative_velocity,
                                double dt, ContactDissipation &dissipation)
  {
    dissipation.viscous -= 0.5 * (stored_force + current_force).dot(relative_velocity) * dt;
    stored_force = current_force;
  }

  /// One step of a contact with overlap delta > 0 under law `Law`. `shear_force` is the stored
  /// tangential force on j, already carried into the current contact plane; `dashpot_force` the
  /// dashpot force on j of the previous step (updated). Returns the force on j.
  template <class Law>
  inline Vec3 frictional_contact_force(const ContactParameters &p, double ri, double rj, double m_eff,
                                       double delta, const PairKinematics &k, double dt, Vec3 &shear_force,
                                       Vec3 &dashpot_force, ContactDissipation &dissipation)
  {
    double kn, ks;
    const double fn_elastic = Law::normal_force(p, ri, rj, delta, kn, ks);
    const double vn = k.relative_velocity.dot(k.normal); // > 0 when separating
    const Vec3 vs = k.relative_velocity - vn * k.normal;

    // Tangential spring, increment -k_s du_s, then Coulomb's cap on the elastic normal force.
    // Sliding dissipates (|F_trial| - cap)(|F_old| + cap) / (2 k_s): the slip length times the mean
    // of the force before and after the step, which is what the leapfrog's trapezoidal work sees;
    // it reduces to slip x cap at a constant cap and to (F_old^2 - cap^2)/(2 k_s) when the cap
    // shrinks without tangential motion.
    const Vec3 old_shear = shear_force;
    shear_force -= ks * dt * vs;
    const double cap = p.friction * fn_elastic;
    const double trial = shear_force.norm();
    bool sliding = false;
    if (trial > cap)
    {
      sliding = true;
      const Vec3 capped = trial > 0 ? Vec3(shear_force * (cap / trial)) : Vec3::Zero();
      dissipation.friction += (trial - cap) * (old_shear.norm() + cap) / (2 * ks);
      shear_force = capped;
    }

    double fn = fn_elastic;
    Vec3 fs = shear_force;
    Vec3 dashpot = Vec3::Zero();
    if (p.damping_ratio > 0)
    {
      const double cn = 2 * p.damping_ratio * std::sqrt(m_eff * kn);
      const double fn_total = std::max(fn_elastic - cn * vn, 0.0); // no attraction from the dashpot
      dashpot = (fn_total - fn_elastic) * k.normal;
      fn = fn_total;
      if (!sliding)
      {
        const double cs = 2 * p.damping_ratio * std::sqrt(m_eff * ks);
        dashpot -= cs * vs;
        fs -= cs * vs;
      }
      book_dashpot_work(dashpot_force, dashpot, k.relative_velocity, dt, dissipation);
    }
    // Repulsion pushes j along +n.
    return fn * k.normal + fs;
  }
} // namespace anticrack::dem
