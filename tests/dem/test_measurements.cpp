// Love-Weber stress and fabric (dem/lab/measurements.h) on states whose answers are known in closed form.

#include "dem/sample/lattice.h"
#include "dem/lab/measurements.h"
#include "dem_test_helpers.h"

#include <gtest/gtest.h>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

namespace
{
  /// Fully periodic n^3 simple-cubic lattice of touching spheres (R = 1 mm), every pair bonded, at
  /// rest with all particles held (so a step evaluates loads without moving anything).
  void build_periodic_lattice(DemSystem &s, Index n)
  {
    s.domain.lower = Vec3::Zero();
    s.domain.upper = Vec3::Constant(2e-3 * n);
    s.domain.periodic = {true, true, true};
    s.materials.add(bonded_material(bond_strengths(1e9, 1e9)));
    LatticeSpec lattice;
    lattice.cells = {n, n, n};
    add_simple_cubic_lattice(s, lattice);
    ASSERT_EQ(s.bond_touching_pairs(BondingRule{1e-9}), 3 * n * n * n);
    for (Index p = 0; p < s.particles.size(); ++p)
      s.particles.blocked[p] = block_all;
  }
} // namespace

// Every bond along x carries a tension F: the Love-Weber stress is sigma_xx = N_x F (2R) / V =
// F / (2R)^2 (one x-bond of length 2R per cell of volume (2R)^3), tension positive, all other
// components zero (round-off). The bonds across the periodic faces count through their shifts:
// leaving them out would give (n-1)/n of it.
TEST(LoveWeberStress, UniformBondTensionInAPeriodicLattice)
{
  DemSystem s;
  const Index n = 4;
  build_periodic_lattice(s, n);
  const double tension = 2.0; // N
  for (Index b = 0; b < s.bonds.size(); ++b)
    if (std::abs(s.bonds.normal[b].x()) > 0.5)
      s.bonds.normal_force[b] = -tension; // compression positive in the bond
  s.initialise();
  s.step(); // zero velocities: no increments, loads evaluated
  const double volume = std::pow(2e-3 * n, 3);
  const Mat3 stress = love_weber_stress(s, volume);
  const double expected = tension / (4e-6);
  EXPECT_NEAR(stress(0, 0), expected, 1e-12 * expected);
  Mat3 rest = stress;
  rest(0, 0) = 0;
  EXPECT_LE(rest.cwiseAbs().maxCoeff(), 1e-12 * expected);
}

// A single free sphere moving at v in a volume V, touching nothing: sigma = -m v (x) v / V, the
// kinetic (Reynolds) part, which include_kinetic = false removes.
TEST(LoveWeberStress, KineticPartOfAMovingSphere)
{
  DemSystem s;
  s.domain = open_box();
  s.materials.add(Material{});
  const Index p = s.particles.add_sphere(Vec3::Zero(), 1e-3, 1e4, 0);
  const Vec3 v(0.3, -0.2, 0.1);
  s.particles.velocity[p] = v;
  s.initialise();
  const double volume = 1e-6;
  const Mat3 expected = -s.particles.mass[p] * v * v.transpose() / volume;
  EXPECT_LE((love_weber_stress(s, volume) - expected).cwiseAbs().maxCoeff(), 1e-14 * expected.cwiseAbs().maxCoeff());
  EXPECT_EQ(love_weber_stress(s, volume, false), Mat3::Zero());
}

