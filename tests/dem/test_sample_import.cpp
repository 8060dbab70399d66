// Import of external samples (dem/io/state_hdf5.h read_sample): an anticrack snapshot read back as a
// sample gives its spheres and its intact bonds with their radii.

#include "dem/io/state_hdf5.h"
#include "dem/sample/lattice.h"
#include "dem_test_helpers.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

TEST(SampleImport, SnapshotGivesSpheresAndIntactBonds)
{
  DemSystem s;
  s.domain = open_box();
  s.materials.add(bonded_material(bond_strengths(1e6, 1e6)));
  LatticeSpec lattice;
  lattice.cells = {3, 2, 2};
  add_simple_cubic_lattice(s, lattice);
  const Index bonds = s.bond_touching_pairs(BondingRule{1e-9});
  ASSERT_EQ(bonds, 2 * 2 * 2 + 3 * 1 * 2 + 3 * 2 * 1); // x, y and z bonds of a 3 x 2 x 2 block
  s.bonds.state[0] = BondState::broken_tension;
  s.bonds.radius[1] = 0.4e-3;
  s.initialise();
  const std::string file = (std::filesystem::temp_directory_path() / "anticrack_sample_import.h5").string();
  io::write_snapshot(file, s);

  const io::ExternalSample sample = io::read_sample(file);
  std::remove(file.c_str());
  ASSERT_EQ(sample.position.size(), 12u);
  EXPECT_EQ(sample.position[5], s.particles.position[5]);
  EXPECT_EQ(sample.radius[7], s.particles.radius[7]);
  ASSERT_EQ(sample.bond_i.size(), static_cast<std::size_t>(bonds - 1)); // the broken one is left out
  EXPECT_EQ(sample.bond_i[0], s.bonds.i[1]);
  EXPECT_DOUBLE_EQ(sample.bond_radius[0], 0.4e-3);

  // Rebuilt from the file, the bonds are the same pairs.
  DemSystem t;
  t.domain = open_box();
  t.materials.add(bonded_material(bond_strengths(1e6, 1e6)));
  for (std::size_t k = 0; k < sample.position.size(); ++k)
    t.particles.add_sphere(sample.position[k], sample.radius[k], 1e4, 0);
  for (std::size_t b = 0; b < sample.bond_i.size(); ++b)
    t.add_bond(sample.bond_i[b], sample.bond_j[b], sample.bond_radius[b]);
  EXPECT_EQ(t.bonds.size(), bonds - 1);
  EXPECT_EQ(t.bonds.radius[0], 0.4e-3);
}

TEST(SampleImport, MissingOrBrokenFilesNameTheProblem)
{
  EXPECT_THROW(io::read_sample("/nonexistent/sample.h5"), std::runtime_error);
}
