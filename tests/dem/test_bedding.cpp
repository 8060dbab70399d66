// Bedding planes (dem/sample/bedding.h): which bonds get the bedding strengths.

#include "dem/sample/bedding.h"
#include "dem/sample/lattice.h"
#include "dem_test_helpers.h"

#include <gtest/gtest.h>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

namespace
{
  /// 4 x 4 x 6 bonded simple-cubic lattice (spacing 2 mm, centres at odd mm), open box.
  void lattice(DemSystem &s)
  {
    s.domain = open_box();
    s.materials.add(bonded_material(bond_strengths(1e6, 1e6)));
    LatticeSpec spec;
    spec.cells = {4, 4, 6};
    add_simple_cubic_lattice(s, spec);
    s.bond_touching_pairs(BondingRule{1e-9});
  }
} // namespace

// Horizontal planes z = 0, 8, 16 mm (layers at z = 1, 3, ..., 11 mm). Thickness 0: only the 16
// vertical bonds across z = 8 mm. A band 2.2 mm thick (+-1.1 mm) also takes the horizontal bonds of
// the layers at z = 1, 7 and 9 mm (3 x 24) and every vertical bond whose widened segment reaches a
// plane: [1, 3] (z = 0), [5, 7], [7, 9] and [9, 11] (z = 8), 4 x 16; total 136.
TEST(Bedding, HorizontalPlanesPickTheCrossingBonds)
{
  DemSystem s;
  lattice(s);
  BeddingSpec bedding;
  bedding.spacing = 8e-3;
  bedding.offset = 0;
  bedding.tensile_strength = 2e5;
  EXPECT_EQ(apply_bedding(s, bedding), 16);
  Index weak = 0;
  for (Index b = 0; b < s.bonds.size(); ++b)
    if (s.bonds.tensile_strength[b] == 2e5)
    {
      ++weak;
      EXPECT_GT(std::abs(s.bonds.normal[b].z()), 0.99); // vertical bonds only
    }
  EXPECT_EQ(weak, 16);
  DemSystem t;
  lattice(t);
  bedding.thickness = 2.2e-3;
  EXPECT_EQ(apply_bedding(t, bedding), 3 * 24 + 4 * 16);
}

// Inclined planes: the count equals a brute-force test of each bond's segment against every plane
// of the family (sign change of n.x - c_k along the segment).
TEST(Bedding, InclinedPlanesMatchABruteForceCount)
{
  DemSystem s;
  lattice(s);
  BeddingSpec bedding;
  bedding.normal = Vec3(std::sin(0.5), 0, std::cos(0.5));
  bedding.spacing = 3.3e-3;
  bedding.offset = 0.7e-3;
  const Vec3 n = bedding.normal.normalized();
  Index expected = 0;
  for (Index b = 0; b < s.bonds.size(); ++b)
  {
    const double a = n.dot(s.particles.position[s.bonds.i[b]]), c = n.dot(s.particles.position[s.bonds.j[b]]);
    bool crosses = false;
    for (int k = -20; k <= 20; ++k)
    {
      const double plane = bedding.offset + k * bedding.spacing;
      crosses = crosses || (a - plane) * (c - plane) <= 0;
    }
    expected += crosses;
  }
  ASSERT_GT(expected, 0);
  EXPECT_EQ(apply_bedding(s, bedding), expected);
  BeddingSpec bad = bedding;
  bad.spacing = 0;
  EXPECT_THROW(apply_bedding(s, bad), SetupError);
}
