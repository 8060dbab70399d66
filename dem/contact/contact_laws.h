// Contact force kernels (docs/physics.md §1.1). Pure functions of parameters, geometry and the pair's
// tangential state: they update the state, return the load on the pair and report the energy they
// dissipate. The normal force is repulsive only; the tangential force is incremental, carried with
// the contact plane and capped by Coulomb's law |F_s| <= mu F_n.
#pragma once

#include "dem/core/interactions.h"
#include "dem/core/materials.h"
#include "dem/contact/pair_kinematics.h"

#include <algorithm>
#include <cmath>

namespace anticrack::dem
{
  struct ContactDissipation
  {
    double friction = 0; ///< energy dissipated by sliding this step [J]
    double viscous = 0;  ///< energy dissipated by the dashpots this step [J]
  };

  /// Normal and tangential stiffness of the linear law: k_n = E_c pi min(R)^2 / (R_i + R_j),
  /// k_s = k_n / kappa. For a wall, pass rj = 0 (L = R_i, A = pi R_i^2).
  inline void linear_stiffness(const ContactParameters &p, double ri, double rj, double &kn, double &ks)
  {
    const double rmin = rj > 0 ? std::min(ri, rj) : ri;
    kn = p.contact_modulus * M_PI * rmin * rmin / (ri + rj);
    ks = kn / p.stiffness_ratio;
  }

  /// Effective modulus and radius of Hertz-Mindlin for two spheres of the same material (rj = 0 for
  /// a rigid flat wall): 1/E* = 2 (1 - nu^2)/E, 1/G* = 2 (2 - nu)/G.
  inline void hertz_effective(const ContactParameters &p, double ri, double rj, double &e_star,
                              double &g_star, double &r_star)
  {
    const double nu = p.poisson_ratio;
    const double shear_modulus = p.young_modulus / (2 * (1 + nu));
    const bool wall = rj <= 0;
    e_star = p.young_modulus / ((wall ? 1.0 : 2.0) * (1 - nu * nu));
    g_star = shear_modulus / ((wall ? 1.0 : 2.0) * (2 - nu));
    r_star = wall ? ri : ri * rj / (ri + rj);
  }

  /// Current tangent stiffnesses of a contact with overlap delta (for the critical time step).
  inline void contact_tangent_stiffness(const ContactParameters &p, double ri, double rj, double delta,
                                        double &kn, double &ks)
  {
    if (p.law == ContactLaw::linear)
    {
      linear_stiffness(p, ri, rj, kn, ks);
      return;
    }
    double e_star, g_star, r_star;
    hertz_effective(p, ri, rj, e_star, g_star, r_star);
    const double a = std::sqrt(r_star * std::max(delta, 0.0));
    kn = 2 * e_star * a;
    ks = 8 * g_star * a;
  }

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

  /// One step of a contact with overlap delta > 0. `shear_force` is the stored tangential force on j,
  /// already carried into the current contact plane; `dashpot_force` the dashpot force on j of the
  /// previous step (updated). Returns the force on j.
  inline Vec3 contact_force(const ContactParameters &p, double ri, double rj, double m_eff, double delta,
                            const PairKinematics &k, double dt, Vec3 &shear_force, Vec3 &dashpot_force,
                            ContactDissipation &dissipation)
  {
    double kn, ks, fn_elastic;
    if (p.law == ContactLaw::linear)
    {
      linear_stiffness(p, ri, rj, kn, ks);
      fn_elastic = kn * delta;
    }
    else
    {
      double e_star, g_star, r_star;
      hertz_effective(p, ri, rj, e_star, g_star, r_star);
      const double a = std::sqrt(r_star * delta);
      fn_elastic = 4.0 / 3.0 * e_star * a * delta;
      kn = 2 * e_star * a; // tangent dF_n/d(delta), sets the dashpot scale
      ks = 8 * g_star * a;
    }
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

  /// Elastic energy stored in a contact with overlap delta and tangential force fs [J].
  inline double contact_elastic_energy(const ContactParameters &p, double ri, double rj, double delta,
                                       const Vec3 &fs)
  {
    if (delta <= 0)
      return 0;
    double kn, ks;
    contact_tangent_stiffness(p, ri, rj, delta, kn, ks);
    const double shear_part = 0.5 * fs.squaredNorm() / ks;
    if (p.law == ContactLaw::linear)
      return 0.5 * kn * delta * delta + shear_part;
    // int_0^delta 4/3 E* sqrt(R*) x^{3/2} dx = 8/15 E* sqrt(R*) delta^{5/2}
    double e_star, g_star, r_star;
    hertz_effective(p, ri, rj, e_star, g_star, r_star);
    return 8.0 / 15.0 * e_star * std::sqrt(r_star) * std::pow(delta, 2.5) + shear_part;
  }
} // namespace anticrack::dem
