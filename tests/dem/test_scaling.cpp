// Homothetic scaling (dem/sample/scaling.h): a scaled sample under the scaled loading is the same
// experiment in other units, so its stresses must be the original ones.

#include "dem/sample/lattice.h"
#include "dem/sample/scaling.h"
#include "dem_test_helpers.h"

#include <gtest/gtest.h>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

namespace
{
  /// A 3 x 3 x 4 bonded lattice, periodic in x and y, bottom layer fixed, top layer a clump pulled up
  /// by a force ramp; optionally scaled by s. Returns the peak base reaction stress (tension
  /// positive) and the time step used.
  std::pair<double, double> tension_test(double s)
  {
    DemSystem sys;
    sys.domain.lower = Vec3::Zero();
    sys.domain.upper = Vec3(6e-3, 6e-3, 8e-3);
    sys.domain.periodic = {true, true, false};
    sys.materials.add(bonded_material(bond_strengths(1e6, 1e6)));
    LatticeSpec lattice;
    lattice.cells = {3, 3, 4};
    add_simple_cubic_lattice(sys, lattice);
    sys.bond_touching_pairs(BondingRule{1e-9});
    std::vector<Index> fixed, top;
    for (Index p = 0; p < sys.particles.size(); ++p)
    {
      if (sys.particles.position[p].z() < 2e-3)
        fixed.push_back(p);
      if (sys.particles.position[p].z() > 6e-3)
        top.push_back(p);
    }
    for (const Index p : fixed)
      sys.particles.blocked[p] = block_all;
    const Index clump = sys.add_clump(top);
    sys.clumps[clump].applied_force = ForceHistory::ramp(2e4, Vec3::UnitZ());
    sys.settings.local_damping = 0.7;
    if (s != 1)
      scale_sample(sys, s);
    sys.initialise();
    const double area = sys.domain.length().x() * sys.domain.length().y();
    double peak = 0;
    for (Index n = 0; n < 20000 && sys.bonds.count_intact() == sys.bonds.size(); ++n)
    {
      sys.step();
      double reaction = 0;
      for (const Index p : fixed)
        reaction += sys.particles.force[p].z();
      peak = std::max(peak, reaction / area);
    }
    EXPECT_LT(sys.bonds.count_intact(), sys.bonds.size()) << "the sample should break, s = " << s;
    return {peak, sys.dt};
  }
} // namespace

// Scaled by 2.5 (lengths), with the clump force scaled by s^2 at times scaled by s: the critical time
// step grows by s and the discrete run is the same run in other units, so the peak base stress (the
// lattice's strength, close to sigma_c pi/4) agrees to round-off accumulated over the steps (1e-9).
TEST(HomotheticScaling, ScaledLatticeHasTheSameStrength)
{
  const auto [peak, dt] = tension_test(1.0);
  const auto [peak_scaled, dt_scaled] = tension_test(2.5);
  EXPECT_NEAR(dt_scaled / dt, 2.5, 1e-12);
  EXPECT_NEAR(peak_scaled / peak, 1.0, 1e-9) << peak << " vs " << peak_scaled;
  EXPECT_NEAR(peak, M_PI / 4 * 1e6, 0.02 * M_PI / 4 * 1e6); // the lattice's strength (one bond per column)
}

TEST(HomotheticScaling, RefusesBadFactorOrARunningSystem)
{
  DemSystem sys;
  sys.domain = open_box();
  sys.materials.add(Material{});
  sys.particles.add_sphere(Vec3::Zero(), 1e-3, 1e4, 0);
  EXPECT_THROW(scale_sample(sys, 0.0), SetupError);
  EXPECT_THROW(scale_sample(sys, -2.0), SetupError);
  sys.initialise();
  sys.step();
  EXPECT_THROW(scale_sample(sys, 2.0), SetupError);
}
