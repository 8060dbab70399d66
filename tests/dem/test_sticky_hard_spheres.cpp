// Percus-Yevick relations of sticky hard spheres (dem/sample/sticky_hard_spheres.h) against the reference
// values of docs/physics.md §1.4 and against their own inverse.

#include "dem/sample/sticky_hard_spheres.h"
#include "dem/common/types.h"

#include <gtest/gtest.h>

#include <string>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

using namespace anticrack::dem;

// docs/physics.md §1.4 quotes z = 2.74 at (phi, tau) = (0.3, 0.2) and z = 5.84 at (0.5, 0.1), to the
// printed digits: tolerance half a unit of the last digit.
TEST(StickyHardSpheres, PercusYevickCoordinationMatchesReferenceValues)
{
  EXPECT_NEAR(shs::percus_yevick_coordination(0.3, 0.2), 2.74, 0.005);
  EXPECT_NEAR(shs::percus_yevick_coordination(0.5, 0.1), 5.84, 0.005);
  // The root really solves the quadratic (round-off).
  const double phi = 0.4, tau = 0.1, lambda = shs::percus_yevick_lambda(phi, tau);
  const double residual = phi / 12 * lambda * lambda - (tau + phi / (1 - phi)) * lambda +
                          (1 + phi / 2) / ((1 - phi) * (1 - phi));
  EXPECT_NEAR(residual, 0.0, 1e-12);
  // Stickier spheres (smaller tau) touch more.
  EXPECT_GT(shs::percus_yevick_coordination(0.3, 0.1), shs::percus_yevick_coordination(0.3, 0.2));
}

// tau_min(phi) from its closed form at two points (hand-evaluated: phi = 0.3 gives
// (1.26 - 1.2 - 1)/(12 (0.18 - 0.3 - 1)) = 0.0699405; phi = 0.5 gives (3.5 - 2 - 1)/(12 (0.5 - 0.5 - 1))
// = -0.0416667), and requests below it are refused with a message naming tau and tau_min.
TEST(StickyHardSpheres, MinimumStickinessAndRefusal)
{
  EXPECT_NEAR(shs::minimum_stickiness(0.3), 0.94 / 13.44, 1e-12);
  EXPECT_NEAR(shs::minimum_stickiness(0.5), -0.5 / 12, 1e-12);
  try
  {
    shs::percus_yevick_lambda(0.3, 0.05);
    FAIL() << "tau below tau_min accepted";
  }
  catch (const SetupError &e)
  {
    EXPECT_NE(std::string(e.what()).find("tau_min"), std::string::npos) << e.what();
  }
  EXPECT_THROW(shs::percus_yevick_lambda(1.2, 0.2), SetupError);
}

// Solving for tau inverts the forward relation (round-off), and a z beyond what tau_min allows is
// refused.
TEST(StickyHardSpheres, StickinessForCoordinationInvertsThePercusYevickRelation)
{
  for (const double phi : {0.2, 0.3, 0.4, 0.5})
    for (const double tau : {0.12, 0.2, 0.5, 1.0})
    {
      if (tau < shs::minimum_stickiness(phi))
        continue;
      const double z = shs::percus_yevick_coordination(phi, tau);
      EXPECT_NEAR(shs::stickiness_for_coordination(phi, z), tau, 1e-10 * tau) << "phi " << phi << " tau " << tau;
    }
  const double z_max = shs::percus_yevick_coordination(0.3, shs::minimum_stickiness(0.3));
  EXPECT_THROW(shs::stickiness_for_coordination(0.3, 1.5 * z_max), SetupError);
}

// ------------------------------------------------------------------------------------------------
// Monte Carlo sampler