// Simple-cubic lattice: fabric C = I/3 exactly (bond normals along the three axes in equal numbers),
// coordination 6; a broken bond fraction that counts what was broken.
TEST(Fabric, SimpleCubicLatticeIsIsotropicWithSixNeighbours)
{
  DemSystem s;
  build_periodic_lattice(s, 3);
  s.initialise();
  const Fabric fabric = contact_and_bond_fabric(s);
  EXPECT_EQ(fabric.pairs, 81);
  EXPECT_DOUBLE_EQ(fabric.coordination, 6.0);
  EXPECT_LE((fabric.tensor - Mat3::Identity() / 3).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_DOUBLE_EQ(broken_bond_fraction(s.bonds), 0.0);
  s.bonds.state[0] = BondState::broken_tension;
  EXPECT_NEAR(broken_bond_fraction(s.bonds), 1.0 / 81, 1e-15);
}

// The sample volume is the box along periodic axes and the spheres' extent along open ones.
TEST(SampleVolume, PeriodicBoxAndOpenExtent)
{
  DemSystem s;
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(0.01, 0.02, 0.5);
  s.domain.periodic = {true, true, false};
  s.materials.add(Material{});
  s.particles.add_sphere(Vec3(0.005, 0.005, 0.1), 1e-3, 1e4, 0);
  s.particles.add_sphere(Vec3(0.005, 0.015, 0.103), 2e-3, 1e4, 0);
  // z from 0.1 - 0.001 to 0.103 + 0.002: 0.006 m
  EXPECT_NEAR(sample_volume(s), 0.01 * 0.02 * 0.006, 1e-15);
}

// A laterally periodic column of n x n x m touching spheres (2R = 2 mm), every z-bond carrying the
// compression F, with the bottom layer a fixed base and the top layer a loading platen. Static, no
// body force: the platens' separation is the distance between their centre planes, 2R (m - 1), and
// the specimen's Love-Weber stress over the platen area times it is the platen traction sigma_zz = -F / (2R)^2 exactly (m - 1 bonds
// of length 2R per column). Over the volume every sphere occupies, 2R m high, it would be diluted
// to (m - 1) / m of that.
TEST(LoveWeberStress, ASpecimenBetweenRigidPlatensCarriesThePlatenTraction)
{
  DemSystem s;
  const Index n = 3, m = 6;
  s.domain.lower = Vec3::Zero();
  s.domain.upper = Vec3(2e-3 * n, 2e-3 * n, 1.0);
  s.domain.periodic = {true, true, false};
  s.materials.add(bonded_material(bond_strengths(1e9, 1e9)));
  LatticeSpec lattice;
  lattice.cells = {n, n, m};
  add_simple_cubic_lattice(s, lattice);
  ASSERT_EQ(s.bond_touching_pairs(BondingRule{1e-9}), 3 * n * n * m - n * n);
  PlatenSpheres platens(s.particles.size(), Platen::none);
  for (Index p = 0; p < s.particles.size(); ++p)
  {
    s.particles.blocked[p] = block_all;
    const double z = s.particles.position[p].z();
    platens[p] = z < 2e-3 ? Platen::base : z > 2e-3 * (m - 1) ? Platen::top : Platen::none;
  }
  const double force = 3.0; // N, compression in every z-bond
  for (Index b = 0; b < s.bonds.size(); ++b)
    if (std::abs(s.bonds.normal[b].z()) > 0.5)
      s.bonds.normal_force[b] = force;
  s.initialise();
  s.step();
  const double traction = -force / 4e-6;
  const double area = std::pow(2e-3 * n, 2);
  EXPECT_NEAR(platen_separation(s, platens), 2e-3 * (m - 1), 1e-15);
  const Mat3 stress = love_weber_stress(s, area * platen_separation(s, platens), true, platens);
  EXPECT_NEAR(stress(2, 2), traction, 1e-12 * std::abs(traction));
  Mat3 rest = stress;
  rest(2, 2) = 0;
  EXPECT_LE(rest.cwiseAbs().maxCoeff(), 1e-12 * std::abs(traction));
  EXPECT_NEAR(sample_volume(s), area * 2e-3 * m, 1e-18);
  const Mat3 diluted = love_weber_stress(s, sample_volume(s));
  EXPECT_NEAR(diluted(2, 2), traction * (m - 1) / m, 1e-12 * std::abs(traction));
}

// Pairs within a platen and the platens' motion are no stress of the specimen: two bonded spheres
// of one platen moving at v add nothing; as material they add -F l / V and -m v (x) v / V.
TEST(LoveWeberStress, PairsWithinAPlatenAndItsMotionDoNotCount)
{
  DemSystem s;
  s.domain = open_box();
  s.materials.add(bonded_material(bond_strengths(1e9, 1e9)));
  const double r = 1e-3;
  s.particles.add_sphere(Vec3::Zero(), r, 1e4, 0);
  s.particles.add_sphere(Vec3(2 * r, 0, 0), r, 1e4, 0);
  ASSERT_EQ(s.bond_touching_pairs(BondingRule{1e-9}), 1);
  for (Index p = 0; p < 2; ++p)
    s.particles.blocked[p] = block_all;
  const double force = 2.0;
  s.bonds.normal_force[0] = force;
  s.initialise();
  s.step();
  const Vec3 v(0.1, 0, 0);
  for (Index p = 0; p < 2; ++p)
    s.particles.velocity[p] = v;
  const double volume = 1e-6;
  EXPECT_EQ(love_weber_stress(s, volume, true, {Platen::top, Platen::top}), Mat3::Zero());
  const double bond_part = -force * 2 * r / volume, kinetic_part = -2 * s.particles.mass[0] * v.x() * v.x() / volume;
  EXPECT_NEAR(love_weber_stress(s, volume, false, {Platen::none, Platen::none})(0, 0), bond_part, 1e-12 * std::abs(bond_part));
  EXPECT_NEAR(love_weber_stress(s, volume, true, {Platen::none, Platen::top})(0, 0), bond_part + kinetic_part / 2,
              1e-12 * std::abs(bond_part));
}

// A rough platen: two material spheres (r) on a base, under a top platen whose spheres sit at two
// heights, r at z = 4r and 2r at z = 5r. The columns carry F and 3F: the top platen's load enters
// at (F 4r + 3F 5r) / 4F = 4.75 r, the base's at 0, so the separation is 4.75 r (the distance
// between the highest base and the lowest top centre, 4r, would misplace it).
TEST(PlatenSeparation, IsWhereTheLoadEntersARoughPlaten)
{
  DemSystem s;
  s.domain = open_box();
  s.materials.add(bonded_material(bond_strengths(1e9, 1e9)));
  const double r = 1e-3;
  for (const double x : {0.0, 4 * r})
  {
    s.particles.add_sphere(Vec3(x, 0, 0), r, 1e4, 0);     // base
    s.particles.add_sphere(Vec3(x, 0, 2 * r), r, 1e4, 0); // material
  }
  s.particles.add_sphere(Vec3(0, 0, 4 * r), r, 1e4, 0);         // top, on the first column
  s.particles.add_sphere(Vec3(4 * r, 0, 5 * r), 2 * r, 1e4, 0); // top, on the second
  ASSERT_EQ(s.bond_touching_pairs(BondingRule{1e-9}), 4);
  for (Index p = 0; p < s.particles.size(); ++p)
    s.particles.blocked[p] = block_all;
  const PlatenSpheres platens{Platen::base, Platen::none, Platen::base, Platen::none, Platen::top, Platen::top};
  const double force = 1.0;
  for (Index b = 0; b < s.bonds.size(); ++b)
    s.bonds.normal_force[b] = s.particles.position[s.bonds.i[b]].x() > r ? 3 * force : force;
  s.initialise();
  s.step();
  EXPECT_NEAR(platen_separation(s, platens), 4.75 * r, 1e-15);
  EXPECT_THROW(platen_separation(s, {}), SetupError);
}
