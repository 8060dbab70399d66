// Contact laws (docs/physics.md §1.1): Coulomb sliding threshold and friction dissipation (kinematic on a
// wall, and dynamic on an inclined plane), Hertz normal force and Mindlin tangential stiffness.

#include "dem_test_helpers.h"

#include <cmath>

using namespace anticrack::dem;
using namespace anticrack::dem::test;

namespace
{
  Material plain_material(double density = 1e4)
  {
    Material m;
    m.density = density;
    m.bond.enabled = false;
    return m;
  }
} // namespace

// ------------------------------------------------------------------------------------------------
// 6. Coulomb sliding threshold.
// ------------------------------------------------------------------------------------------------

// A sphere pressed into a flat wall by a fixed overlap delta (N = kn delta, kn = E_c pi R for a
// wall) is dragged tangentially at constant speed. While ks u < mu N it sticks and the wall's
// tangential force is -ks u; beyond, the force stays at mu N opposite to the motion. The energy
// dissipated by friction is mu N times the slip, slip = u_total - mu N / ks. The overlap never
// changes on a flat wall, so everything is exact up to round-off: tolerance 1e-9 relative.
TEST(CoulombFriction, KinematicStickThenSlipOnWall)
{
  DemSystem s;
  s.domain = open_box();
  s.materials.add(plain_material());
  const double r = 1e-3, delta = 1e-6, dt = 1e-7, mu = 0.4;
  const ContactParameters c = wall_contact(mu);
  s.walls.push_back(floor_wall(c));
  const Index p = s.particles.add_sphere(Vec3(0, 0, r - delta), r, 1e4, 0);
  const double v = 0.01; // m/s: 1e-9 m per step
  prescribe(s, p, v * Vec3::UnitX());
  kinematic_settings(s, dt);
  s.initialise();

  const double kn = c.contact_modulus * M_PI * r; // A = pi R^2, L = R
  const double ks = kn / c.stiffness_ratio;
  const double normal = kn * delta;
  const double cap = mu * normal;
  const Index steps = 4000; // 4e-6 m of travel, 5x the stick length cap/ks = 8e-7 m
  Index stick_steps = 0, slip_steps = 0;
  for (Index m = 1; m <= steps; ++m)
  {
    s.step();
    const Vec3 f = s.particles.force[p];
    ASSERT_LE(rel(f.z(), normal, normal), 1e-9) << "step " << m;
    ASSERT_LE(std::abs(f.y()), 1e-9 * cap) << "step " << m;
    const double elastic = ks * m * v * dt;
    if (elastic < cap * (1 - 1e-9))
    {
      ++stick_steps;
      ASSERT_LE(rel(f.x(), -elastic, cap), 1e-9) << "stick, step " << m;
    }
    else if (elastic > cap * (1 + 1e-9))
    {
      ++slip_steps;
      ASSERT_LE(rel(f.x(), -cap, cap), 1e-9) << "slip, step " << m;
    }
  }
  EXPECT_GT(stick_steps, 700);
  EXPECT_GT(slip_steps, 3000);
  const double slip = steps * v * dt - cap / ks;
  const EnergyLedger e = s.energy();
  EXPECT_LE(rel(e.friction, cap * slip, cap * slip), 1e-9);
  EXPECT_EQ(e.viscous, 0.0);
  // The contact still stores the capped spring: 1/2 kn delta^2 + 1/2 cap^2 / ks.
  const double stored = 0.5 * kn * delta * delta + 0.5 * cap * cap / ks;
  EXPECT_LE(rel(e.elastic_contacts, stored, stored), 1e-9);
}

