// Parameters of the contact laws (docs/physics.md §1.1): one flat struct shared by every law of the
// registry in dem/contact/contact_law.h; each law reads the fields it names, and names them as
// scene entries (ContactEntry). Plain data, kept apart from the state the contacts carry
// (MercuryDPM "species" style).
#pragma once

#include <limits>

namespace anticrack::dem
{
  /// Identifies a law of the registry (dem/contact/contact_law.h); its value is the id checkpoints
  /// store, so a new law takes the next free value.
  enum class ContactLaw
  {
    linear,       ///< k_n = E_c A / L, k_s = k_n / kappa, Coulomb cap (dem/contact/linear_contact.h)
    hertz_mindlin ///< F_n = 4/3 E* sqrt(R*) delta^{3/2}, k_t = 8 G* sqrt(R* delta) (hertz_mindlin_contact.h)
  };

  struct ContactParameters
  {
    ContactLaw law = ContactLaw::linear;
    double contact_modulus = 1e9;  ///< E_c [Pa] (linear law, PFC "deformability")
    double stiffness_ratio = 3.0;  ///< kappa = k_n / k_s [-] (linear law)
    double friction = 0.5;         ///< mu = tan(phi_contact) [-]
    double damping_ratio = 0.0;    ///< beta_d of the normal and shear dashpots [-]
    double young_modulus = 1e9;    ///< E [Pa] of the grain material (Hertz-Mindlin)
    double poisson_ratio = 0.3;    ///< nu [-] (Hertz-Mindlin)
  };

  /// One entry of subsection DEM/Material that a law reads (its kernel's visit_entries()): the
  /// scene declares it with a Double(lower, upper) pattern, parses it into `field` and refuses a
  /// value for which `acceptable` is false with `requirement` (dem/scene/parameters.cpp). Plain data:
  /// the engine stays free of the scene's parameter handler.
  struct ContactEntry
  {
    const char *name;
    const char *default_value;
    double lower, upper;
    const char *documentation;
    double ContactParameters::*field;
    bool (*acceptable)(double value);
    const char *requirement;
  };

  inline constexpr double unbounded = std::numeric_limits<double>::max();
} // namespace anticrack::dem
