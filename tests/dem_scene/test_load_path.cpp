// The load-path check of a DEM specimen (dem/scene/model.h, require_load_path): a column of
// spheres between a fixed base and an actuator clump carries a test only if its intact bonds join
// the two. Known by construction: a chain base - 1 - 2 - clump with every link, with one link
// missing, and with that link present but broken.
#include "dem/scene/model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

namespace
{
  using namespace anticrack;
  using namespace anticrack::dem;

  /// Six spheres in a vertical column: 0 and 1 the fixed base, 2 and 3 the sample, 4 and 5 the clump;
  /// bonds along the column except those named in `missing` (bond k joins spheres k and k + 1).
  DemModel column(const std::vector<Index> &missing)
  {
    DemModel model;
    DemSystem &s = model.system;
    s.domain.lower = Vec3(-0.01, -0.01, -0.01);
    s.domain.upper = Vec3(0.01, 0.01, 0.02);
    Material material;
    material.bond.enabled = true;
    material.bond.modulus = 1e9;
    s.materials.add(material);
    for (int k = 0; k < 6; ++k)
      s.particles.add_sphere(Vec3(0, 0, 2e-3 * k), 1e-3, 1e4, 0);
    for (Index k = 0; k < 5; ++k)
      if (std::find(missing.begin(), missing.end(), k) == missing.end())
        s.add_bond(k, k + 1);
    model.fixed_particles = {0, 1};
    model.clump = s.add_clump({4, 5});
    return model;
  }
} // namespace

TEST(LoadPath, ConnectedColumnPasses)
{
  const DemModel model = column({});
  EXPECT_NO_THROW(require_load_path(model.system, model));
  // links inside the base and inside the clump are not needed: each is one body
  const DemModel without_inner_links = column({0, 4});
  EXPECT_NO_THROW(require_load_path(without_inner_links.system, without_inner_links));
}

TEST(LoadPath, MissingOrBrokenLinkIsRefusedNamingBothEnds)
{
  const DemModel gap = column({2});
  try
  {
    require_load_path(gap.system, gap);
    ADD_FAILURE() << "a column without the link 2-3 was accepted";
  }
  catch (const SpecimenWithoutLoadPath &e)
  {
    const std::string message = e.what();
    EXPECT_NE(message.find("fixed base (2 spheres)"), std::string::npos) << message;
    EXPECT_NE(message.find("actuator clump (2 spheres)"), std::string::npos) << message;
    EXPECT_NE(message.find("holds 3 of 6 spheres"), std::string::npos) << message;
  }
  DemModel broken = column({});
  broken.system.bonds.state[2] = BondState::broken_tension;
  EXPECT_THROW(require_load_path(broken.system, broken), SpecimenWithoutLoadPath);
}
