// Rigid clumps (dem/core/clumps.h) and servo-controlled walls (dem/core/walls.h).

#include "dem_test_helpers.h"

#include <cmath>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

// A two-sphere clump (radii 1 and 0.5 mm, touching) under a constant applied force F on its centre
// of mass and nothing else: mass M = m_a + m_b, centre at the mass-weighted mean, and after n steps
// exactly v = n (F/M) dt, x = x0 + (F/M) dt^2 n (n + 1) / 2 (leapfrog under a constant force, see
// the free-fall test). The force passes through the centre, so there is no rotation: both members
// move by the same vector. Tolerance 1e-12 relative (round-off of n-term sums).
TEST(Clumps, ConstantAppliedForceAcceleratesAsFOverM)
{
  DemSystem s;
  s.domain = open_box(0.02); // the clump travels 6 mm
  s.materials.add(Material{});
  const double ra = 1e-3, rb = 0.5e-3, rho = 1e4;
  const Vec3 xa(0.01, 0.0, 0.0), xb(0.01 + ra + rb, 0.0, 0.0);
  const Index a = s.particles.add_sphere(xa, ra, rho, 0);
  const Index b = s.particles.add_sphere(xb, rb, rho, 0);
  const Index c = s.add_clump({a, b});
  const double ma = sphere_mass(ra, rho), mb = sphere_mass(rb, rho), mass = ma + mb;
  const Vec3 centre0 = (ma * xa + mb * xb) / mass;
  EXPECT_LE(rel(s.clumps[c].mass, mass, mass), 1e-12);
  EXPECT_LE(rel(s.clumps[c].centre, centre0, ra), 1e-12);
  EXPECT_EQ(s.particles.clump_id[a], static_cast<int>(c));
  EXPECT_EQ(s.particles.clump_id[b], static_cast<int>(c));

  const Vec3 force(2e-4, -1e-4, 5e-5);
  ForceHistory h;
  h.time = {0.0};
  h.value = {force};
  s.clumps[c].applied_force = h;
  const double dt = 1e-4;
  s.settings.time_step = dt;
  s.settings.enforce_critical_step = false; // nothing stiff in the system
  s.initialise();
  const Index n = 500;
  s.run(n);

  const Vec3 acc = force / mass;
  const Vec3 shift = acc * (dt * dt * n * (n + 1) / 2.0);
  EXPECT_LE(rel(s.clumps[c].velocity, Vec3(acc * (n * dt)), (acc * n * dt).norm()), 1e-12);
  EXPECT_LE(rel(s.clumps[c].centre, Vec3(centre0 + shift), shift.norm()), 1e-12);
  EXPECT_LE(rel(s.particles.position[a], Vec3(xa + shift), shift.norm()), 1e-12);
  EXPECT_LE(rel(s.particles.position[b], Vec3(xb + shift), shift.norm()), 1e-12);
  EXPECT_LE(s.clumps[c].angular_velocity.norm() * ra, 1e-12 * (acc * n * dt).norm());
  // External work of the applied force = kinetic energy gained: booked with the mean velocity of
  // each step, F.(v_{k-1} + v_k)/2 dt summed over k = 1..n is M a^2 dt^2 n^2 / 2 = 1/2 M v_n^2
  // exactly, so only round-off remains (1e-10).
  const EnergyLedger e = s.energy();
  EXPECT_GT(e.external_work, 0.0);
  EXPECT_LE(std::abs(e.balance() - s.initial_balance), 1e-10 * e.external_work);
}

