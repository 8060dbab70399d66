// Material parameters of contacts (dem/contact/contact_parameters.h) and parallel bonds (docs/physics.md §1.1, §1.2). Parameters are
// plain data kept apart from the state the interactions carry (MercuryDPM "species" style).
#pragma once

#include "dem/contact/contact_parameters.h"
#include "dem/common/types.h"

#include <vector>

namespace anticrack::dem
{
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
