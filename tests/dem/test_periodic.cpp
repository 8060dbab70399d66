// Periodic boundaries (dem/core/domain.h): a pair straddling the periodic face must behave exactly like
// the same pair inside the box, through neighbour-list rebuilds that wrap the positions.

#include "dem_test_helpers.h"

#include <cmath>
#include <vector>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

namespace
{
  constexpr double box = 0.02; // periodic length along x [m]
  constexpr double radius = 1e-3;
  constexpr double dt = 1e-6;  // s
  constexpr Index steps = 10000;

  /// Two pairs of prescribed (blocked) particles: a bonded pair (material 1) at y = -5 mm with a
  /// 1e-6 m gap (so that its contact never closes and only the bond acts), and an unbonded pair
  /// (material 0) at y = +5 mm, 2e-6 m apart, which is pressed together, slid past each other
  /// (beyond the Coulomb limit) and separated. Particle 0 of each pair starts at x = x_start.
  void build(DemSystem &s, double x_start)
  {
    s.domain.lower = Vec3(0.0, -0.01, -0.01);
    s.domain.upper = Vec3(box, 0.01, 0.01);
    s.domain.periodic = {true, false, false};
    Material plain;
    plain.density = 1e4;
    plain.contact.friction = 0.3;
    s.materials.add(plain);
    BondSpec strong;
    strong.tensile_strength = 1e9;
    strong.cohesion = 1e9;
    s.materials.add(bonded_material(strong));

    auto place = [&](double x, double y) { return s.domain.wrap(Vec3(x, y, 0.0)); };
    s.particles.add_sphere(place(x_start, -0.005), radius, 1e4, 1);
    s.particles.add_sphere(place(x_start + 2 * radius + 1e-6, -0.005), radius, 1e4, 1);
    s.particles.add_sphere(place(x_start, 0.005), radius, 1e4, 0);
    s.particles.add_sphere(place(x_start + 2 * radius + 2e-6, 0.005), radius, 1e4, 0);
    EXPECT_EQ(s.bond_touching_pairs(BondingRule{2e-3}), 1);
    for (Index p = 0; p < 4; ++p)
      prescribe(s, p, Vec3::Zero());
    kinematic_settings(s, dt);
    s.initialise();
  }

  /// The same motion for both systems at step n: a common drift of 0.2 m/s along x (2 mm over the
  /// run, across the face) plus relative motions.
  void drive(DemSystem &s, Index n)
  {
    const Vec3 drift(0.2, 0.0, 0.0);
    const double w = 2 * M_PI / (2500 * dt); // four cycles over the run
    const double t = n * dt;
    // Bonded pair: opening +-1e-7 m, shear 2e-7 m (y) and 1e-7 m (z), spins of amplitude 1e-4 rad.
    prescribe(s, 0, drift, Vec3::Zero());
    prescribe(s, 1,
              drift + w * Vec3(1e-7 * std::cos(w * t), 2e-7 * std::cos(w * t), 1e-7 * std::sin(w * t)),
              w * 1e-4 * Vec3(std::cos(w * t), std::sin(w * t), -std::cos(w * t)));
    // Contact pair: close 3e-6 m (overlap 1e-6 m), slide 3e-6 m along y while rolling, separate.
    Vec3 v = Vec3::Zero(), spin = Vec3::Zero();
    if (n < 3000)
      v = Vec3(-3e-6 / (3000 * dt), 0, 0);
    else if (n < 6000)
    {
      v = Vec3(0, 3e-6 / (3000 * dt), 0);
      spin = Vec3(0, 0, 0.5);
    }
    else if (n < 9000)
      v = Vec3(3e-6 / (3000 * dt), 0, 0);
    prescribe(s, 2, drift, Vec3::Zero());
    prescribe(s, 3, drift + v, spin);
  }

  /// x_a - x_b - offset along the periodic axis, reduced to the minimum image.
  Vec3 periodic_difference(const Vec3 &xa, const Vec3 &xb, double offset)
  {
    Vec3 d = xa - xb;
    d.x() -= offset;
    d.x() -= box * std::nearbyint(d.x() / box);
    return d;
  }
} // namespace