namespace
{
  shs::SamplerReport sample(DemSystem &s, double phi, double tau, Index sweeps, double delta = 0.03,
                            std::uint64_t seed = 1, Index count = 500, const Vec3 &aspect_ratios = Vec3::Ones())
  {
    s.materials.add(Material{});
    shs::SamplerSpec spec;
    spec.particle_count = count;
    spec.volume_fraction = phi;
    spec.stickiness = tau;
    spec.sweeps = sweeps;
    spec.well_width = delta;
    spec.radius = 1e-3;
    spec.seed = seed;
    spec.aspect_ratios = aspect_ratios;
    spec.require_percolation = false; // short runs too; the tests check report.percolating themselves
    spec.equilibration_tolerance = 0; // and short of equilibrium: the tests say what they compare
    return shs::sample_sticky_hard_spheres(s, spec);
  }

  /// No two spheres of diameter `diameter` overlap, through any periodic image (round-off allowed).
  void expect_hard_cores(const DemSystem &s, double diameter)
  {
    for (Index i = 0; i < s.particles.size(); ++i)
      for (Index j = i + 1; j < s.particles.size(); ++j)
      {
        const Vec3 d = s.particles.position[j] - s.particles.position[i];
        const Vec3 image = d + s.domain.minimum_image_shift(s.particles.position[i], s.particles.position[j]);
        ASSERT_GE(image.norm(), diameter * (1 - 1e-12)) << i << " " << j;
      }
  }

  /// Six slabs along each axis of the box `lengths` each hold their share of 600 spheres within 25.
  void expect_even_slabs(const DemSystem &s, const Vec3 &lengths, const std::string &what)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      std::array<int, 6> slab{};
      for (Index p = 0; p < s.particles.size(); ++p)
        ++slab[std::min(5, static_cast<int>(6 * s.particles.position[p][axis] / lengths[axis]))];
      for (int k = 0; k < 6; ++k)
        EXPECT_NEAR(slab[k], 100, 25) << what << ", axis " << axis << ", slab " << k;
    }
  }
} // namespace

// (phi, tau) = (0.3, 0.2): the sampled coordination number within 15 % of Percus-Yevick (PY is an
// approximation), phi exact, no hard-core overlap, a percolating network, and the drawn adhesive
// contacts become the bonds (gap tolerance 2 delta radii, restricted to the drawn pairs). The
// unequilibrated start (an FCC lattice, z = 0) fails the first check.
TEST(StickyHardSpheresSampler, CoordinationNearPercusYevickAtPhi03Tau02)
{
  DemSystem s;
  const shs::SamplerReport r = sample(s, 0.3, 0.2, 3000);
  EXPECT_NEAR(r.volume_fraction, 0.3, 1e-12);
  EXPECT_NEAR(r.coordination / r.percus_yevick_coordination, 1.0, 0.15)
    << "z = " << r.coordination << ", PY " << r.percus_yevick_coordination;
  EXPECT_TRUE(r.percolating);
  ASSERT_EQ(s.particles.size(), 500);
  // Hard cores respected: nearest centre distance >= 2R (round-off).
  expect_hard_cores(s, 2e-3);
  s.materials[0].bond.enabled = true;
  BondingRule rule;
  rule.gap_tolerance = 2 * 0.03 * (1 + 1e-9);
  rule.only_pairs.insert(r.bonded_pairs.begin(), r.bonded_pairs.end());
  EXPECT_EQ(s.bond_touching_pairs(rule), r.contacts);
  EXPECT_GT(r.well_pairs, r.contacts); // some close pairs are plain hard-sphere neighbours
}

// (0.4, 0.1), denser and stickier, equilibrates slowly: after 1e4 sweeps z is 5 % below PY (4.42 vs
// 4.66) and still creeping up; the test keeps the 15 % band.
TEST(StickyHardSpheresSampler, CoordinationNearPercusYevickAtPhi04Tau01)
{
  DemSystem s;
  const shs::SamplerReport r = sample(s, 0.4, 0.1, 10000);
  EXPECT_NEAR(r.coordination / r.percus_yevick_coordination, 1.0, 0.15)
    << "z = " << r.coordination << ", PY " << r.percus_yevick_coordination;
  ASSERT_FALSE(r.coordination_history.empty());
  EXPECT_GT(r.coordination_history.back(), r.coordination_history.front()) << "contacts should form from the lattice start";
}

