// Shared set-up for the DEM physics tests: materials, two-particle systems with prescribed motion,
// bonded lattices, walls, closed-form bond constants (docs/physics.md §1.2) and small comparison
// helpers. Everything a test checks against is computed here from the formulas, never read back
// from the engine's own constants.
#pragma once

#include "dem/sample/lattice.h"
#include "dem/core/system.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace anticrack::dem::test
{
  inline constexpr double inf = std::numeric_limits<double>::infinity();

  /// A non-periodic box of half-width `half` around the origin (every test geometry fits in it).
  inline Domain open_box(double half = 0.05)
  {
    Domain d;
    d.lower = Vec3::Constant(-half);
    d.upper = Vec3::Constant(half);
    return d;
  }

  /// Material with parallel bonds enabled. Strengths default to "never breaks" (1e20 Pa) so that
  /// the closed-form elastic tests are not cut short; tests of breakage pass their own.
  struct BondSpec
  {
    double modulus = 1e9;
    double stiffness_ratio = 2.5;
    double radius_multiplier = 1.0;
    double tensile_strength = 1e20;
    double cohesion = 1e20;
    double friction_angle = 0.0;
    double moment_factor = 1.0;
  };

  inline Material bonded_material(const BondSpec &b = {}, double density = 1e4)
  {
    Material m;
    m.density = density;
    m.contact.law = ContactLaw::linear;
    m.contact.contact_modulus = 1e9;
    m.contact.stiffness_ratio = 3.0;
    m.contact.friction = 0.5;
    m.contact.damping_ratio = 0.0;
    m.bond.enabled = true;
    m.bond.modulus = b.modulus;
    m.bond.stiffness_ratio = b.stiffness_ratio;
    m.bond.radius_multiplier = b.radius_multiplier;
    m.bond.tensile_strength = b.tensile_strength;
    m.bond.cohesion = b.cohesion;
    m.bond.friction_angle = b.friction_angle;
    m.bond.moment_factor = b.moment_factor;
    return m;
  }

  /// Closed-form constants of a parallel bond between touching spheres of radii ri, rj:
  /// R = lambda min(ri, rj), A = pi R^2, I = pi R^4 / 4, J = 2 I, kn = E / (ri + rj), ks = kn / kappa.
  struct BondClosedForm
  {
    double radius, area, inertia, polar, kn, ks;
    [[nodiscard]] double normal_stiffness() const { return kn * area; }   // N/m
    [[nodiscard]] double shear_stiffness() const { return ks * area; }    // N/m
    [[nodiscard]] double twist_stiffness() const { return ks * polar; }   // N m/rad
    [[nodiscard]] double bending_stiffness() const { return kn * inertia; } // N m/rad
  };

  /// Energy 1/2 F^2 / k stored by a linear spring of stiffness k under the load F (force or moment).
  inline double spring_energy(double load, double stiffness) { return 0.5 * load * load / stiffness; }

  inline BondClosedForm bond_closed_form(const BondParameters &p, double ri, double rj)
  {
    BondClosedForm c;
    c.radius = p.radius_multiplier * std::min(ri, rj);
    c.area = M_PI * c.radius * c.radius;
    c.inertia = M_PI * std::pow(c.radius, 4) / 4.0;
    c.polar = 2.0 * c.inertia;
    c.kn = p.modulus / (ri + rj);
    c.ks = c.kn / p.stiffness_ratio;
    return c;
  }

  /// Linear contact stiffness of docs/physics.md §1.1, k_n = E_c pi min(R)^2 / (R_i + R_j).
  inline double linear_contact_kn(const ContactParameters &p, double ri, double rj)
  {
    const double r = std::min(ri, rj);
    return p.contact_modulus * M_PI * r * r / (ri + rj);
  }

  inline double sphere_mass(double r, double density) { return 4.0 / 3.0 * M_PI * r * r * r * density; }

  struct Pair
  {
    Index i = -1, j = -1;
    Vec3 normal = Vec3::UnitX(); ///< unit i -> j at set-up
    double ri = 0, rj = 0;
  };

  struct PairSpec
  {
    double ri = 1e-3, rj = 1e-3;
    Vec3 axis = Vec3::UnitX();     ///< direction i -> j (normalised here)
    Vec3 centre_i = Vec3::Zero();  ///< centre of particle i
    double gap = 0.0;              ///< surface gap (negative: overlap)
    int material = 0;
    double density = 1e4;
  };

  /// Adds two spheres along `axis`, i at `centre_i`, j at distance ri + rj + gap.
  inline Pair add_pair(DemSystem &s, const PairSpec &spec)
  {
    Pair p;
    p.normal = spec.axis.normalized();
    p.ri = spec.ri;
    p.rj = spec.rj;
    p.i = s.particles.add_sphere(spec.centre_i, spec.ri, spec.density, spec.material);
    p.j = s.particles.add_sphere(spec.centre_i + (spec.ri + spec.rj + spec.gap) * p.normal, spec.rj,
                                 spec.density, spec.material);
    return p;
  }

  /// Blocks every DOF of p and gives it the velocity and spin it keeps until changed again.
  inline void prescribe(DemSystem &s, Index p, const Vec3 &v, const Vec3 &w = Vec3::Zero())
  {
    s.particles.blocked[p] = block_all;
    s.particles.velocity[p] = v;
    s.particles.angular_velocity[p] = w;
  }

  /// Settings for purely kinematic tests (every particle prescribed): a fixed step and no energy
  /// abort, so that a test of a force law fails on the force law only. Energy closure under
  /// prescribed motion has its own test (test_energy.cpp).
  inline void kinematic_settings(DemSystem &s, double dt)
  {
    s.settings.time_step = dt;
    s.settings.energy_drift_tolerance = inf;
  }

  /// A bonded pair and the closed-form constants of its bond.
  struct BondedPair
  {
    Pair pair;
    BondClosedForm closed_form;
  };

  /// A touching bonded pair in an open box, both particles prescribed at rest, initialised.
  /// Returns the pair (the bond is s.bonds[0] with i < j) and the bond's closed-form constants.
  inline BondedPair make_bonded_pair(DemSystem &s, const PairSpec &spec, const BondSpec &bond, double dt)
  {
    s.domain = open_box();
    s.materials.add(bonded_material(bond, spec.density));
    Pair p = add_pair(s, spec);
    const Index n = s.bond_touching_pairs(BondingRule{1e-6});
    EXPECT_EQ(n, 1);
    EXPECT_EQ(s.bonds.size(), 1);
    if (s.bonds.size() == 1)
    {
      EXPECT_EQ(s.bonds.i[0], p.i);
      EXPECT_EQ(s.bonds.j[0], p.j);
    }
    prescribe(s, p.i, Vec3::Zero());
    prescribe(s, p.j, Vec3::Zero());
    kinematic_settings(s, dt);
    s.initialise();
    return {p, bond_closed_form(s.materials[0].bond, p.ri, p.rj)};
  }

  /// Bonds of tensile strength sigma_c and cohesion c [Pa], friction angle phi [rad], and the
  /// default stiffness of BondSpec.
  inline BondSpec bond_strengths(double tensile_strength, double cohesion, double friction_angle = 0.0)
  {
    BondSpec b;
    b.tensile_strength = tensile_strength;
    b.cohesion = cohesion;
    b.friction_angle = friction_angle;
    return b;
  }

  /// An n x n x n simple-cubic lattice of touching spheres (R = 1 mm, spacing 2 mm) of material
  /// `mat` in an open box, centred on the z axis and standing on z = 0, with random initial
  /// velocities up to `velocity_amplitude` per component (from `seed`); touching pairs are bonded
  /// (gap tolerance 1e-6). Returns the number of bonds made, 3 n^2 (n - 1).
  inline Index add_bonded_block(DemSystem &s, const Material &mat, Index n, double velocity_amplitude = 0,
                                std::uint64_t seed = 1)
  {
    s.domain = open_box();
    s.materials.add(mat);
    LatticeSpec lat;
    lat.cells = {n, n, n};
    lat.radius = 1e-3;
    lat.spacing = 2e-3;
    lat.origin = Vec3(-0.5 * n * lat.spacing, -0.5 * n * lat.spacing, 0.0);
    lat.velocity_amplitude = velocity_amplitude;
    lat.seed = seed;
    add_simple_cubic_lattice(s, lat);
    return s.bond_touching_pairs(BondingRule{1e-6});
  }

  /// A planar wall through `point` with unit `normal` pointing to the particle side, the sphere-wall
  /// `contact` law, and its `control` starting at `velocity`.
  inline Wall make_wall(const std::string &name, const Vec3 &normal, const Vec3 &point = Vec3::Zero(),
                        const ContactParameters &contact = {}, WallControl control = WallControl::fixed,
                        const Vec3 &velocity = Vec3::Zero())
  {
    Wall w;
    w.name = name;
    w.normal = normal;
    w.point = point;
    w.contact = contact;
    w.control = control;
    w.velocity = velocity;
    return w;
  }

  /// The fixed wall z = 0 facing up, named "floor".
  inline Wall floor_wall(const ContactParameters &contact = {})
  {
    return make_wall("floor", Vec3::UnitZ(), Vec3::Zero(), contact);
  }

  /// Linear sphere-wall contact law of the wall tests: E_c = 1e8 Pa, kappa = 2, no dashpots.
  inline ContactParameters wall_contact(double friction)
  {
    ContactParameters c;
    c.law = ContactLaw::linear;
    c.contact_modulus = 1e8;
    c.stiffness_ratio = 2.0;
    c.friction = friction;
    c.damping_ratio = 0.0;
    return c;
  }

  /// |a - b| / scale, for readable EXPECT_LE with a stated tolerance.
  inline double rel(double a, double b, double scale) { return std::abs(a - b) / scale; }
  inline double rel(const Vec3 &a, const Vec3 &b, double scale) { return (a - b).norm() / scale; }

  /// A number in scientific notation, for RecordProperty.
  inline std::string sci(double x)
  {
    std::ostringstream s;
    s.precision(3);
    s << std::scientific << x;
    return s.str();
  }

  /// Unit part of v orthogonal to n.
  inline Vec3 tangent_part(const Vec3 &v, const Vec3 &n)
  {
    const Vec3 t = v - v.dot(n) * n;
    return t.normalized();
  }

  /// Restores the OpenMP thread count at scope exit.
  struct ThreadGuard
  {
    int saved = DemSystem::threads();
    ~ThreadGuard() { DemSystem::set_threads(saved); }
  };

  /// One thread for long runs of a handful of particles, where thread start-up and barriers would
  /// dominate the run time; thread independence has its own test (test_threads.cpp).
  struct SingleThread
  {
    ThreadGuard guard;
    SingleThread() { DemSystem::set_threads(1); }
  };
} // namespace anticrack::dem::test
