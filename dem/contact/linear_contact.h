// The linear contact law (docs/physics.md §1.1): constant stiffnesses k_n = E_c pi min(R)^2 / (R_i + R_j)
// and k_s = k_n / kappa, F_n = k_n delta. A stateless kernel of the registry in
// dem/contact/contact_law.h; friction and dashpots are common to every law (frictional_contact.h).
#pragma once

#include "dem/contact/contact_parameters.h"
#include "dem/common/types.h"

#include <algorithm>
#include <cmath>

namespace anticrack::dem
{
  struct LinearContact
  {
    static constexpr const char *name = "linear";
    static constexpr const char *documentation = "k_n = E_c A / L with A = pi min(R)^2, L = R_i + R_j, k_s = k_n / kappa";

    /// Its entries of DEM/Material (ContactEntry), in the order `anticrack params` lists them.
    template <class Visitor>
    static void visit_entries(Visitor &&entry)
    {
      entry(ContactEntry{"Contact modulus [Pa]", "1e9", 0, unbounded,
                         "E_c: contact modulus of the linear law (PFC 'deformability'). Units: Pa.",
                         &ContactParameters::contact_modulus, [](double v) { return v > 0; },
                         "must be positive for the linear contact law"});
      entry(ContactEntry{"Stiffness ratio", "3", 0, unbounded,
                         "kappa = k_n / k_s: normal-to-shear stiffness ratio of the linear law. Units: none.",
                         &ContactParameters::stiffness_ratio, [](double v) { return v > 0; }, "must be positive"});
    }
    /// The stiffness does not depend on the overlap: the critical time step counts every candidate
    /// pair, so that contacts forming before the next evaluation are covered.
    static constexpr bool stiffness_depends_on_overlap = false;

    /// k_n and k_s; for a wall, pass rj = 0 (L = R_i, A = pi R_i^2).
    static void stiffness(const ContactParameters &p, double ri, double rj, double &kn, double &ks)
    {
      const double rmin = rj > 0 ? std::min(ri, rj) : ri;
      kn = p.contact_modulus * M_PI * rmin * rmin / (ri + rj);
      ks = kn / p.stiffness_ratio;
    }

    /// Tangent stiffnesses at overlap delta (the critical time step, servo gains).
    static void tangent_stiffness(const ContactParameters &p, double ri, double rj, double /*delta*/,
                                  double &kn, double &ks)
    {
      stiffness(p, ri, rj, kn, ks);
    }

    /// Elastic normal force at overlap delta > 0, with the tangent stiffnesses that set the
    /// tangential spring and the dashpots.
    static double normal_force(const ContactParameters &p, double ri, double rj, double delta, double &kn,
                               double &ks)
    {
      stiffness(p, ri, rj, kn, ks);
      return kn * delta;
    }

    /// Elastic energy at overlap delta > 0 with tangential force fs: 1/2 k_n delta^2 + |F_s|^2 / (2 k_s).
    static double elastic_energy(const ContactParameters &p, double ri, double rj, double delta, const Vec3 &fs)
    {
      double kn, ks;
      stiffness(p, ri, rj, kn, ks);
      const double shear_part = 0.5 * fs.squaredNorm() / ks;
      return 0.5 * kn * delta * delta + shear_part;
    }

    /// Energy of the tangential spring that a separating contact releases (booked as friction):
    /// k_s stays finite as the overlap vanishes, so F_s may be non-zero at separation.
    static double shear_energy_at_separation(const ContactParameters &p, double ri, double rj, const Vec3 &fs)
    {
      double kn, ks;
      stiffness(p, ri, rj, kn, ks);
      return 0.5 * fs.squaredNorm() / ks;
    }

    /// The modulus of the law: E_c (P-wave time step estimate, packing pressure bounds).
    static double modulus(const ContactParameters &p) { return p.contact_modulus; }
  };
} // namespace anticrack::dem