// A two-sphere clump falls under gravity with one member landing on a fixed sphere, which pushes
// it off-centre. Free: the clump tips (its axis turns by more than 1e-3 rad) while its members
// keep their distance (rigid, 1e-12 relative). Rotation locked: the member offset vector stays
// exactly as it was (1e-12) although the same off-centre contact acts.
TEST(Clumps, OffCentreContactRotatesFreeClumpButNotLockedOne)
{
  for (const bool locked : {false, true})
  {
    SCOPED_TRACE(locked ? "rotation locked" : "free rotation");
    DemSystem s;
    s.domain = open_box();
    Material m;
    m.density = 1e4;
    m.contact.contact_modulus = 1e8;
    s.materials.add(m);
    const double r = 1e-3;
    const Index a = s.particles.add_sphere(Vec3(-r, 0, 0), r, 1e4, 0);
    const Index b = s.particles.add_sphere(Vec3(r, 0, 0), r, 1e4, 0);
    const Index base = s.particles.add_sphere(Vec3(-r, 0, -2 * r - 1e-6), r, 1e4, 0);
    prescribe(s, base, Vec3::Zero());
    const Index c = s.add_clump({a, b});
    s.clumps[c].rotation_locked = locked;
    s.settings.gravity = Vec3(0, 0, -9.81);
    s.settings.time_step = 1e-6;
    s.initialise();
    const Vec3 offset0 = s.particles.position[b] - s.particles.position[a];
    const double z0 = s.clumps[c].centre.z();
    double max_contact = 0;
    s.run(3000, [&](const DemSystem &sys) { max_contact = std::max(max_contact, sys.particles.force[a].norm()); });
    ASSERT_GT(max_contact, 0.0) << "the clump never touched the base";
    const Vec3 offset = s.particles.position[b] - s.particles.position[a];
    EXPECT_LE(rel(offset.norm(), offset0.norm(), offset0.norm()), 1e-12);
    EXPECT_LT(s.clumps[c].centre.z(), z0); // it fell
    const double turned = std::acos(std::min(1.0, offset.normalized().dot(offset0.normalized())));
    if (locked)
    {
      EXPECT_LE(rel(offset, offset0, offset0.norm()), 1e-12);
      EXPECT_LE(s.clumps[c].angular_velocity.norm(), 1e-12);
    }
    else
      EXPECT_GT(turned, 1e-3);
  }
}

// A 3x3x3 bonded lattice between a fixed floor and a servo-controlled top wall with target stress
// 1e5 Pa on the lattice's cross-section (6 mm x 6 mm): the wall must settle at the target.
// Reference: the simple-cubic columns compress uniformly; each of the 9 columns is 4 springs in
// series (2 wall contacts kn = E_c pi R, 2 bonded contacts kn_bar A_bar + kn_contact), so the wall
// must move by F / K. The servo is first order with time constant 1/(gain K) = 200 steps; after
// 20 time constants its residual is e^-20 = 2e-9 of the target, local damping 0.7 has removed the
// column's vibrations, and the compressed lattice is linear (bonds and contacts in parallel, wall
// contacts in series), so stress and displacement must match to 1e-6 (500x that residual).
TEST(Walls, ServoWallReachesTargetStress)
{
  DemSystem s;
  BondSpec bond;
  bond.modulus = 1e9;
  bond.stiffness_ratio = 3.0;
  const Material mat = bonded_material(bond);
  ASSERT_EQ(add_bonded_block(s, mat, 3), 54);

  const double r = 1e-3, area = 36e-6, target = 1e5;
  Wall top = make_wall("top", -Vec3::UnitZ(), Vec3(0, 0, 6e-3), mat.contact, WallControl::servo);
  top.target_stress = target;
  top.area = area;
  top.max_speed = 0.05;
  s.walls = {floor_wall(mat.contact), top};
  s.settings.local_damping = 0.7;
  s.initialise();

  const double k_wall = mat.contact.contact_modulus * M_PI * r;
  const double k_pair = bond_closed_form(mat.bond, r, r).normal_stiffness() + linear_contact_kn(mat.contact, r, r);
  const double k_column = 1.0 / (2.0 / k_wall + 2.0 / k_pair);
  const double k_total = 9 * k_column;
  s.walls[1].servo_gain = 1.0 / (200 * s.dt * k_total);

  const Index steps = 4000;
  double mean_stress = 0;
  s.run(steps, [&](const DemSystem &sys) {
    if (sys.step_count > steps - 200)
      mean_stress += sys.walls[1].normal_stress() / 200;
  });
  RecordProperty("mean_stress_error", sci(rel(mean_stress, target, target)));
  RecordProperty("displacement_error", sci(rel(6e-3 - s.walls[1].point.z(), target * area / k_total, target * area / k_total)));
  EXPECT_LE(rel(mean_stress, target, target), 1e-6);
  EXPECT_LE(rel(s.walls[1].normal_stress(), target, target), 1e-6);
  const double moved = 6e-3 - s.walls[1].point.z();
  const double expected = target * area / k_total;
  EXPECT_LE(rel(moved, expected, expected), 1e-6) << "moved " << moved << " m, F/K = " << expected << " m";
  EXPECT_EQ(s.bonds.count_intact(), 54);
}
