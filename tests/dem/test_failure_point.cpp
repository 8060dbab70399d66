// Failure-point analysis (dem/lab/failure_point.h) on synthetic histories with known answers.

#include "dem/lab/failure_point.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

using namespace anticrack::dem;

namespace
{
  constexpr double pi = 3.14159265358979323846;

  Mat3 uniaxial_zz(double sigma_zz)
  {
    Mat3 s = Mat3::Zero();
    s(2, 2) = sigma_zz;
    return s;
  }

  /// n samples at dt = 0.01 s; stress uniaxial compression with q = q_of(i); base sigma = q, tau = -q/2;
  /// clump velocity v_of(i) along -z; strain 1e-3 i.
  TestHistory synthetic(Index n, const std::function<double(Index)> &q_of,
                        const std::function<double(Index)> &v_of)
  {
    TestHistory h;
    for (Index i = 0; i < n; ++i)
    {
      h.time.push_back(0.01 * i);
      h.stress.push_back(uniaxial_zz(-q_of(i)));
      h.clump_velocity.push_back(Vec3(0, 0, -v_of(i)));
      h.clump_displacement.push_back(Vec3(0, 0, -1e-4 * i));
      h.strain.push_back(1e-3 * i);
      h.base_normal_stress.push_back(q_of(i));
      h.base_shear_stress.push_back(-0.5 * q_of(i));
    }
    return h;
  }

  /// Runs f, expects std::invalid_argument whose message contains `needle`.
  void expect_invalid(const std::function<void()> &f, const std::string &needle)
  {
    try
    {
      f();
      ADD_FAILURE() << "no exception; expected one mentioning \"" << needle << "\"";
    }
    catch (const std::invalid_argument &e)
    {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << "message: " << e.what();
    }
  }
} // namespace

TEST(FailurePointInvariants, UniaxialPureShearHydrostatic)
{
  const double S = 2.5e3;
  auto inv = stress_invariants(uniaxial_zz(-S)); // uniaxial compression
  EXPECT_NEAR(inv.p, S / 3, 1e-12 * S);
  EXPECT_NEAR(inv.q, S, 1e-12 * S);

  inv = stress_invariants(uniaxial_zz(S)); // uniaxial tension: p negative, same q
  EXPECT_NEAR(inv.p, -S / 3, 1e-12 * S);
  EXPECT_NEAR(inv.q, S, 1e-12 * S);

  Mat3 shear = Mat3::Zero();
  shear(0, 2) = shear(2, 0) = S; // pure shear: q = sqrt(3) tau
  inv = stress_invariants(shear);
  EXPECT_NEAR(inv.p, 0, 1e-12 * S);
  EXPECT_NEAR(inv.q, std::sqrt(3.0) * S, 1e-12 * S);

  inv = stress_invariants(-S * Mat3::Identity()); // hydrostatic compression
  EXPECT_NEAR(inv.p, S, 1e-12 * S);
  EXPECT_NEAR(inv.q, 0, 1e-12 * S);

  // q is unchanged by adding a pressure.
  inv = stress_invariants(uniaxial_zz(-S) - 7 * S * Mat3::Identity());
  EXPECT_NEAR(inv.p, S / 3 + 7 * S, 1e-12 * S);
  EXPECT_NEAR(inv.q, S, 1e-11 * S);
}

TEST(FailureKineticWindow, PeakInsideWindowAndSpikeMovesAnswer)
{
  // q rises linearly to a peak at i = 50, then falls; the clump runs away from index `spike` on.
  const auto q = [](Index i) { return i <= 50 ? 100.0 * i : 5000.0 - 20.0 * (i - 50); };
  for (const Index spike : {70, 40, 30})
  {
    const auto v = [spike](Index i) { return i < spike ? 1e-3 : 1.0; };
    const TestHistory h = synthetic(100, q, v);
    const FailurePoint fp = failure_by_kinetic_energy_window(h);
    const Index expected = std::min<Index>(50, spike - 1);
    EXPECT_EQ(fp.index, expected) << "spike at " << spike;
    EXPECT_EQ(fp.window_begin, 0);
    EXPECT_EQ(fp.window_end, spike - 1);
    EXPECT_DOUBLE_EQ(fp.time, 0.01 * expected);
    EXPECT_NEAR(fp.q, q(expected), 1e-9);
    EXPECT_NEAR(fp.p, q(expected) / 3, 1e-9);
    EXPECT_DOUBLE_EQ(fp.stress(2, 2), -q(expected));
    ASSERT_TRUE(fp.sigma.has_value());
    ASSERT_TRUE(fp.tau.has_value());
    EXPECT_DOUBLE_EQ(*fp.sigma, q(expected));
    EXPECT_DOUBLE_EQ(*fp.tau, -0.5 * q(expected));
  }
}