// An independent check that does not rely on PY: at low density the adhesive contacts per sphere
// are z = rho * (sticky part of the well integral) = 2 phi / tau exactly to first order in phi (the
// hard-sphere contact value adds O(phi): PY gives 0.108 at phi = 0.05, tau = 1). Counting every pair
// in the well instead would give 0.137 (+ 8 phi ((1+delta)^3 - 1)); tolerance 10 % of 0.1 around PY.
// One sample of 1000 spheres holds about 54 contacts, so its z scatters by 2 sqrt(54) / 1000 = 0.015
// (measured over seeds 1-8: 0.084-0.130, mean 0.108): the mean over 16 seeds has a standard error of
// 0.004, which puts the 0.01 band at 2.7 of them and 0.137 at 7.
TEST(StickyHardSpheresSampler, DiluteLimitIsBaxters)
{
  const int seeds = 16;
  double mean_z = 0;
  for (int seed = 1; seed <= seeds; ++seed)
  {
    DemSystem s; // a dilute fluid of small clusters: not percolating
    mean_z += sample(s, 0.05, 1.0, 2000, 0.03, static_cast<std::uint64_t>(seed), 1000).coordination / seeds;
  }
  EXPECT_NEAR(mean_z, shs::percus_yevick_coordination(0.05, 1.0), 0.01)
    << "mean z over " << seeds << " seeds = " << mean_z << " (2 phi / tau = 0.1)";
}

// Another check that does not rely on PY: the square-well representation must
// reach Baxter's limit, i.e. z must not depend on the well width once it is narrow. The narrower
// well equilibrates more slowly (its coordination history levels off after ~1e4 sweeps; at 6000
// sweeps it is still ~10 % low), so both run 20 000 sweeps: 0.02 vs 0.03 diameters give 2.696 vs
// 2.700 (seed 1) and 2.840 vs 2.788 (seed 2); tolerance 5 %, about the sampling noise of 500
// spheres. A wrong contact weight (e.g. exp(eps/kT) = 1/(12 tau delta) without the exact
// (1+delta)^3 - 1) would separate them.
TEST(StickyHardSpheresSampler, NarrowWellReachesBaxterLimit)
{
  DemSystem a, b;
  const double za = sample(a, 0.3, 0.2, 20000, 0.02).coordination;
  const double zb = sample(b, 0.3, 0.2, 20000, 0.03).coordination;
  EXPECT_NEAR(za / zb, 1.0, 0.05) << "z(delta = 0.02) = " << za << ", z(delta = 0.03) = " << zb;
}

// Same seed, same sample (bit for bit); another seed, another sample; refusals with the reason.
TEST(StickyHardSpheresSampler, ReproducibleBySeedAndRefusesBadRequests)
{
  DemSystem a, b, c;
  sample(a, 0.3, 0.2, 50, 0.03, 7);
  sample(b, 0.3, 0.2, 50, 0.03, 7);
  sample(c, 0.3, 0.2, 50, 0.03, 8);
  EXPECT_EQ(a.particles.position, b.particles.position);
  EXPECT_NE(a.particles.position, c.particles.position);
  DemSystem d;
  EXPECT_THROW(sample(d, 0.3, 0.05, 10), SetupError); // tau below tau_min(0.3) = 0.07
  DemSystem e;
  EXPECT_THROW(sample(e, 0.7, 0.2, 10), SetupError); // phi above the fluid range
}

// ------------------------------------------------------------------------------------------------
// Cluster moves (SamplerSpec::cluster_move_fraction)

