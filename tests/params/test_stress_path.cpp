// The FE point on a DEM test's path (params/stress_path.h): Eq. (P1) against the stress tensor built
// from Hooke's law under each lateral condition, the ray property the fit relies on, and the chord
// test on the measured strengths of the ballistic layer.
#include "params/envelope_fit.h"
#include "params/stress_path.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>

namespace
{
  using namespace anticrack::params;
  constexpr double pi = 3.14159265358979323846;

  /// The stress (tension positive, z normal to the layer) of an isotropic solid (E, ν) carrying the
  /// layer-plane traction σ_zz = −σ, σ_xz = τ: with no lateral strain (confined) the lateral stresses
  /// are solved from Hooke's law ε_xx = ε_yy = 0; with open sides they are zero.
  Eigen::Matrix3d stress_on_path(double sigma, double tau, bool confined, double E, double nu)
  {
    Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
    s(2, 2) = -sigma;
    s(0, 2) = s(2, 0) = tau;
    if (confined)
    {
      // ε_xx = [s_xx − ν (s_yy + s_zz)]/E = 0 and ε_yy likewise: a 2×2 system for (s_xx, s_yy).
      Eigen::Matrix2d A;
      A << 1, -nu, -nu, 1;
      const Eigen::Vector2d lateral = A.colPivHouseholderQr().solve(Eigen::Vector2d(nu * s(2, 2), nu * s(2, 2)));
      s(0, 0) = lateral(0), s(1, 1) = lateral(1);
      const double strain_xx = (s(0, 0) - nu * (s(1, 1) + s(2, 2))) / E;
      EXPECT_NEAR(strain_xx, 0, 1e-15 * std::abs(sigma) / E);
    }
    return s;
  }

  StressPoint invariants_of(const Eigen::Matrix3d &s)
  {
    const double p = -s.trace() / 3;
    const Eigen::Matrix3d d = s + p * Eigen::Matrix3d::Identity();
    return {p, std::sqrt(1.5 * (d.array() * d.array()).sum())};
  }
} // namespace

TEST(TestPath, InvariantsAreThoseOfTheStressTensorUnderTheLateralCondition)
{
  for (const bool confined : {true, false})
    for (const double nu : {0.0, 0.2, 0.35})
      for (const double psi_deg : {0.0, 30.0, 90.0, 135.0, 180.0})
      {
        const double psi = psi_deg * pi / 180, sigma = 1200 * std::cos(psi), tau = 1200 * std::sin(psi);
        const TestPath path{confined, nu};
        const StressPoint expected = invariants_of(stress_on_path(sigma, tau, confined, 1e6, nu));
        const StressPoint got = path.invariants(sigma, tau);
        EXPECT_NEAR(got.normal, expected.normal, 1e-10 * 1200) << confined << " " << nu << " " << psi_deg;
        EXPECT_NEAR(got.shear, expected.shear, 1e-10 * 1200) << confined << " " << nu << " " << psi_deg;
      }
  EXPECT_DOUBLE_EQ((TestPath{true, 0.2}.lateral_stress_ratio()), 0.25);
  EXPECT_EQ((TestPath{false, 0.2}.lateral_stress_ratio()), 0.0);
}

TEST(TestPath, ARayOfBaseStressesIsARayOfInvariants)
{
  // The fit's relative radial residual is the same in both planes only because (P1) is homogeneous
  // of degree one: a point twice as far along a (σ, τ) ray maps twice as far along one (p, q) ray.
  const TestPath path{true, 0.3};
  for (const double psi_deg : {0.0, 45.0, 100.0, 180.0})
  {
    const double psi = psi_deg * pi / 180;
    const StressPoint a = path.invariants(std::cos(psi), std::sin(psi)),
                      b = path.invariants(2.5 * std::cos(psi), 2.5 * std::sin(psi));
    EXPECT_NEAR(polar_angle(a), polar_angle(b), 1e-14);
    EXPECT_NEAR(polar_radius(b) / polar_radius(a), 2.5, 1e-14);
  }
}

TEST(TestPath, TheBallisticLayerFailsTheChordTestAndAnIsotropicStrengthSetPassesIt)
{
  // Base stresses at failure of the ballistic weak layer (open sides, scenes/ballistic_weak_layer.prm,
  // one realization): compression 1515 Pa at psi = 0, shear 273.5 Pa at 90 deg, tension 871.5 Pa at 180.
  const TestPath open{false, 0};
  const double deficit = chord_shear_deficit(open, 1515.3, 273.5, -871.5);
  // On the paths: (505, 1515), (0, 473.7), (-290.5, 871.5); the chord at p = 0 is at
  // 871.5 + (1515.3 - 871.5) 290.5/795.6 = 1106.6 Pa, so the shear point is 57 % below it.
  EXPECT_NEAR(deficit, 1 - 473.7 / 1106.6, 2e-3);
  // von Mises (no pressure dependence): uniaxial strengths sqrt(3) times the shear strength; the
  // shear point lies on the chord (q = const).
  EXPECT_NEAR(chord_shear_deficit(open, std::sqrt(3.0), 1.0, -std::sqrt(3.0)), 0, 1e-14);
}