// A non-rotating sphere (rotation blocked, so it cannot roll) rests on a wall under gravity tilted
// by psi: N = m g cos(psi), T = m g sin(psi). Started at the equilibrium overlap, the normal
// direction stays at rest.
//  - tan(psi) = 0.4 mu: the undamped tangential spring oscillates with a peak force 2 T = 0.8 mu N
//    < mu N, so it never slips: displacement <= 2 T / ks, no friction energy.
//  - tan(psi) = 2 mu: after a short stick phase the force saturates at mu N and the sphere
//    accelerates at exactly a = g (sin psi - mu cos psi) (leapfrog is exact for constant force):
//    tolerance 1e-8 relative (round-off of the equilibrium overlap, ~1e-10 of N).
//    Friction dissipation over a window = mu N times the distance slid, up to the half-step offset
//    between the velocity a step uses and the displacement it produces: mu N |dv| dt.
TEST(CoulombFriction, InclinedPlaneSticksBelowAndSlidesAboveMu)
{
  const double r = 1e-3, density = 1e4, g = 9.81, mu = 0.5, dt = 1e-6;
  const double m = sphere_mass(r, density);
  for (const double ratio : {0.4, 2.0})
  {
    SCOPED_TRACE(testing::Message() << "tan(psi) / mu = " << ratio);
    const double psi = std::atan(ratio * mu);
    DemSystem s;
    s.domain = open_box();
    s.materials.add(plain_material(density));
    const ContactParameters c = wall_contact(mu);
    s.walls.push_back(floor_wall(c));
    const double kn = c.contact_modulus * M_PI * r, ks = kn / c.stiffness_ratio;
    const double normal = m * g * std::cos(psi), tangential = m * g * std::sin(psi);
    const double delta = normal / kn;
    const Index p = s.particles.add_sphere(Vec3(0, 0, r - delta), r, density, 0);
    s.particles.blocked[p] = block_rotation;
    s.settings.gravity = g * Vec3(std::sin(psi), 0, -std::cos(psi));
    s.settings.time_step = dt; // sqrt(m/kn) = 1.2e-5 s
    // This test is about friction; the energy balance of a start in contact has its own test
    // (EnergyBalance.InitialOverlapsAreCounted), so the balance abort is switched off here.
    s.settings.energy_drift_tolerance = inf;
    s.initialise();
    const Vec3 x0 = s.particles.position[p];

    if (ratio < 1)
    {
      double max_dx = 0;
      s.run(3000, [&](const DemSystem &sys) {
        max_dx = std::max(max_dx, std::abs(sys.particles.position[p].x() - x0.x()));
      });
      // Leapfrog orbit of the undamped spring started at rest: amplitude x_e / cos(w dt / 2), so
      // the peak is 2 x_e (1 + (w dt)^2 / 16) at most; (w dt)^2 = ks dt^2 / m = 3.7e-3.
      const double wdt2 = ks * dt * dt / m;
      EXPECT_LE(max_dx, 2 * tangential / ks * (1 + wdt2 / 8));
      EXPECT_GE(max_dx, 1.5 * tangential / ks); // the load really cycles the spring
      EXPECT_EQ(s.energy().friction, 0.0);
      EXPECT_LE(std::abs(s.particles.position[p].z() - x0.z()), 1e-6 * delta);
    }
    else
    {
      s.run(1000);
      const double v1 = s.particles.velocity[p].x(), x1 = s.particles.position[p].x();
      const double friction1 = s.energy().friction;
      const Index window = 2000;
      s.run(window);
      const double v2 = s.particles.velocity[p].x(), x2 = s.particles.position[p].x();
      const double a = g * (std::sin(psi) - mu * std::cos(psi));
      EXPECT_LE(rel((v2 - v1) / (window * dt), a, a), 1e-8);
      // Wall force on the sphere: mu N against the motion, N normal.
      EXPECT_LE(rel(s.particles.force[p].x(), -mu * normal, mu * normal), 1e-8);
      EXPECT_LE(rel(s.particles.force[p].z(), normal, normal), 1e-8);
      const double dissipated = s.energy().friction - friction1;
      EXPECT_LE(std::abs(dissipated - mu * normal * (x2 - x1)), mu * normal * std::abs(v2 - v1) * dt * 1.01);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// 7. Hertz-Mindlin.
// ------------------------------------------------------------------------------------------------

namespace
{
  Material hertz_material()
  {
    Material m = plain_material();
    m.contact.law = ContactLaw::hertz_mindlin;
    m.contact.young_modulus = 1e9;
    m.contact.poisson_ratio = 0.3;
    m.contact.friction = 0.5;
    m.contact.damping_ratio = 0.0;
    return m;
  }
} // namespace

// j pushed into a fixed i in steps; at several overlaps it is stopped for one step and the force
// compared with F = 4/3 E* sqrt(R*) delta^{3/2}, E* = E / (2 (1 - nu^2)) (same material),
// R* = Ri Rj / (Ri + Rj) (R/2 for equal radii), delta from the current positions. At delta = 4e-6 m
// the pair is then sheared by u = 1e-9 m: F_t = 8 G* sqrt(R* delta) u, G* = G / (2 (2 - nu)),
// G = E / (2 (1 + nu)).
// Tolerances: normal 1e-9 relative (one evaluation at a known overlap; delta = Ri + Rj - d carries
// ~1e-19 m of round-off on >= 1e-6 m); tangential 1e-6 relative (the slide tilts the normal by
// u/d = 5e-7 and changes the overlap by u^2/(2d) ~ 1e-16 m, both far below 1e-6).
TEST(HertzMindlin, NormalForceAndTangentialStiffness)
{
  for (const double rj : {1e-3, 0.5e-3})
  {
    SCOPED_TRACE(testing::Message() << "Rj = " << rj);
    DemSystem s;
    s.domain = open_box();
    s.materials.add(hertz_material());
    const ContactParameters &c = s.materials[0].contact;
    PairSpec spec;
    spec.ri = 1e-3;
    spec.rj = rj;
    const Pair pr = add_pair(s, spec);
    prescribe(s, pr.i, Vec3::Zero());
    prescribe(s, pr.j, Vec3::Zero());
    const double dt = 1e-7;
    kinematic_settings(s, dt);
    s.initialise();

    const double nu = c.poisson_ratio, e = c.young_modulus;
    const double e_star = e / (2 * (1 - nu * nu));
    const double g_star = e / (2 * (1 + nu)) / (2 * (2 - nu));
    const double r_star = spec.ri * rj / (spec.ri + rj);
    if (rj == spec.ri)
    {
      EXPECT_DOUBLE_EQ(r_star, spec.ri / 2);
    }

    const double v = 0.01; // 1e-9 m per step
    double reached = 0;
    for (const double target : {1e-6, 4e-6})
    {
      const Index k = static_cast<Index>(std::llround((target - reached) / (v * dt)));
      prescribe(s, pr.j, -v * pr.normal);
      s.run(k);
      reached = target;
      prescribe(s, pr.j, Vec3::Zero());
      s.step();
      const Vec3 branch = s.particles.position[pr.j] - s.particles.position[pr.i];
      const Vec3 n = branch.normalized();
      const double delta = spec.ri + rj - branch.norm();
      ASSERT_NEAR(delta, target, 1e-12);
      const double f = 4.0 / 3.0 * e_star * std::sqrt(r_star) * std::pow(delta, 1.5);
      const Vec3 fj = s.particles.force[pr.j];
      EXPECT_LE(rel(fj.dot(n), f, f), 1e-9) << "delta = " << delta;
      EXPECT_LE((fj - fj.dot(n) * n).norm(), 1e-9 * f);
      // Elastic energy of the contact: integral of F, 8/15 E* sqrt(R*) delta^{5/2}.
      const double w = 8.0 / 15.0 * e_star * std::sqrt(r_star) * std::pow(delta, 2.5);
      EXPECT_LE(rel(s.energy().elastic_contacts, w, w), 1e-9);
    }

    // Small tangential displacement at delta = 4e-6 m.
    const double delta = 4e-6;
    const Index k = 1000;
    const double u = 1e-9;
    prescribe(s, pr.j, u / (k * dt) * Vec3::UnitY());
    s.run(k);
    prescribe(s, pr.j, Vec3::Zero());
    s.step();
    const Vec3 branch = s.particles.position[pr.j] - s.particles.position[pr.i];
    const Vec3 n = branch.normalized();
    const Vec3 fj = s.particles.force[pr.j];
    const Vec3 ft = fj - fj.dot(n) * n;
    const double kt = 8 * g_star * std::sqrt(r_star * delta);
    const double fn = 4.0 / 3.0 * e_star * std::sqrt(r_star) * std::pow(delta, 1.5);
    ASSERT_LT(kt * u, 0.1 * c.friction * fn); // well inside the Coulomb cone
    const Vec3 expected = -kt * u * tangent_part(Vec3::UnitY(), n);
    EXPECT_LE(rel(ft, expected, expected.norm()), 1e-6);
  }
}