namespace
{
  shs::SamplerReport sample_with_clusters(DemSystem &s, Index n, double phi, double tau, Index sweeps, double delta,
                                          double fraction, std::uint64_t seed)
  {
    s.materials.add(Material{});
    shs::SamplerSpec spec;
    spec.particle_count = n;
    spec.volume_fraction = phi;
    spec.stickiness = tau;
    spec.sweeps = sweeps;
    spec.well_width = delta;
    spec.radius = 1e-3;
    spec.seed = seed;
    spec.cluster_move_fraction = fraction;
    spec.require_percolation = false; // these runs study the fluid's equilibrium, dilute ones included
    spec.equilibration_tolerance = 0; // and how fast it is reached
    return shs::sample_sticky_hard_spheres(s, spec);
  }
} // namespace

// Cluster moves must not change the equilibrium. At (phi, tau) = (0.3, 0.2) with a wide well
// (delta = 0.1, which levels off within ~1000 sweeps; with delta = 0.03 neither run would be in
// equilibrium after a few thousand sweeps and the comparison would measure equilibration speed),
// N = 256: the well coordination number (2 well pairs / N) averaged over the coordination history
// from sweep 1100 to 3000, for 3 seeds with and 3 without cluster moves (20 % of the trials).
// Measured over 10 seeds each: 3.587 (sd 0.048) without, 3.572 (sd 0.050) with. Tolerance: 3
// standard errors of the difference of two 3-seed means, 3 * 0.05 * sqrt(2/3) = 0.12 (3.4 %).
// A cluster move that linked well pairs with probability 0.5 instead of 1 - exp(-eps/kT) fails
// this check (2.85); one that linked every well pair without refusing new well pairs passes it at
// this fraction (the single-sphere moves undo most of its bias) and is caught by the next test.
TEST(StickyHardSpheresSampler, ClusterMovesKeepTheEquilibrium)
{
  const auto run = [](double fraction, std::uint64_t seed, double &bonded) {
    DemSystem s;
    const shs::SamplerReport r = sample_with_clusters(s, 256, 0.3, 0.2, 3000, 0.1, fraction, seed);
    EXPECT_EQ(r.coordination_history.size(), 30u);
    bonded = r.coordination;
    return std::accumulate(r.coordination_history.begin() + 10, r.coordination_history.end(), 0.0) / 20;
  };
  double mean[2] = {0, 0}, bonded_mean[2] = {0, 0}, square[2] = {0, 0};
  const double fractions[2] = {0.0, 0.2};
  for (int k = 0; k < 2; ++k)
    for (const std::uint64_t seed : {11u, 12u, 13u})
    {
      double bonded = 0;
      const double z = run(fractions[k], seed, bonded);
      mean[k] += z / 3;
      square[k] += z * z / 3;
      bonded_mean[k] += bonded / 3;
    }
  const auto sd = [&](int k) { return std::sqrt(std::max(0.0, (square[k] - mean[k] * mean[k]) * 3 / 2)); };
  std::printf("[ measured ] well coordination %.4f (sd %.4f) without cluster moves, %.4f (sd %.4f) with; "
              "bonded z %.4f without, %.4f with\n",
              mean[0], sd(0), mean[1], sd(1), bonded_mean[0], bonded_mean[1]);
  EXPECT_NEAR(mean[1], mean[0], 0.12);
}

