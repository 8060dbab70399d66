// The registry of contact laws (docs/physics.md §1.1): each law is a stateless kernel in its own header
// (linear_contact.h, hertz_mindlin_contact.h) on ContactParameters and the pair geometry. The scene
// picks a law by name once at set-up (contact_law_by_name); the engine reaches a pair's kernels through
// visit_contact_law, one switch per pair that selects an inlined instantiation of the law (no
// indirect call in the force loop). A law's header also names the scene entries it reads
// (visit_entries: DEM/Material declares, parses and checks them from that list). Adding a law: its
// header, an id (and any new fields) in contact_parameters.h, and one line in
// registered_contact_laws and in visit_contact_law below.
#pragma once

#include "dem/contact/contact_parameters.h"
#include "dem/contact/frictional_contact.h"
#include "dem/contact/hertz_mindlin_contact.h"
#include "dem/contact/linear_contact.h"
#include "dem/common/types.h"

#include <array>
#include <string>

namespace anticrack::dem
{
  /// Every law, in the order of their ids.
  inline constexpr std::array<ContactLaw, 2> registered_contact_laws = {ContactLaw::linear,
                                                                        ContactLaw::hertz_mindlin};

  /// Calls visit(Law{}) with the kernel type of `law` and returns its result.
  template <class Visitor>
  inline decltype(auto) visit_contact_law(ContactLaw law, Visitor &&visit)
  {
    switch (law)
    {
      case ContactLaw::linear:
        return visit(LinearContact{});
      case ContactLaw::hertz_mindlin:
        return visit(HertzMindlinContact{});
    }
    throw SetupError("contact law id " + std::to_string(static_cast<int>(law)) + " is not registered");
  }

  /// The law's name as scenes spell it ("linear", "hertz-mindlin").
  inline std::string contact_law_name(ContactLaw law)
  {
    return visit_contact_law(law, [](auto kernel) { return std::string(decltype(kernel)::name); });
  }

  /// The names of every law joined by '|' (a deal.II Patterns::Selection).
  inline std::string contact_law_names()
  {
    std::string names;
    for (const ContactLaw law : registered_contact_laws)
      names += (names.empty() ? "" : "|") + contact_law_name(law);
    return names;
  }

  /// "`linear` has ...; `hertz-mindlin` has ...": each law's documentation, for the help text.
  inline std::string contact_law_documentation()
  {
    std::string text;
    for (const ContactLaw law : registered_contact_laws)
      text += (text.empty() ? "`" : "; `") +
              visit_contact_law(law, [](auto kernel) {
                using Kernel = decltype(kernel);
                return std::string(Kernel::name) + "` has " + Kernel::documentation;
              });
    return text;
  }

  /// Calls entry(ContactEntry) for every entry of every registered law, law by law.
  template <class Visitor>
  inline void visit_contact_entries(Visitor &&entry)
  {
    for (const ContactLaw law : registered_contact_laws)
      visit_contact_law(law, [&](auto kernel) { decltype(kernel)::visit_entries(entry); });
  }

  /// Calls entry(ContactEntry) for the entries of `law`.
  template <class Visitor>
  inline void visit_contact_entries(const ContactLaw law, Visitor &&entry)
  {
    visit_contact_law(law, [&](auto kernel) { decltype(kernel)::visit_entries(entry); });
  }

  /// The law called `name`; throws SetupError naming the known laws otherwise.
  inline ContactLaw contact_law_by_name(const std::string &name)
  {
    for (const ContactLaw law : registered_contact_laws)
      if (contact_law_name(law) == name)
        return law;
    throw SetupError("unknown contact law '" + name + "' (known: " + contact_law_names() + ")");
  }

  /// One step of a contact with overlap delta > 0 (see frictional_contact_force). Returns the force on j.
  inline Vec3 contact_force(const ContactParameters &p, double ri, double rj, double m_eff, double delta,
                            const PairKinematics &k, double dt, Vec3 &shear_force, Vec3 &dashpot_force,
                            ContactDissipation &dissipation)
  {
    return visit_contact_law(p.law, [&](auto kernel) {
      return frictional_contact_force<decltype(kernel)>(p, ri, rj, m_eff, delta, k, dt, shear_force,
                                                        dashpot_force, dissipation);
    });
  }

  /// Current tangent stiffnesses of a contact with overlap delta (rj = 0 for a wall).
  inline void contact_tangent_stiffness(const ContactParameters &p, double ri, double rj, double delta,
                                        double &kn, double &ks)
  {
    visit_contact_law(p.law, [&](auto kernel) { decltype(kernel)::tangent_stiffness(p, ri, rj, delta, kn, ks); });
  }

  /// Whether the law's stiffness depends on the overlap (then apart pairs have none).
  inline bool contact_stiffness_depends_on_overlap(const ContactParameters &p)
  {
    return visit_contact_law(p.law, [](auto kernel) { return decltype(kernel)::stiffness_depends_on_overlap; });
  }

  /// Elastic energy stored in a contact with overlap delta and tangential force fs [J].
  inline double contact_elastic_energy(const ContactParameters &p, double ri, double rj, double delta,
                                       const Vec3 &fs)
  {
    if (delta <= 0)
      return 0;
    return visit_contact_law(p.law, [&](auto kernel) { return decltype(kernel)::elastic_energy(p, ri, rj, delta, fs); });
  }

  /// Energy of the tangential spring that a contact releases when it separates [J].
  inline double contact_shear_energy_at_separation(const ContactParameters &p, double ri, double rj, const Vec3 &fs)
  {
    return visit_contact_law(p.law,
                             [&](auto kernel) { return decltype(kernel)::shear_energy_at_separation(p, ri, rj, fs); });
  }

  /// The law's modulus: E_c (linear) or E (Hertz-Mindlin); the P-wave time step estimate and the
  /// bounds of packing pressures compare with it.
  inline double contact_law_modulus(const ContactParameters &p)
  {
    return visit_contact_law(p.law, [&](auto kernel) { return decltype(kernel)::modulus(p); });
  }
} // namespace anticrack::dem