// The straddling system starts with particle 0 of each pair 0.3 mm below the upper face (its
// partner already across it); the reference is the same system shifted into the middle of the box.
// Prescribed motions (no feedback, so round-off cannot be amplified by the dynamics) carry both
// across the face and trigger many neighbour-list rebuilds, which wrap the positions. The two runs
// do the same arithmetic on relative quantities and differ only by the round-off of absolute
// positions (ulp(0.02 m) = 3.5e-18 m per operation, at most ~1e-13 m after 1e4 steps if every
// error added up): positions must agree to 1e-12 m. The bond integrates velocity increments, in
// which positions enter only through the normal (1e-12 m / 2e-3 m): bond loads to 1e-9 of their
// peak. The contact's overlap is a difference of absolute positions, so its force can differ by
// kn times the position tolerance, 1.6e6 N/m x 1e-12 m = 1.6e-6 N, i.e. 1e-6 of its 1.6 N peak.
TEST(PeriodicBoundary, StraddlingPairMatchesInteriorPair)
{
  DemSystem a, b;
  const double x_face = box - 0.3 * radius;
  const double x_mid = 0.5 * box - 0.3 * radius;
  build(a, x_face);
  build(b, x_mid);
  ASSERT_EQ(a.particles.size(), 4);
  ASSERT_EQ(a.bonds.size(), 1);
  ASSERT_EQ(b.bonds.size(), 1);
  const double offset = x_face - x_mid;

  double max_position_error = 0, bond_error = 0, bond_scale = 0, contact_error = 0, contact_scale = 0;
  double max_friction = 0;
  bool wrapped = false;
  for (Index n = 0; n < steps; ++n)
  {
    drive(a, n);
    drive(b, n);
    a.step();
    b.step();
    for (Index p = 0; p < 4; ++p)
      max_position_error = std::max(
        max_position_error, periodic_difference(a.particles.position[p], b.particles.position[p], offset).norm());
    if (a.particles.position[0].x() < 0.25 * box)
      wrapped = true;
    for (Index p : {0, 1})
    {
      bond_scale = std::max(bond_scale, b.particles.force[p].norm());
      bond_error = std::max(bond_error, (a.particles.force[p] - b.particles.force[p]).norm());
      bond_error = std::max(bond_error, (a.particles.torque[p] - b.particles.torque[p]).norm() / radius);
    }
    for (Index p : {2, 3})
    {
      contact_scale = std::max(contact_scale, b.particles.force[p].norm());
      contact_error = std::max(contact_error, (a.particles.force[p] - b.particles.force[p]).norm());
      contact_error = std::max(contact_error, (a.particles.torque[p] - b.particles.torque[p]).norm() / radius);
    }
    max_friction = b.energy().friction;
  }
  EXPECT_TRUE(wrapped) << "particle 0 of the straddling system never crossed the face";
  EXPECT_GE(a.neighbor_builds(), 10);
  EXPECT_GT(bond_scale, 0.0);
  EXPECT_GT(contact_scale, 0.0) << "the contact pair never touched";
  EXPECT_GT(max_friction, 0.0) << "the contact pair never slid";
  EXPECT_LE(max_position_error, 1e-12);
  RecordProperty("max_position_error_m", sci(max_position_error));
  RecordProperty("bond_error_relative", sci(bond_error / bond_scale));
  RecordProperty("contact_error_relative", sci(contact_error / contact_scale));
  EXPECT_LE(bond_error, 1e-9 * bond_scale);
  EXPECT_LE(contact_error, 1e-6 * contact_scale);
  EXPECT_EQ(a.bonds.state[0], BondState::intact);
  EXPECT_LE(rel(a.bonds.normal_force[0], b.bonds.normal_force[0], bond_scale), 1e-9);
  EXPECT_LE(rel(a.bonds.shear_force[0], b.bonds.shear_force[0], bond_scale), 1e-9);
  EXPECT_LE(rel(a.energy().friction, b.energy().friction, max_friction), 1e-6);
}