// The cluster moves' own equilibrium, with 95 % of the trials cluster moves: in the dilute limit
// (phi = 0.05, tau = 1, delta = 0.03, N = 1000) the mean number of partners in the well is
// z_PY / (1 - exp(-eps/kT)) = 0.108 / 0.7295 = 0.148 (each well pair is a contact with probability
// 1 - exp(-eps/kT); PY is within ~1 % of exact this dilute). Measured: 0.146 and 0.152 (2 seeds,
// history averaged over sweeps 600-2000), 0.150 and 0.142 without cluster moves; run-to-run sd
// 0.0046, so the 2-seed mean has a standard error of 0.0033: tolerance 3 of them, 0.01. Broken
// cluster moves are far off: links drawn with probability 0.5 give 0.087, every well pair linked
// without refusing new well pairs 1.92.
TEST(StickyHardSpheresSampler, ClusterMovesAloneReachTheDiluteLimit)
{
  const double phi = 0.05, tau = 1.0, delta = 0.03;
  const double contact_weight = 1 + 1 / (4 * tau * (std::pow(1 + delta, 3) - 1));
  const double expected = shs::percus_yevick_coordination(phi, tau) / (1 - 1 / contact_weight);
  double mean = 0;
  for (const std::uint64_t seed : {1u, 2u})
  {
    DemSystem s;
    const shs::SamplerReport r = sample_with_clusters(s, 1000, phi, tau, 2000, delta, 0.95, seed);
    ASSERT_EQ(r.coordination_history.size(), 20u);
    mean += std::accumulate(r.coordination_history.begin() + 5, r.coordination_history.end(), 0.0) / 15 / 2;
    EXPECT_GT(r.cluster_acceptance, 0.5); // small clusters in a dilute fluid: most moves go through
  }
  std::printf("[ measured ] dilute well coordination with cluster moves %.4f, expected %.4f\n", mean, expected);
  EXPECT_NEAR(mean, expected, 0.01);
}

// Invariants with cluster moves: no hard-core overlap (gap >= 0 for every pair), some cluster moves
// accepted, the drawn contacts inside the well (they become bonds with the usual gap tolerance),
// reproducible by seed, and refusals of a fraction outside [0, 1).
TEST(StickyHardSpheresSampler, ClusterMovesKeepHardCoresAndAreReproducible)
{
  DemSystem s, again;
  const shs::SamplerReport r = sample_with_clusters(s, 256, 0.3, 0.2, 600, 0.03, 0.3, 5);
  const shs::SamplerReport r2 = sample_with_clusters(again, 256, 0.3, 0.2, 600, 0.03, 0.3, 5);
  EXPECT_EQ(s.particles.position, again.particles.position);
  EXPECT_EQ(r.bonded_pairs, r2.bonded_pairs);
  EXPECT_GT(r.cluster_acceptance, 0.0);
  EXPECT_LE(r.cluster_acceptance, 1.0);
  EXPECT_NEAR(r.volume_fraction, 0.3, 1e-12);
  for (Index i = 0; i < s.particles.size(); ++i)
    for (Index j = i + 1; j < s.particles.size(); ++j)
    {
      const Vec3 d = s.particles.position[j] - s.particles.position[i];
      const Vec3 image = d + s.domain.minimum_image_shift(s.particles.position[i], s.particles.position[j]);
      ASSERT_GE(image.norm() - 2e-3, -1e-12 * 2e-3) << i << " " << j;
    }
  s.materials[0].bond.enabled = true;
  BondingRule rule;
  rule.gap_tolerance = 2 * 0.03 * (1 + 1e-9);
  rule.only_pairs.insert(r.bonded_pairs.begin(), r.bonded_pairs.end());
  EXPECT_EQ(s.bond_touching_pairs(rule), r.contacts);
  DemSystem bad1, bad2;
  EXPECT_THROW(sample_with_clusters(bad1, 64, 0.3, 0.2, 10, 0.03, 1.0, 1), SetupError);
  EXPECT_THROW(sample_with_clusters(bad2, 64, 0.3, 0.2, 10, 0.03, -0.1, 1), SetupError);
}

