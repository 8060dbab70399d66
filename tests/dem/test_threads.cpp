// Thread independence: per-pair loads are gathered by each particle in a fixed order, so a run with
// 2 OpenMP threads must reproduce the 1-thread run bit for bit (exact equality, no tolerance).

#include "dem_test_helpers.h"

#include <vector>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

namespace
{
  struct Snapshot
  {
    std::vector<Vec3> position, velocity, angular_velocity;
    std::vector<BondState> bond_state;
    Index intact = 0;
    Index contacts = 0;
    double wall_force_z = 0;
  };

  /// 6x6x6 bonded lattice (216 spheres, 540 bonds) with weak bonds and random velocities, on a
  /// floor, squeezed by a wall moving down and pulled by gravity: bonds break and contacts open
  /// and close during the run.
  Snapshot run_lattice(int threads)
  {
    DemSystem::set_threads(threads);
    EXPECT_EQ(DemSystem::threads(), threads);
    DemSystem s;
    Material mat = bonded_material(bond_strengths(3e5, 3e5, 0.4));
    mat.contact.damping_ratio = 0.1;
    EXPECT_EQ(add_bonded_block(s, mat, 6, 0.2, 11), 3 * 6 * 6 * 5); // velocities up to 0.2 m/s, seed 11

    s.walls = {floor_wall(mat.contact), make_wall("top", -Vec3::UnitZ(), Vec3(0, 0, 12e-3), mat.contact,
                                                  WallControl::velocity, Vec3(0, 0, -0.3))};
    s.settings.gravity = Vec3(0, 0, -9.81);
    s.settings.local_damping = 0.1;
    s.initialise();
    s.run(400);

    Snapshot snap;
    snap.position = s.particles.position;
    snap.velocity = s.particles.velocity;
    snap.angular_velocity = s.particles.angular_velocity;
    snap.bond_state = s.bonds.state;
    snap.intact = s.bonds.count_intact();
    for (Index c = 0; c < s.contacts.size(); ++c)
      snap.contacts += s.contacts.active[c] ? 1 : 0;
    snap.wall_force_z = s.walls[1].force.z();
    return snap;
  }
} // namespace

TEST(Threads, OneAndTwoThreadsAgreeBitForBit)
{
  ThreadGuard guard;
  const Snapshot one = run_lattice(1);
  const Snapshot two = run_lattice(2);
  // The run must exercise breakage and contacts, otherwise the comparison proves little.
  EXPECT_LT(one.intact, static_cast<Index>(one.bond_state.size()));
  EXPECT_GT(one.intact, 0);
  EXPECT_GT(one.contacts, 0);

  ASSERT_EQ(one.position.size(), two.position.size());
  Index differing = 0;
  for (std::size_t p = 0; p < one.position.size(); ++p)
    if (one.position[p] != two.position[p] || one.velocity[p] != two.velocity[p] ||
        one.angular_velocity[p] != two.angular_velocity[p])
      ++differing;
  EXPECT_EQ(differing, 0) << "particles whose state differs between 1 and 2 threads";
  EXPECT_EQ(one.intact, two.intact);
  EXPECT_TRUE(one.bond_state == two.bond_state);
  EXPECT_EQ(one.contacts, two.contacts);
  EXPECT_EQ(one.wall_force_z, two.wall_force_z);
}
