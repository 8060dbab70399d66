#include "dem/common/interactions.h"

#include <algorithm>
#include <cmath>

namespace anticrack::dem
{
  void ContactList::clear()
  {
    i.clear();
    j.clear();
    shift.clear();
    shear_force.clear();
    normal.clear();
    active.clear();
    overlap.clear();
    dashpot_force.clear();
    load.clear();
  }

  void ContactList::push_back(Index a, Index b, const Vec3 &s)
  {
    i.push_back(a);
    j.push_back(b);
    shift.push_back(s);
    shear_force.push_back(Vec3::Zero());
    normal.push_back(Vec3::Zero());
    active.push_back(0);
    overlap.push_back(0);
    dashpot_force.push_back(Vec3::Zero());
    load.emplace_back();
  }

  Index BondList::count_intact() const
  {
    return std::count(state.begin(), state.end(), BondState::intact);
  }

  void BondList::clear() { resize(0); }

  void BondList::resize(Index n)
  {
    i.resize(n);
    j.resize(n);
    shift.resize(n);
    radius.resize(n);
    normal_stiffness.resize(n);
    shear_stiffness.resize(n);
    twist_stiffness.resize(n);
    bending_stiffness.resize(n);
    tensile_strength.resize(n);
    cohesion.resize(n);
    tan_friction.resize(n);
    moment_factor.resize(n);
    normal_force.resize(n);
    shear_force.resize(n);
    twist_moment.resize(n);
    bending_moment.resize(n);
    normal.resize(n);
    state.resize(n);
  }

  Index BondList::add(Index a, Index b, const Vec3 &s, const Vec3 &n, double bond_radius,
                      double gap_length, double modulus, double stiffness_ratio,
                      double strength_tension, double strength_cohesion, double friction_angle,
                      double beta)
  {
    const Index k = size();
    resize(k + 1);
    const bool flip = b < a;
    i[k] = flip ? b : a;
    j[k] = flip ? a : b;
    shift[k] = flip ? Vec3(-s) : s;
    radius[k] = bond_radius;
    // Stiffness per unit area k_n = E / L with L = R_i + R_j (docs/physics.md §1.2).
    const double kn = modulus / gap_length;
    const double ks = kn / stiffness_ratio;
    const double area_k = M_PI * bond_radius * bond_radius;
    const double inertia_k = M_PI * bond_radius * bond_radius * bond_radius * bond_radius / 4;
    normal_stiffness[k] = kn * area_k;
    shear_stiffness[k] = ks * area_k;
    twist_stiffness[k] = ks * 2 * inertia_k;
    bending_stiffness[k] = kn * inertia_k;
    tensile_strength[k] = strength_tension;
    cohesion[k] = strength_cohesion;
    tan_friction[k] = std::tan(friction_angle);
    moment_factor[k] = beta;
    normal_force[k] = 0;
    shear_force[k] = Vec3::Zero();
    twist_moment[k] = 0;
    bending_moment[k] = Vec3::Zero();
    normal[k] = flip ? Vec3(-n) : n;
    state[k] = BondState::intact;
    return k;
  }

  double BondList::area(Index b) const { return M_PI * radius[b] * radius[b]; }
  double BondList::bending_inertia(Index b) const
  {
    const double r2 = radius[b] * radius[b];
    return M_PI * r2 * r2 / 4;
  }
  double BondList::polar_inertia(Index b) const { return 2 * bending_inertia(b); }

  double BondList::elastic_energy(Index b) const
  {
    return 0.5 * (normal_force[b] * normal_force[b] / normal_stiffness[b] +
                  shear_force[b].squaredNorm() / shear_stiffness[b] +
                  twist_moment[b] * twist_moment[b] / twist_stiffness[b] +
                  bending_moment[b].squaredNorm() / bending_stiffness[b]);
  }
} // namespace anticrack::dem