TEST(FailureKineticWindow, EarlyTransientDoesNotEndWindow)
{
  // q rises linearly throughout; a transient at 5..7 (E_k* = 0.64) and the run-away from 70 on.
  const auto q = [](Index i) { return 10.0 * i + 1; };
  const auto v = [](Index i) { return (i >= 5 && i <= 7) ? 0.8 : (i < 70 ? 1e-3 : 1.0); };
  TestHistory h = synthetic(100, q, v);
  FailurePoint fp = failure_by_kinetic_energy_window(h);
  EXPECT_EQ(fp.index, 69);
  EXPECT_EQ(fp.window_end, 69);

  // The transient's own samples are not candidates: put a q spike inside the transient.
  h.stress[6] = uniaxial_zz(-1e6);
  fp = failure_by_kinetic_energy_window(h);
  EXPECT_EQ(fp.index, 69);
  // ... but a q spike in a quiet sample of the window is.
  h.stress[10] = uniaxial_zz(-1e6);
  fp = failure_by_kinetic_energy_window(h);
  EXPECT_EQ(fp.index, 10);
  // Samples after the run-away (quiet again after a maximum) are outside the window.
  h.stress[10] = uniaxial_zz(-q(10));
  h.clump_velocity[90] = Vec3(0, 0, -1e-3);
  h.stress[90] = uniaxial_zz(-1e7);
  fp = failure_by_kinetic_energy_window(h);
  EXPECT_EQ(fp.index, 69);
}

TEST(FailureKineticWindow, ZetaSetsTheWindowEndOnAGradualRunAway)
{
  // v = (i - 60)/39 after i = 60: E_k* = ((i-60)/39)^2 < zeta  <=>  i - 60 < 39 sqrt(zeta).
  const auto q = [](Index i) { return 1.0 + i; };
  const auto v = [](Index i) { return i <= 60 ? 0.0 : (i - 60) / 39.0; };
  const TestHistory h = synthetic(100, q, v);
  EXPECT_EQ(failure_by_kinetic_energy_window(h, 0.3).index, 60 + 21); // 39 sqrt(0.3) = 21.36
  EXPECT_EQ(failure_by_kinetic_energy_window(h, 0.1).index, 60 + 12); // 39 sqrt(0.1) = 12.33
}

TEST(FailurePeak, EachMeasure)
{
  const auto q = [](Index i) { return i <= 30 ? 10.0 * i : 300.0 - 5.0 * (i - 30); };
  TestHistory h = synthetic(60, q, [](Index) { return 1.0; });
  EXPECT_EQ(failure_by_peak(h, Measure::von_mises).index, 30);
  // Base series with different peaks: sigma peaks at 12, |tau| at 44 (negative tau).
  h.base_normal_stress[12] = 1e6;
  h.base_shear_stress[44] = -1e6;
  EXPECT_EQ(failure_by_peak(h, Measure::base_normal).index, 12);
  const FailurePoint fp = failure_by_peak(h, Measure::base_shear);
  EXPECT_EQ(fp.index, 44);
  EXPECT_DOUBLE_EQ(*fp.tau, -1e6);
  EXPECT_EQ(fp.window_end, 59);
  h.base_shear_stress.clear();
  expect_invalid([&] { failure_by_peak(h, Measure::base_shear); }, "base_shear_stress");
}

