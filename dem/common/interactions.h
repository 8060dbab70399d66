// Pairwise interactions and their persistent state: contacts (from the neighbour list, any two
// spheres that overlap) and parallel bonds (created once, broken for good). Both keep a per-pair
// force/torque buffer filled in parallel; particles then gather their own sums in a fixed order,
// which makes the result independent of the number of threads (no racy accumulation).
#pragma once

#include "dem/common/types.h"

#include <cmath>
#include <utility>
#include <vector>

namespace anticrack::dem
{
  /// Output of one pair kernel: force on particle j (particle i gets the opposite) and the
  /// torques on i and j about their centres.
  struct PairLoad
  {
    Vec3 force_on_j = Vec3::Zero();
    Vec3 torque_on_i = Vec3::Zero();
    Vec3 torque_on_j = Vec3::Zero();

    PairLoad &operator+=(const PairLoad &other)
    {
      force_on_j += other.force_on_j;
      torque_on_i += other.torque_on_i;
      torque_on_j += other.torque_on_j;
      return *this;
    }
  };

  /// Candidate pairs of the Verlet list; a pair is an active contact while the spheres overlap.
  struct ContactList
  {
    std::vector<Index> i, j;
    std::vector<Vec3> shift;        ///< image shift added to x_j (periodic boundaries)
    std::vector<Vec3> shear_force;  ///< accumulated tangential force on j [N]
    std::vector<Vec3> normal;       ///< contact normal of the previous step (i -> j)
    std::vector<char> active;       ///< overlapping during the previous step
    std::vector<double> overlap;    ///< overlap at the last force evaluation (<= 0: apart) [m]
    std::vector<Vec3> dashpot_force;///< dashpot force on j at the last evaluation [N]
    std::vector<PairLoad> load;

    [[nodiscard]] Index size() const { return static_cast<Index>(i.size()); }
    void clear();
    void push_back(Index a, Index b, const Vec3 &s);
  };

  enum class BondState : std::uint8_t
  {
    intact = 0,
    broken_tension = 1,
    broken_shear = 2
  };

  /// Parallel bonds (Potyondy & Cundall 2004), docs/physics.md §1.2. Geometry and strengths are stored
  /// per bond so that generators can give individual bonds their own properties (bedding planes).
  struct BondList
  {
    std::vector<Index> i, j;
    std::vector<Vec3> shift;
    // --- constants of each bond
    std::vector<double> radius;           ///< R_bar = lambda_bar min(R_i, R_j) [m]
    std::vector<double> normal_stiffness; ///< k_n_bar A_bar [N/m]
    std::vector<double> shear_stiffness;  ///< k_s_bar A_bar [N/m]
    std::vector<double> twist_stiffness;  ///< k_s_bar J_bar [N m/rad]
    std::vector<double> bending_stiffness;///< k_n_bar I_bar [N m/rad]
    std::vector<double> tensile_strength; ///< sigma_bar_c [Pa]
    std::vector<double> cohesion;         ///< c_bar [Pa]
    std::vector<double> tan_friction;     ///< tan(phi_bar) [-]
    std::vector<double> moment_factor;    ///< beta_bar [-]
    // --- state
    std::vector<double> normal_force;     ///< F_bar_n, compression positive [N]
    std::vector<Vec3> shear_force;        ///< F_bar_s on particle j [N]
    std::vector<double> twist_moment;     ///< M_bar_t along n, on particle j [N m]
    std::vector<Vec3> bending_moment;     ///< M_bar_b on particle j [N m]
    std::vector<Vec3> normal;             ///< unit normal i -> j of the previous step
    std::vector<BondState> state;

    [[nodiscard]] Index size() const { return static_cast<Index>(i.size()); }
    [[nodiscard]] Index count_intact() const;
    void clear();
    /// Adds a bond with zero initial load; returns its index. Bonds are stored with i < j (the pair
    /// is flipped if needed), the order of the contact list.
    Index add(Index a, Index b, const Vec3 &shift, const Vec3 &normal, double bond_radius,
              double gap_length, double modulus, double stiffness_ratio, double tensile_strength,
              double cohesion, double friction_angle, double moment_factor);
    void resize(Index n);

    [[nodiscard]] double area(Index b) const;
    [[nodiscard]] double bending_inertia(Index b) const; ///< I_bar = pi R^4 / 4
    [[nodiscard]] double polar_inertia(Index b) const;   ///< J_bar = 2 I_bar
    /// Rim stresses of bond b from its current state, docs/physics.md §1.2: sigma_bar (tension positive)
    /// and tau_bar. With A = pi R^2, R/I = 4/(pi R^3) and R/J = 2/(pi R^3).
    [[nodiscard]] std::pair<double, double> rim_stresses(Index b) const
    {
      const double inverse_radius = 1.0 / radius[b];
      const double inverse_area = M_1_PI * inverse_radius * inverse_radius;
      const double rim_over_inertia = 4.0 * inverse_area * inverse_radius; // R / I
      const double sigma = -normal_force[b] * inverse_area +
                           moment_factor[b] * bending_moment[b].norm() * rim_over_inertia;
      const double tau = shear_force[b].norm() * inverse_area +
                         moment_factor[b] * std::abs(twist_moment[b]) * 0.5 * rim_over_inertia;
      return {sigma, tau};
    }
    /// Cheap screen before the exact failure test: the rim stresses with the vector norms replaced by
    /// the larger L1 norms (|v|_2 <= |v|_1) bound sigma and tau from above; sigma enters the shear
    /// criterion with -tan(phi) <= 0. Returns false only when neither criterion can be met.
    [[nodiscard]] bool may_fail(Index b) const
    {
      const double inverse_radius = 1.0 / radius[b];
      const double inverse_area = M_1_PI * inverse_radius * inverse_radius;
      const double rim_over_inertia = 4.0 * inverse_area * inverse_radius;
      const double sigma_bound = -normal_force[b] * inverse_area +
                                 moment_factor[b] * bending_moment[b].lpNorm<1>() * rim_over_inertia;
      const double tau_bound = shear_force[b].lpNorm<1>() * inverse_area +
                               moment_factor[b] * std::abs(twist_moment[b]) * 0.5 * rim_over_inertia;
      return sigma_bound >= tensile_strength[b] || tau_bound >= cohesion[b] - sigma_bound * tan_friction[b];
    }

    /// Elastic energy stored in bond b [J].
    [[nodiscard]] double elastic_energy(Index b) const;
  };
} // namespace anticrack::dem
