// Time integration (docs/physics.md §1.3): the leapfrog under constant force, and detection of a time
// step above the critical one (refused up front, or caught by the stability check).

#include "dem_test_helpers.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

namespace
{
  std::string lower(std::string s)
  {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
  }

  /// A free bonded pair (equal radii 1 mm, density 1e4) with unbreakable bonds and small opposite
  /// velocities along the bond and across it. Returns kn_bar A_bar.
  double make_free_bonded_pair(DemSystem &s)
  {
    s.domain = open_box();
    s.materials.add(bonded_material(bond_strengths(1e300, 1e300)));
    const Pair p = add_pair(s, PairSpec{});
    EXPECT_EQ(s.bond_touching_pairs(BondingRule{1e-6}), 1);
    s.particles.velocity[p.i] = Vec3(-0.01, 0.004, 0);
    s.particles.velocity[p.j] = Vec3(0.01, -0.004, 0);
    return bond_closed_form(s.materials[0].bond, p.ri, p.rj).normal_stiffness();
  }
} // namespace

// Free fall from rest under gravity g. The leapfrog (v_{n+1/2} = v_{n-1/2} + g dt,
// x_{n+1} = x_n + v_{n+1/2} dt, forces before the update as system.h documents) gives after n steps
// exactly v = n g dt and x = x0 + g dt^2 n (n + 1) / 2 = x0 + g t^2 / 2 + g dt t / 2: the continuous
// parabola plus the half-step offset of the velocities. Tolerance 1e-12 relative (sums of n terms).
TEST(Leapfrog, GravityFreeFallIsExactDiscreteParabola)
{
  DemSystem s;
  s.domain = open_box(0.1); // falls 5 cm
  Material m;
  s.materials.add(m);
  const Vec3 x0(0.01, -0.02, 0.03);
  const Index p = s.particles.add_sphere(x0, 1e-3, 1e4, 0);
  const Vec3 g(0.5, -1.0, -9.81);
  s.settings.gravity = g;
  s.settings.time_step = 1e-4;
  s.settings.enforce_critical_step = false; // a lone sphere has no stiffness to limit dt
  s.initialise();
  const Index n = 1000;
  s.run(n);
  const double dt = 1e-4;
  const Vec3 v_expected = g * (n * dt);
  const Vec3 x_expected = x0 + g * (dt * dt * n * (n + 1) / 2.0);
  EXPECT_LE(rel(s.particles.velocity[p], v_expected, v_expected.norm()), 1e-12);
  EXPECT_LE(rel(s.particles.position[p], x_expected, (x_expected - x0).norm()), 1e-12);
  EXPECT_NEAR(s.time, n * dt, 1e-12 * n * dt);
  EXPECT_EQ(s.step_count, n);
  // Gravity is not part of the contact/bond loads gathered into particles.force.
  EXPECT_EQ(s.particles.force[p].norm(), 0.0);
}

// (a) A fixed step of twice the critical estimate is refused when enforce_critical_step is on
// (NumericalError naming the time step); half the estimate runs.
TEST(TimeStep, FixedStepAboveCriticalIsRefused)
{
  DemSystem s;
  const double kb = make_free_bonded_pair(s);
  s.initialise(); // automatic step
  const double dt_c = s.critical_time_step();
  const double m = sphere_mass(1e-3, 1e4);
  // The estimate must not exceed the true stability limit of the pair's axial mode with the bond
  // alone, dt < 2 / omega = sqrt(2 m / kb), and must not be absurdly small.
  EXPECT_GT(dt_c, 0.0);
  EXPECT_LT(dt_c, std::sqrt(2 * m / kb));
  EXPECT_GT(dt_c, 0.1 * std::sqrt(m / kb));
  EXPECT_NEAR(s.dt, s.settings.time_step_safety * dt_c, 1e-9 * dt_c);

  s.settings.time_step = 2 * dt_c;
  s.settings.enforce_critical_step = true;
  try
  {
    s.initialise();
    s.run(10);
    ADD_FAILURE() << "a fixed time step of 2 x the critical step was accepted";
  }
  catch (const NumericalError &e)
  {
    const std::string what = lower(e.what());
    EXPECT_TRUE(what.find("time step") != std::string::npos || what.find("time_step") != std::string::npos ||
                what.find("dt") != std::string::npos)
        << "message does not name the time step: " << e.what();
  }

  DemSystem ok;
  make_free_bonded_pair(ok);
  ok.settings.time_step = 0.5 * dt_c;
  ok.settings.enforce_critical_step = true;
  EXPECT_NO_THROW({
    ok.initialise();
    ok.run(200);
  });
}

// (b) Without the up-front check, dt = 3 sqrt(m/kb) puts the pair's axial mode at
// omega dt = 3 sqrt(2) = 4.2 > 2: the leapfrog amplifies it by ~16 per step, and the run must stop
// with a NumericalError (energy drift or non-finite state) within a bounded number of steps (the
// stability check runs every 100 steps). The same pair at dt = 0.1 sqrt(m/kb) runs quietly.
TEST(TimeStep, UnstableStepIsDetectedWhileRunning)
{
  const double m = sphere_mass(1e-3, 1e4);
  {
    DemSystem s;
    const double kb = make_free_bonded_pair(s);
    s.settings.time_step = 3 * std::sqrt(m / kb);
    s.settings.enforce_critical_step = false;
    s.initialise();
    EXPECT_THROW(s.run(1000), NumericalError);
    EXPECT_LE(s.step_count, 400);
  }
  {
    DemSystem s;
    const double kb = make_free_bonded_pair(s);
    s.settings.time_step = 0.1 * std::sqrt(m / kb);
    s.settings.enforce_critical_step = false;
    s.initialise();
    EXPECT_NO_THROW(s.run(2000));
    for (Index p = 0; p < s.particles.size(); ++p)
      EXPECT_TRUE(s.particles.position[p].allFinite());
  }
}