TEST(FailureSecantModulus, PiecewiseLinearCurve)
{
  // Slope E1 up to eps = 0.05, then E2 up to the peak at eps = 0.08, then a drop. Samples every 0.0025.
  const double E1 = 1e6, E2 = 0.2e6;
  std::vector<double> eps, sig;
  for (int i = 0; i <= 48; ++i)
  {
    const double e = 0.0025 * i;
    eps.push_back(e);
    sig.push_back(i <= 20 ? E1 * e : (i <= 32 ? E1 * 0.05 + E2 * (e - 0.05) : 1e4));
  }
  const Index peak = 32; // eps = 0.08
  const double s_peak = E1 * 0.05 + E2 * 0.03;
  ASSERT_NEAR(sig[peak], s_peak, 1e-9 * s_peak);
  // 70 % of the peak lies on the first segment: the secant is E1.
  EXPECT_NEAR(secant_modulus(eps, sig, peak), E1, 1e-9 * E1);
  // 95 % lies on the second segment, between samples (eps = 0.066): sigma/eps.
  const double target = 0.95 * s_peak;
  const double eps_target = 0.05 + (target - E1 * 0.05) / E2;
  EXPECT_NEAR(secant_modulus(eps, sig, peak, 0.95), target / eps_target, 1e-9 * E1);
  // Mirrored curve (tension-positive measure of a compression test): same modulus.
  std::vector<double> neg_eps(eps), neg_sig(sig);
  for (auto &x : neg_eps)
    x = -x;
  for (auto &x : neg_sig)
    x = -x;
  EXPECT_NEAR(secant_modulus(neg_eps, neg_sig, peak, 0.95), target / eps_target, 1e-9 * E1);
}

TEST(FailureSecantModulus, InterpolatesBetweenCoarseSamples)
{
  // sigma = E eps^2 sampled coarsely; the secant to the interpolated 70 % point is known exactly.
  std::vector<double> eps = {0, 1, 2, 3, 4};
  std::vector<double> sig = {0, 1, 4, 9, 16};
  // target 11.2 between (3, 9) and (4, 16): eps = 3 + 2.2/7.
  const double e = 3 + 2.2 / 7;
  EXPECT_NEAR(secant_modulus(eps, sig, 4), 11.2 / e, 1e-12);
  expect_invalid([&] { secant_modulus(eps, {0, 1, 4}, 2); }, "samples");
  expect_invalid([&] { secant_modulus(eps, sig, 7); }, "peak_index");
  expect_invalid([&] { secant_modulus({0, 0, 0, 0, 0}, sig, 4); }, "strain is zero");
  expect_invalid([&] { secant_modulus(eps, {0, 0, 0, 0, 0}, 4); }, "zero");
}

TEST(FailureSofteningRatio, StepDownCurve)
{
  // Rise to 10 at i = 30, 7 for 31..49, residual 4 from 50 to 99.
  std::vector<double> s(100);
  for (int i = 0; i < 100; ++i)
    s[i] = i <= 30 ? i / 3.0 : (i < 50 ? 7.0 : 4.0);
  // 69 samples follow the peak; the last half of them, 35 (65..99), are all at the residual 4.
  EXPECT_NEAR(softening_ratio(s, 30), 0.4, 1e-12);
  // Peak at 40: 59 follow, the last 30 (70..99) at 4. Peak at 70: 29 follow, the last 15 at 4.
  s[40] = 10;
  EXPECT_NEAR(softening_ratio(s, 40), 0.4, 1e-12);
  s[70] = 10;
  EXPECT_NEAR(softening_ratio(s, 70), 0.4, 1e-12);
  // Peak at 90 of a series 7 until 94, then 4: 9 follow, the last 5 (95..99) are 4; with 4 at 94
  // too, the last 5 still are; with 7 at 95 the mean of the last 5 is (7 + 4 * 4) / 5.
  std::vector<double> late(100, 7.0);
  late[90] = 10;
  for (int i = 95; i < 100; ++i)
    late[i] = 4;
  EXPECT_NEAR(softening_ratio(late, 90), 0.4, 1e-12);
  late[95] = 7;
  EXPECT_NEAR(softening_ratio(late, 90), (7 + 4 * 4) / 5.0 / 10, 1e-12);
  // One sample after the peak is too few; two give the last one (4 over the "peak" 4 at 97).
  expect_invalid([&] { softening_ratio(late, 98); }, "follow the peak");
  EXPECT_NEAR(softening_ratio(late, 97), 1.0, 1e-12);
  expect_invalid([&] { softening_ratio({}, 0); }, "empty");
}