TEST(TestPath, FailurePointsOfAnInvariantSurfaceOnThePathsGiveItBackFromTheirBaseStresses)
{
  // The cohesive Cam-Clay surface (p0, beta, M) = (10 kPa, 0.45, 1.8) of an FE point with nu = 0.2
  // under periodic sides: its failure along each ray of the (sigma, tau) plane, found by bisection
  // of the yield function of the tensor of stress_on_path (not through Eq. (P1)), then 3 % scatter.
  const double p0 = 1e4, beta = 0.45, M = 1.8, nu = 0.2;
  const auto yield = [&](const StressPoint &pq) {
    return (1 + 2 * beta) * pq.shear * pq.shear + M * M * (pq.normal + beta * p0) * (pq.normal - p0);
  };
  std::vector<StressPoint> points;
  std::uint64_t state = 12345;
  const auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  const TestPath path{true, nu};
  for (int k = 0; k <= 8; ++k)
    for (int r = 0; r < 3; ++r)
    {
      const double psi = k * pi / 8;
      double low = 0, high = 1e6;
      for (int i = 0; i < 200; ++i)
      {
        const double mid = 0.5 * (low + high);
        const StressPoint pq = invariants_of(stress_on_path(mid * std::cos(psi), mid * std::sin(psi), true, 1e6, nu));
        (yield(pq) > 0 ? high : low) = mid;
      }
      const double scatter = 1 + 0.03 * (2 * uniform() - 1) * std::sqrt(3.0);
      points.push_back(path.invariants(low * scatter * std::cos(psi), low * scatter * std::sin(psi)));
    }
  const auto model = make_envelope(EnvelopeKind::cohesive_cam_clay);
  const EnvelopeFit fit = fit_envelope(*model, points, {}, {});
  // 27 points with 3 % scatter: the fit's 95 % intervals are a few per cent wide.
  EXPECT_TRUE(fit.identifiable);
  EXPECT_GE(p0, fit.ci_lower(0));
  EXPECT_LE(p0, fit.ci_upper(0));
  EXPECT_NEAR(fit.parameters(1), beta, 0.1 * beta);
  EXPECT_NEAR(fit.parameters(2), M, 0.1 * M);
  EXPECT_LT(fit.rmse, 0.03);
}

TEST(TestPath, TheImageOfAnInvariantSurfaceIsNeverFlatterThanTheLeastShearRatio)
{
  // The image of (p0, beta, M) in the (sigma, tau) plane on the confined path, traced ray by ray by
  // bisection of the yield function of the tensor from Hooke's law: its tau semi-axis over its
  // sigma semi-axis is sqrt(A/D) of stress_path.h, which exceeds (1 - k)/sqrt(3) however small M is.
  const double nu = 0.15, p0 = 1e4;
  const TestPath path{true, nu};
  const double k = path.lateral_stress_ratio(), c = (1 + 2 * k) / 3;
  for (const auto &[beta, M] : {std::pair{0.5, 1.0}, std::pair{0.3, 0.2}, std::pair{0.9, 3.0}})
  {
    const auto yield = [&, beta = beta, M = M](const StressPoint &pq) {
      return (1 + 2 * beta) * pq.shear * pq.shear + M * M * (pq.normal + beta * p0) * (pq.normal - p0);
    };
    double compression = 0, tension = 0, largest_tau = 0;
    for (int j = 0; j <= 3600; ++j)
    {
      const double psi = j * pi / 3600;
      double low = 0, high = 1e7;
      for (int i = 0; i < 100; ++i)
      {
        const double mid = 0.5 * (low + high);
        (yield(invariants_of(stress_on_path(mid * std::cos(psi), mid * std::sin(psi), true, 1e6, nu))) > 0 ? high : low) =
          mid;
      }
      largest_tau = std::max(largest_tau, low * std::sin(psi));
      if (j == 0)
        compression = low;
      if (j == 3600)
        tension = low;
    }
    const double ratio = largest_tau / (0.5 * (compression + tension));
    const double expected = std::sqrt((1 - k) * (1 - k) / 3 + M * M * c * c / (3 * (1 + 2 * beta)));
    EXPECT_NEAR(ratio, expected, 1e-5 * expected) << beta << " " << M;
    EXPECT_GT(ratio, least_cam_clay_shear_ratio(path));
  }
  EXPECT_DOUBLE_EQ(least_cam_clay_shear_ratio(TestPath{false, 0.3}), 1 / std::sqrt(3.0));
}
