// The Hertz-Mindlin contact law (docs/physics.md §1.1) for two spheres of the same material or a sphere
// on a rigid flat wall: F_n = 4/3 E* sqrt(R*) delta^{3/2}, tangent stiffnesses k_n = 2 E* a and
// k_t = 8 G* a with a = sqrt(R* delta). A stateless kernel of the registry in dem/contact/contact_law.h;
// friction and dashpots are common to every law (frictional_contact.h).
#pragma once

#include "dem/contact/contact_parameters.h"
#include "dem/common/types.h"

#include <algorithm>
#include <cmath>

namespace anticrack::dem
{
  struct HertzMindlinContact
  {
    static constexpr const char *name = "hertz-mindlin";
    static constexpr const char *documentation = "F_n = 4/3 E* sqrt(R*) delta^(3/2) and k_t = 8 G* sqrt(R* delta)";

    /// Its entries of DEM/Material (ContactEntry), in the order `anticrack params` lists them.
    template <class Visitor>
    static void visit_entries(Visitor &&entry)
    {
      entry(ContactEntry{"Young modulus [Pa]", "1e9", 0, unbounded,
                         "E: Young's modulus of the grain material (Hertz-Mindlin law only). Units: Pa.",
                         &ContactParameters::young_modulus, [](double v) { return v > 0; },
                         "must be positive for the Hertz-Mindlin law"});
      entry(ContactEntry{"Poisson ratio", "0.3", 0, 0.5,
                         "nu: Poisson's ratio of the grain material (Hertz-Mindlin law only). Units: none.",
                         &ContactParameters::poisson_ratio, [](double v) { return v < 0.5; },
                         "must be below 0.5 for the Hertz-Mindlin law"});
    }
    /// Apart pairs have no stiffness: the critical time step counts touching pairs only.
    static constexpr bool stiffness_depends_on_overlap = true;

    /// Effective moduli and radius (rj = 0 for a rigid flat wall): 1/E* = 2 (1 - nu^2)/E,
    /// 1/G* = 2 (2 - nu)/G.
    static void effective(const ContactParameters &p, double ri, double rj, double &e_star, double &g_star,
                          double &r_star)
    {
      const double nu = p.poisson_ratio;
      const double shear_modulus = p.young_modulus / (2 * (1 + nu));
      const bool wall = rj <= 0;
      e_star = p.young_modulus / ((wall ? 1.0 : 2.0) * (1 - nu * nu));
      g_star = shear_modulus / ((wall ? 1.0 : 2.0) * (2 - nu));
      r_star = wall ? ri : ri * rj / (ri + rj);
    }

    /// Tangent stiffnesses at overlap delta (the critical time step, servo gains); zero when apart.
    static void tangent_stiffness(const ContactParameters &p, double ri, double rj, double delta, double &kn,
                                  double &ks)
    {
      double e_star, g_star, r_star;
      effective(p, ri, rj, e_star, g_star, r_star);
      const double a = std::sqrt(r_star * std::max(delta, 0.0));
      kn = 2 * e_star * a;
      ks = 8 * g_star * a;
    }

    /// Elastic normal force at overlap delta > 0, with the tangent stiffnesses that set the
    /// tangential spring and the dashpots.
    static double normal_force(const ContactParameters &p, double ri, double rj, double delta, double &kn,
                               double &ks)
    {
      double e_star, g_star, r_star;
      effective(p, ri, rj, e_star, g_star, r_star);
      const double a = std::sqrt(r_star * delta);
      kn = 2 * e_star * a; // tangent dF_n/d(delta), sets the dashpot scale
      ks = 8 * g_star * a;
      return 4.0 / 3.0 * e_star * a * delta;
    }

    /// Elastic energy at overlap delta > 0 with tangential force fs:
    /// int_0^delta 4/3 E* sqrt(R*) x^{3/2} dx = 8/15 E* sqrt(R*) delta^{5/2}, plus |F_s|^2 / (2 k_t).
    static double elastic_energy(const ContactParameters &p, double ri, double rj, double delta, const Vec3 &fs)
    {
      double kn, ks;
      tangent_stiffness(p, ri, rj, delta, kn, ks);
      const double shear_part = 0.5 * fs.squaredNorm() / ks;
      double e_star, g_star, r_star;
      effective(p, ri, rj, e_star, g_star, r_star);
      return 8.0 / 15.0 * e_star * std::sqrt(r_star) * std::pow(delta, 2.5) + shear_part;
    }

    /// Not booked at separation: with |F_s| <= mu F_n ~ delta^{3/2} and k_t ~ delta^{1/2} the
    /// tangential spring's energy vanishes with the overlap (~ delta^{5/2}).
    static double shear_energy_at_separation(const ContactParameters &, double, double, const Vec3 &)
    {
      return 0;
    }

    /// The modulus of the law: E (P-wave time step estimate, packing pressure bounds).
    static double modulus(const ContactParameters &p) { return p.young_modulus; }
  };
} // namespace anticrack::dem