TEST(FailureFlowAngle, ThirtyDegreesAndSigns)
{
  // Clump moves straight down until index 20, then along (cos a, sin a) with a prescribed angle.
  const auto history = [](double angle) {
    TestHistory h;
    for (int i = 0; i < 40; ++i)
    {
      h.time.push_back(i);
      h.stress.push_back(Mat3::Zero());
      const double after = std::max(0, i - 20);
      h.clump_displacement.push_back(Vec3(0, 0.3 * i, -1e-3 * std::min(i, 20)) +
                                     1e-3 * after * Vec3(std::cos(angle), 0, std::sin(angle)));
    }
    return h;
  };
  const double a = pi / 6;
  EXPECT_NEAR(flow_angle(history(a), 20, 5), a, 1e-12);              // dilation: theta > 0
  EXPECT_NEAR(flow_angle(history(-a), 20, 5), -a, 1e-12);            // compaction: theta < 0
  EXPECT_NEAR(flow_angle(history(pi - a), 20, 19), pi - a, 1e-12);   // shear towards -x, dilating
  EXPECT_NEAR(flow_angle(history(-pi / 2), 20, 5), -pi / 2, 1e-12);  // pure compaction
  EXPECT_NEAR(flow_angle(history(a), 10, 5), -pi / 2, 1e-12);        // before failure: still going down
  // The y component (out of plane) does not enter; a window past the end or no motion throws.
  expect_invalid([&] { flow_angle(history(a), 20, 20); }, "past the last sample");
  expect_invalid([&] { flow_angle(history(a), 20, 0); }, "window");
  TestHistory still = history(a);
  for (auto &u : still.clump_displacement)
    u = Vec3(0, 1, 0);
  expect_invalid([&] { flow_angle(still, 20, 5); }, "does not move");
  still.clump_displacement.clear();
  expect_invalid([&] { flow_angle(still, 20, 5); }, "clump_displacement");
}

TEST(FailureDegenerate, InvalidHistoriesThrow)
{
  TestHistory empty;
  expect_invalid([&] { failure_by_kinetic_energy_window(empty); }, "empty");
  expect_invalid([&] { failure_by_peak(empty, Measure::von_mises); }, "empty");
  expect_invalid([&] { analyse_failure(empty); }, "empty");

  const auto q = [](Index i) { return 1.0 + i; };
  TestHistory h = synthetic(20, q, [](Index) { return 0.0; });
  expect_invalid([&] { failure_by_kinetic_energy_window(h); }, "zero at every sample");

  h = synthetic(20, q, [](Index i) { return 1.0 + i; });
  h.clump_velocity.pop_back();
  expect_invalid([&] { failure_by_kinetic_energy_window(h); }, "clump_velocity has 19 samples");
  h.clump_velocity.clear();
  expect_invalid([&] { failure_by_kinetic_energy_window(h); }, "no clump_velocity");

  h = synthetic(20, q, [](Index i) { return 1.0 + i; });
  h.stress.pop_back();
  expect_invalid([&] { failure_by_peak(h, Measure::von_mises); }, "stress has 19");

  h = synthetic(20, q, [](Index i) { return 1.0 + i; });
  h.time[5] = h.time[4];
  expect_invalid([&] { validate(h); }, "strictly increasing");

  // Always above zeta: no quasi-static part.
  h = synthetic(20, q, [](Index i) { return 1.0 + 0.01 * i; });
  expect_invalid([&] { failure_by_kinetic_energy_window(h); }, "no sample before");
  expect_invalid([&] { failure_by_kinetic_energy_window(h, 0.0); }, "zeta");
}

TEST(FailureAnalysisBundle, MatchesTheParts)
{
  const auto q = [](Index i) { return i <= 50 ? 100.0 * i : (i < 60 ? 2000.0 : 1000.0); };
  const auto v = [](Index i) { return i < 55 ? 1e-3 : 1.0; };
  TestHistory h = synthetic(100, q, v);
  const FailureAnalysis a = analyse_failure(h);
  EXPECT_EQ(a.failure.index, 50);
  EXPECT_EQ(a.peak_q.index, 50);
  ASSERT_TRUE(a.peak_loading.has_value());
  EXPECT_EQ(a.peak_loading->index, 50);
  ASSERT_TRUE(a.secant_modulus.has_value());
  EXPECT_NEAR(*a.secant_modulus, 100.0 / 1e-3, 1e-6); // sigma = 100 i, strain = 1e-3 i
  ASSERT_TRUE(a.softening_ratio.has_value());
  EXPECT_NEAR(*a.softening_ratio, 1000.0 / 5000.0, 1e-12);
  ASSERT_TRUE(a.flow_angle.has_value());
  EXPECT_NEAR(*a.flow_angle, -pi / 2, 1e-12);

  // Wall-driven test without velocity: failure falls back to the peak of q; no strain, no secant.
  h.clump_velocity.clear();
  h.strain.clear();
  const FailureAnalysis b = analyse_failure(h);
  EXPECT_EQ(b.failure.index, 50);
  EXPECT_FALSE(b.secant_modulus.has_value());
}