// Cluster moves in the dense, very sticky state (phi, tau) = (0.4, 0.1), N = 500, delta = 0.03, 6000
// sweeps: the sample stays within the 15 % band of Percus-Yevick that the single-move test uses
// (measured: z = 4.21 without, 4.14 with 20 % cluster moves; PY 4.66), and some cluster moves are
// accepted (measured ~1e-3: the bonded network spans the box early and spanning clusters never
// move; the header discusses why they do not speed this state up).
TEST(StickyHardSpheresSampler, ClusterMovesKeepTheDenseStickyStateNearPercusYevick)
{
  DemSystem s;
  const shs::SamplerReport r = sample_with_clusters(s, 500, 0.4, 0.1, 6000, 0.03, 0.2, 1);
  EXPECT_NEAR(r.coordination / r.percus_yevick_coordination, 1.0, 0.15);
  EXPECT_GT(r.cluster_acceptance, 0.0);
  EXPECT_TRUE(r.percolating);
}

// A sample whose bonded network does not span the box carries no load (Ritter et al. 2020): refused, with the
// reason and the way out. phi = 0.1, tau = 1 is far below percolation (z ~ 0.2).
// A count that is not 4 m^3 (600: the smallest FCC lattice with enough sites has 864) must still
// fill the whole box, at the start and after the sweeps: filling the first 600 sites left the top
// third of the box empty, and under strong stickiness the sweeps kept the gradient (at N = 4096 the
// bonds then did not reach the actuator). Six slabs along each axis, each within 25 % of its share
// (100 spheres: Poisson's standard deviation is 10, and a hard-sphere fluid at phi = 0.3
// fluctuates less).
TEST(StickyHardSpheresSampler, AnyCountFillsTheWholeBox)
{
  for (const Index sweeps : {Index{1}, Index{300}})
  {
    DemSystem s;
    const shs::SamplerReport r = sample(s, 0.3, 0.2, sweeps, 0.03, 1, 600);
    ASSERT_EQ(s.particles.size(), 600);
    expect_even_slabs(s, r.box_lengths, "sweeps " + std::to_string(sweeps));
  }
}

// A layer, not a cube: a box of edges 3 : 2 : 1 (a thin direction, as a weak layer between slab and
// substratum) holds the same fluid. The edges keep their ratio and their product is N v / phi
// (exact), the coordination number is Percus-Yevick's within the cube's 15 % (the fluid does not
// know the box's shape), no hard core overlaps (through every periodic image), and six slabs along
// each axis hold their share within 25 % (AnyCountFillsTheWholeBox's bound). A cube's sample is
// the same bit for bit as before boxes (regression.shs_sample).
TEST(StickyHardSpheresSampler, BoxOfAnyAspectRatioHoldsTheSameFluid)
{
  DemSystem s;
  const shs::SamplerReport r = sample(s, 0.3, 0.2, 3000, 0.03, 1, 600, Vec3(3, 2, 1));
  const Vec3 L = r.box_lengths;
  EXPECT_NEAR(L[0] / L[2], 3, 1e-12);
  EXPECT_NEAR(L[1] / L[2], 2, 1e-12);
  EXPECT_NEAR(r.volume_fraction, 0.3, 1e-12);
  EXPECT_NEAR(600 * 4.0 / 3.0 * M_PI * 1e-9 / L.prod(), 0.3, 1e-12);
  EXPECT_EQ(s.domain.upper, L);
  EXPECT_NEAR(r.coordination / r.percus_yevick_coordination, 1.0, 0.15)
    << "z = " << r.coordination << ", PY " << r.percus_yevick_coordination;
  EXPECT_TRUE(r.percolating);
  expect_hard_cores(s, 2e-3);
  expect_even_slabs(s, L, "box 3 : 2 : 1");
  DemSystem refused;
  EXPECT_THROW(sample(refused, 0.3, 0.2, 10, 0.03, 1, 600, Vec3(1, 0, 1)), SetupError);
}

