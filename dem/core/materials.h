// Material parameters of contacts and parallel bonds (docs/physics.md §1.1, §1.2). Parameters are
// plain data kept apart from the state the interactions carry (MercuryDPM "species" style).
#pragma once

#include "dem/core/types.h"

#include <vector>

namespace anticrack::dem
{
  enum class ContactLaw
  {
    linear,       ///< k_n = E_c A / L, k_s = k_n / kappa, Coulomb cap
    hertz_mindlin ///< F_n = 4/3 E* sqrt(R*) delta^{3/2}, k_t = 8 G* sqrt(R* delta)
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

  struct BondParameters
  {
    bool enabled = false;         ///< whether touching pairs of this material may be bonded
    double modulus = 1e9;         ///< E_bar [Pa]
    double stiffness_ratio = 3.0; ///< kappa_bar = k_n_bar / k_s_bar [-]
    double radius_multiplier = 1; ///< lambda_bar [-]
    double tensile_strength = 1e6;///< sigma_bar_c [Pa]
    double cohesion = 1e6;        ///< c_bar [Pa]
    double friction_angle = 0.0;  ///< phi_bar [rad]
    double moment_factor = 1.0;   ///< beta_bar, moment contribution to the rim stresses [-]
  };

  struct Material
  {
    double density = 1e4; ///< rho [kg/m^3]
    ContactParameters contact;
    BondParameters bond;
  };

  /// Pair lookup. A pair (a, b) uses the explicitly set pair parameters if there are any,
  /// otherwise the parameters of the material with the smaller id.
  class MaterialTable
  {
  public:
    int add(const Material &m);
    void set_pair_contact(int a, int b, const ContactParameters &p);

    [[nodiscard]] int size() const { return static_cast<int>(materials_.size()); }
    [[nodiscard]] const Material &operator[](int id) const { return materials_.at(id); }
    [[nodiscard]] Material &operator[](int id) { return materials_.at(id); }
    [[nodiscard]] const ContactParameters &contact(int a, int b) const
    {
      return pair_contact_[a * size() + b];
    }

  private:
    void rebuild_pairs();
    std::vector<Material> materials_;
    std::vector<ContactParameters> pair_contact_;
    std::vector<char> pair_set_;
  };
} // namespace anticrack::dem
