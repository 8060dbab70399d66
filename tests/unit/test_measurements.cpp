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