// A layer's box at high phi (the pits' dense weak layers, coupling/profile_specimen.h): 469 spheres at
// phi = 0.49 in a 2 : 2 : 1 box. Cells about cubic would give 1024 sites, whose neighbours are 0.88
// diameters apart, and the start would overlap; the sampler takes a lattice of 469 sites or a few
// more instead. No two spheres overlap after one sweep (the start) or after 400, and the
// coordination history never counts an overlap (it would be negative: -1 partners per overlap).
TEST(StickyHardSpheresSampler, DenseFlatBoxStartsWithoutOverlaps)
{
  for (const Index sweeps : {Index(1), Index(400)})
  {
    DemSystem s;
    const shs::SamplerReport r = sample(s, 0.49, 0.8, sweeps, 0.03, 1, 469, Vec3(2, 2, 1));
    expect_hard_cores(s, 2e-3);
    for (const double z : r.coordination_history)
      EXPECT_GE(z, 0) << sweeps << " sweeps";
  }
}

TEST(StickyHardSpheresSampler, NonPercolatingSampleIsRefused)
{
  DemSystem s;
  s.materials.add(Material{});
  shs::SamplerSpec spec;
  spec.particle_count = 300;
  spec.volume_fraction = 0.1;
  spec.stickiness = 1.0;
  spec.sweeps = 200;
  spec.radius = 1e-3;
  spec.equilibration_tolerance = 0; // a dilute fluid that never percolates: only percolation is checked
  try
  {
    shs::sample_sticky_hard_spheres(s, spec);
    FAIL() << "a non-percolating sample was accepted";
  }
  catch (const SetupError &e)
  {
    const std::string message = e.what();
    EXPECT_NE(message.find("does not percolate"), std::string::npos) << message;
    EXPECT_NE(message.find("phi = 0.1"), std::string::npos) << message;
  }
  EXPECT_EQ(s.particles.size(), 0) << "nothing is appended to a refused system";
  spec.require_percolation = false;
  const shs::SamplerReport r = shs::sample_sticky_hard_spheres(s, spec);
  EXPECT_FALSE(r.percolating);
}

// A sample that has not levelled off is refused. (phi, z) = (0.3, 2.9), N = 1024 from the unbonded
// lattice: after 2000 sweeps its well coordination still rises by about 5 % from the third to the
// last quarter (5.4 % in a 2 x 2 x 1 box), beyond 1.5 % + 1.5 x its scatter at equilibrium
// (1.7 %); after 20 000 it has levelled off (from 20 000 to 100 000 sweeps it stays within
// 3.11-3.25, and the rise is within its scatter). The refusal names the entry to raise and nothing
// is appended to the system; fewer than 400 sweeps cannot be judged.
namespace
{
  /// (phi, z) = (0.3, 2.9), N = 1024, from the unbonded lattice: the equilibration tests' sample.
  shs::SamplerSpec spec_for(Index sweeps, double extension_limit = 1)
  {
    shs::SamplerSpec spec;
    spec.particle_count = 1024;
    spec.volume_fraction = 0.3;
    spec.stickiness = 0;
    spec.target_coordination = 2.9;
    spec.sweeps = sweeps;
    spec.sweep_extension_limit = extension_limit;
    spec.radius = 1e-3;
    return spec;
  }
} // namespace

TEST(StickyHardSpheresSampler, SampleThatHasNotLevelledOffIsRefused)
{
  DemSystem short_run;
  short_run.materials.add(Material{});
  try
  {
    shs::sample_sticky_hard_spheres(short_run, spec_for(2000));
    FAIL() << "a sample 2000 sweeps from its lattice start was accepted";
  }
  catch (const SetupError &e)
  {
    const std::string message = e.what();
    EXPECT_NE(message.find("has not levelled off after 2000 sweeps"), std::string::npos) << message;
    EXPECT_NE(message.find("DEM/Sample/Sweeps"), std::string::npos) << message;
  }
  EXPECT_EQ(short_run.particles.size(), 0) << "nothing is appended to a refused system";

  DemSystem long_run;
  long_run.materials.add(Material{});
  const shs::SamplerReport r = shs::sample_sticky_hard_spheres(long_run, spec_for(20000));
  std::printf("[ measured ] coordination rise over the last half after 20 000 sweeps: %.4f (scatter %.4f), z = %.3f\n",
              r.coordination_rise, r.coordination_rise_error, r.coordination);
  EXPECT_EQ(long_run.particles.size(), 1024);
  EXPECT_NEAR(r.coordination_rise_error, 0.54 / 32, 1e-12); // the equilibrium scatter at N = 1024
  EXPECT_LE(r.coordination_rise, 0.015 + 1.5 * r.coordination_rise_error);

  DemSystem too_few;
  too_few.materials.add(Material{});
  EXPECT_THROW(shs::sample_sticky_hard_spheres(too_few, spec_for(300)), SetupError); // cannot be judged
}

// The criterion, not the count, ends the sampling (SamplerSpec::sweep_extension_limit). The sample
// refused above after 2000 sweeps runs on, 2000 sweeps at a time, and stops at the first check that
// finds it levelled off: after more than 2000 sweeps and, since the fixed-count run levels off by
// 20 000, by 20 000 at the latest. Judged strictly (a tolerance of 1e-6, the scatter alone) with a
// limit of 1.5, it gets one shortened extension (3000 sweeps) and is refused, the message naming
// both entries. A sample that levels off within its sweeps is the same to the bit with a limit: the
// extension never starts.
TEST(StickyHardSpheresSampler, SampleRunsOnUntilLevelledOffUpToItsLimit)
{
  DemSystem extended;
  extended.materials.add(Material{});
  const shs::SamplerReport r = shs::sample_sticky_hard_spheres(extended, spec_for(2000, 10));
  std::printf("[ measured ] levelled off after %lld sweeps (from 2000): rise %.4f (scatter %.4f), z = %.3f\n",
              static_cast<long long>(r.sweeps), r.coordination_rise, r.coordination_rise_error, r.coordination);
  EXPECT_GT(r.sweeps, 2000);
  EXPECT_LE(r.sweeps, 20000);
  EXPECT_EQ(r.sweeps % 2000, 0);
  EXPECT_EQ(r.coordination_history.size(), static_cast<std::size_t>(r.sweeps / 100));
  EXPECT_LE(r.coordination_rise, 0.015 + 1.5 * r.coordination_rise_error);
  EXPECT_EQ(extended.particles.size(), 1024);

  DemSystem once;
  once.materials.add(Material{});
  try
  {
    shs::SamplerSpec strict = spec_for(2000, 1.5);
    strict.equilibration_tolerance = 1e-6;
    shs::sample_sticky_hard_spheres(once, strict);
    FAIL() << "a sample 3000 sweeps from its lattice start passed the strict check";
  }
  catch (const SetupError &e)
  {
    const std::string message = e.what();
    EXPECT_NE(message.find("has not levelled off after 3000 sweeps (DEM/Sample/Sweeps, extended up to "
                           "DEM/Sample/Sweep extension limit)"),
              std::string::npos)
      << message;
  }
  EXPECT_EQ(once.particles.size(), 0) << "nothing is appended to a refused system";

  DemSystem fixed, with_limit;
  fixed.materials.add(Material{});
  with_limit.materials.add(Material{});
  const shs::SamplerReport a = shs::sample_sticky_hard_spheres(fixed, spec_for(20000, 1));
  const shs::SamplerReport b = shs::sample_sticky_hard_spheres(with_limit, spec_for(20000, 3));
  EXPECT_EQ(a.sweeps, 20000);
  EXPECT_EQ(b.sweeps, 20000);
  ASSERT_EQ(fixed.particles.size(), with_limit.particles.size());
  for (Index i = 0; i < fixed.particles.size(); ++i)
    ASSERT_EQ(fixed.particles.position[i], with_limit.particles.position[i]) << "sphere " << i;
  EXPECT_THROW(shs::sample_sticky_hard_spheres(once, spec_for(2000, 0.5)), SetupError);
}
