// Tests of params/flow_rule: Ritter et al.'s (2020) normalisation (Eqs. 4-6), loading and flow angles in the
// normalised plane (Eqs. 12-19), the transition angle (Eq. 7) and the measures of associativity.
// Hand-computed cases are worked out in the comments; the geometric construction of psi* is checked
// against Eq. 19 and the associative flow angle against the slope of Eq. 1 by implicit
// differentiation, which the code does not use.
#include "params/calibration_error.h"
#include "params/flow_rule.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace
{
  using namespace anticrack::params;

  constexpr double pi = 3.14159265358979323846;
  constexpr double radians_per_degree = pi / 180;

  /// Round-off tolerance for O(1) angles and normalised stresses: a handful of operations with
  /// relative error 1e-16 each; 1e-12 leaves a wide margin and still catches any formula error.
  constexpr double round_off = 1e-12;

  /// Parameter sets covering the branches: cohesionless (beta = 0), snow-like (0.3), equal tips
  /// (beta = 1, apex on the tau axis), and beta > 1 (apex on the tensile side, obtuse transition).
  const std::vector<CamClaySurface> parameter_sets = {
    {1e5, 0.0, 0.8}, {1e5, 0.3, 0.8}, {2650, 0.5, 0.6}, {1e6, 1.0, 1.0}, {1e5, 1.5, 0.8}};

  /// Standard normal deviates by Box-Muller from mt19937_64, reproducible across platforms.
  class NormalDeviates
  {
  public:
    explicit NormalDeviates(std::uint64_t seed)
      : engine(seed)
    {}

    double operator()()
    {
      const double u1 = (static_cast<double>(engine() >> 11) + 1) * 0x1.0p-53;
      const double u2 = static_cast<double>(engine() >> 11) * 0x1.0p-53;
      return std::sqrt(-2 * std::log(u1)) * std::cos(2 * pi * u2);
    }

  private:
    std::mt19937_64 engine;
  };

  /// Eq. 1 of Ritter et al. (2020) divided by M^2 p0^2 (dimensionless): 0 on the surface.
  double yield_function(double sigma, double tau, const CamClaySurface &c)
  {
    return (tau * tau * (1 + 2 * c.beta) + c.M * c.M * (sigma - c.p0) * (sigma + c.beta * c.p0))
           / (c.M * c.M * c.p0 * c.p0);
  }

  /// Associative flow angle from Eq. 1 directly: along the surface
  /// d tau/d sigma = -M^2 (2 sigma - (1 - beta) p0)/(2 tau (1 + 2 beta)), and the displacement
  /// (du_x, du_z) is proportional to (1, d tau/d sigma) for tau > 0.
  double flow_angle_from_surface_slope(double sigma, double tau, const CamClaySurface &c)
  {
    const double numerator = -c.M * c.M * (2 * sigma - (1 - c.beta) * c.p0);
    const double denominator = 2 * tau * (1 + 2 * c.beta);
    return std::atan2(numerator, denominator);
  }
} // namespace

TEST(Normalise, TipsAndApexOfTheEllipse)
{
  for (const CamClaySurface &c : parameter_sets)
    {
      // Compressive tip sigma_0 -> (1, 0), tensile tip -beta sigma_0 -> (-1, 0) (Eq. 5).
      const NormalisedStress compressive_tip = normalise(c.p0, 0, c);
      EXPECT_NEAR(compressive_tip.sigma, 1, round_off);
      EXPECT_NEAR(compressive_tip.tau, 0, round_off);
      const NormalisedStress tensile_tip = normalise(-c.beta * c.p0, 0, c);
      EXPECT_NEAR(tensile_tip.sigma, -1, round_off);
      // Apex ((1 - beta) sigma_0/2, M (1 + beta) sigma_0/(2 sqrt(1 + 2 beta))) -> (0, 1) (Eq. 6).
      const double apex_tau = c.M * (1 + c.beta) * c.p0 / (2 * std::sqrt(1 + 2 * c.beta));
      const NormalisedStress apex = normalise((1 - c.beta) * c.p0 / 2, apex_tau, c);
      EXPECT_NEAR(apex.sigma, 0, round_off);
      EXPECT_NEAR(apex.tau, 1, round_off);
    }
}

TEST(Normalise, PointsOfEq1AreOnTheUnitCircle)
{
  // tau from Eq. 1 for sigma across the surface; Eq. 4 must hold.
  for (const CamClaySurface &c : parameter_sets)
    for (int i = 1; i < 20; ++i)
      {
        const double sigma = -c.beta * c.p0 + (1 + c.beta) * c.p0 * i / 20.0;
        const double tau =
          std::sqrt(-c.M * c.M * (sigma - c.p0) * (sigma + c.beta * c.p0) / (1 + 2 * c.beta));
        const NormalisedStress normalised = normalise(sigma, tau, c);
        EXPECT_NEAR(normalised.sigma * normalised.sigma + normalised.tau * normalised.tau, 1, round_off);
      }
  EXPECT_THROW(normalise(1, 1, CamClaySurface{0, 0.3, 0.8}), CalibrationError);
  EXPECT_THROW(normalise(1, 1, CamClaySurface{1e5, -0.1, 0.8}), CalibrationError);
  EXPECT_THROW(normalise(1, 1, CamClaySurface{1e5, 0.3, 0}), CalibrationError);
}

TEST(LoadingAngle, RayIntersectionLiesOnSurfaceAndRay)
{
  // Eq. 1 residual relative to M^2 p0^2, and the point's direction is psi.
  for (const CamClaySurface &c : parameter_sets)
    for (int i = 0; i <= 36; ++i)
      {
        const double psi = pi * i / 36;
        const StressPoint point = surface_point_on_loading_ray(psi, c);
        if (c.beta == 0 && psi >= pi / 2)
          {
            // Cohesionless: the origin is the tensile tip and the only point of these rays.
            EXPECT_NEAR(point.normal, 0, round_off * c.p0);
            EXPECT_NEAR(point.shear, 0, round_off * c.p0);
            continue;
          }
        EXPECT_NEAR(yield_function(point.normal, point.shear, c), 0, round_off) << "psi = " << psi;
        EXPECT_NEAR(std::atan2(point.shear, point.normal), psi, round_off) << "psi = " << psi;
      }
}

TEST(LoadingAngle, HandCases)
{
  for (const CamClaySurface &c : parameter_sets)
    {
      // Pure compression meets the compressive tip, pure tension the tensile tip.
      EXPECT_NEAR(normalised_loading_angle(0, c), 0, round_off);
      EXPECT_NEAR(normalised_loading_angle(pi, c), pi, round_off);
      // The ray through the apex (Eq. 7) meets the circle at its top.
      EXPECT_NEAR(normalised_loading_angle(transition_loading_angle(c), c), pi / 2, round_off);
      // psi* increases with psi over [0, pi] (beta > 0: the origin is inside the surface).
      if (c.beta > 0)
        {
          double previous = -1;
          for (int i = 0; i <= 36; ++i)
            {
              const double psi_star = normalised_loading_angle(pi * i / 36, c);
              EXPECT_GT(psi_star, previous);
              EXPECT_GE(psi_star, 0);
              EXPECT_LE(psi_star, pi);
              previous = psi_star;
            }
        }
    }
  const CamClaySurface snow{1e5, 0.3, 0.8};
  EXPECT_THROW(normalised_loading_angle(-0.1, snow), CalibrationError);
  EXPECT_THROW(normalised_loading_angle(pi + 0.1, snow), CalibrationError);
}

TEST(LoadingAngle, Eq19ClosedFormMatchesGeometry)
{
  // For psi in (0, psi+-), the sigma* > 0 branch, tan of the geometric psi* must equal the closed
  // form of Eq. 19, and the result must satisfy the unsquared Eq. 19. For beta > 1 this includes
  // psi in (pi/2, psi+-) with mu < 0 (the other root of the quadratic). The tolerance is relative:
  // near psi+- mu* grows (tan of an angle near pi/2), and its relative error with it.
  for (const CamClaySurface &c : parameter_sets)
    {
      const double transition = transition_loading_angle(c);
      const double d = (1 - c.beta) / (1 + c.beta);
      for (int i = 1; i < 40; ++i)
        {
          const double psi = transition * i / 40;
          if (std::abs(psi - pi / 2) < 1e-3)
            continue;  // mu = tan psi is not representable there
          const double mu = std::tan(psi);
          const double mu_star_geometric = std::tan(normalised_loading_angle(psi, c));
          const double mu_star = normalised_loading_slope_eq19(mu, c);
          EXPECT_NEAR(mu_star, mu_star_geometric, 1e-10 * std::max(1.0, std::abs(mu_star_geometric)))
            << "beta = " << c.beta << ", psi = " << psi / radians_per_degree << " deg";
          EXPECT_GT(mu_star, 0);
          const double eq19_right_hand_side =
            mu / c.M * std::sqrt(1 + 2 * c.beta) * (1 + d * std::sqrt(1 + mu_star * mu_star));
          EXPECT_NEAR(mu_star, eq19_right_hand_side, 1e-10 * std::max(1.0, std::abs(mu_star)));
        }
      // Beyond the transition the ray meets the surface at sigma* < 0: Eq. 19 does not apply.
      const double beyond = 0.5 * (transition + pi);
      if (std::abs(beyond - pi / 2) > 1e-3)
        {
          EXPECT_THROW(normalised_loading_slope_eq19(std::tan(beyond), c), CalibrationError);
        }
      // For beta < 1 also an acute loading angle beyond psi+- (mu > 0, sigma* < 0).
      if (transition < pi / 2 - 1e-3)
        {
          EXPECT_THROW(normalised_loading_slope_eq19(std::tan(0.5 * (transition + pi / 2)), c),
                       CalibrationError);
        }
    }
}

TEST(TransitionAngle, Eq7LimitsAndApex)
{
  // Ritter et al. (2020): beta = 0 gives arctan M (critical state line), beta = 1 gives pi/2.
  EXPECT_NEAR(transition_loading_angle({1e5, 0.0, 0.8}), std::atan(0.8), round_off);
  EXPECT_NEAR(transition_loading_angle({1e5, 1.0, 0.8}), pi / 2, round_off);
  // beta = 0.3, M = 0.8: tan psi+- = 0.8 * 1.3/(0.7 sqrt(1.6)) = 1.04/0.885438 = 1.174560,
  // psi+- = 49.59 deg; beta = 1.5: tan = 0.8 * 2.5/(-0.5 * 2) = -2, psi+- = pi - arctan 2 (obtuse).
  EXPECT_NEAR(std::tan(transition_loading_angle({1e5, 0.3, 0.8})),
              0.8 * 1.3 / (0.7 * std::sqrt(1.6)), round_off);
  EXPECT_NEAR(transition_loading_angle({1e5, 1.5, 0.8}), pi - std::atan(2.0), round_off);
  // It is the direction of the apex.
  for (const CamClaySurface &c : parameter_sets)
    {
      const double apex_sigma = (1 - c.beta) * c.p0 / 2;
      const double apex_tau = c.M * (1 + c.beta) * c.p0 / (2 * std::sqrt(1 + 2 * c.beta));
      EXPECT_NEAR(transition_loading_angle(c), std::atan2(apex_tau, apex_sigma), round_off);
    }
}

TEST(FlowAngle, HandComputedEq18)
{
  // beta = 0.5, M = 0.8, theta = 30 deg: sqrt(1 + 2 beta) = sqrt(2), tan 30 deg = 1/sqrt(3), so
  // tan theta* = sqrt(2)/(0.8 sqrt(3)) = sqrt(2/3)/0.8 = 0.816496581/0.8 = 1.020620726 and
  // theta* = arctan(1.020620726) = 45 deg + 0.5847 deg = 0.795602953 rad (series of arctan about 1:
  // pi/4 + h/2 - h^2/4 + h^3/12 with h = 0.020620726).
  const CamClaySurface c{1e5, 0.5, 0.8};
  EXPECT_NEAR(normalised_flow_angle(30 * radians_per_degree, c), 0.795602953, 1e-9);
  EXPECT_NEAR(flow_angle_from_normalised(0.7956029534845354, c), 30 * radians_per_degree, 1e-12);

  // The quadrant is kept: compaction near -90 deg stays compaction near -90 deg, and theta = +-90
  // deg are fixed points (pure compaction/expansion).
  const double near_vertical = normalised_flow_angle(-89 * radians_per_degree, c);
  EXPECT_LT(near_vertical, -pi / 4);
  EXPECT_GT(near_vertical, -pi / 2);
  EXPECT_NEAR(normalised_flow_angle(-pi / 2, c), -pi / 2, round_off);
  EXPECT_NEAR(normalised_flow_angle(pi / 2, c), pi / 2, round_off);

  // Round trip over all directions.
  for (int i = -179; i <= 180; i += 7)
    {
      const double theta = i * radians_per_degree;
      EXPECT_NEAR(flow_angle_from_normalised(normalised_flow_angle(theta, c), c), theta, round_off);
    }
}

TEST(FlowAngle, AssociativeFlowIsNormalToEq1)
{
  // associative_flow_angle goes through psi*, Eq. 16 and the inverse of Eq. 18; the slope of Eq. 1
  // at the failure point by implicit differentiation must give the same angle. Compaction below the
  // transition angle, expansion above (Ritter et al. 2020, Results and Discussion).
  for (const CamClaySurface &c : parameter_sets)
    {
      const double transition = transition_loading_angle(c);
      const double last_psi = (c.beta == 0) ? pi / 2 : pi;  // beta = 0: tensile rays end at the origin
      for (int i = 1; i < 36; ++i)
        {
          const double psi = last_psi * i / 36;
          if (c.beta == 0 && psi >= pi / 2)
            continue;
          const StressPoint point = surface_point_on_loading_ray(psi, c);
          const double theta = associative_flow_angle(psi, c);
          EXPECT_NEAR(theta, flow_angle_from_surface_slope(point.normal, point.shear, c), round_off)
            << "beta = " << c.beta << ", psi = " << psi / radians_per_degree << " deg";
          if (psi < transition - 1e-6)
            {
              EXPECT_LT(theta, 0) << "compaction expected below psi+-";
            }
          if (psi > transition + 1e-6)
            {
              EXPECT_GT(theta, 0) << "expansion expected above psi+-";
            }
        }
      // Pure compression: vertical compaction; pure tension: vertical expansion.
      EXPECT_NEAR(associative_flow_angle(0, c), -pi / 2, round_off);
      if (c.beta > 0)
        {
          EXPECT_NEAR(associative_flow_angle(pi, c), pi / 2, round_off);
        }
    }
}

TEST(Associativity, AssociativeDataAreRecognised)
{
  const CamClaySurface c{1e5, 0.3, 0.8};
  std::vector<double> psi_star, theta_star;
  for (int degrees = 0; degrees <= 180; degrees += 15)
    {
      const double psi = degrees * radians_per_degree;
      psi_star.push_back(normalised_loading_angle(psi, c));
      theta_star.push_back(normalised_flow_angle(associative_flow_angle(psi, c), c));
    }
  const AssociativityMeasure measure = measure_associativity(psi_star, theta_star);
  EXPECT_EQ(measure.n, 13);
  EXPECT_LT(measure.rms_deviation, round_off);
  EXPECT_LT(measure.max_abs_deviation, round_off);
  EXPECT_NEAR(measure.line.slope, 1, round_off);
  EXPECT_NEAR(measure.line.intercept, -pi / 2, round_off);
  EXPECT_NEAR(measure.r_squared_associative, 1, round_off);
  EXPECT_TRUE(measure.slope_consistent_with_associative);
  EXPECT_TRUE(measure.intercept_consistent_with_associative);
}

TEST(Associativity, ConstantOffsetOfTenDegrees)
{
  // theta* = psi* - pi/2 + 10 deg: every deviation is 10 deg, the line keeps slope 1 and its
  // intercept moves by 10 deg.
  const double offset = 10 * radians_per_degree;
  std::vector<double> psi_star, theta_star;
  for (int i = 0; i <= 12; ++i)
    {
      psi_star.push_back(0.1 + 2.9 * i / 12);
      theta_star.push_back(psi_star.back() - pi / 2 + offset);
    }
  const AssociativityMeasure measure = measure_associativity(psi_star, theta_star);
  EXPECT_NEAR(measure.rms_deviation_deg, 10, 1e-10);
  EXPECT_NEAR(measure.max_abs_deviation_deg, 10, 1e-10);
  EXPECT_NEAR(measure.mean_deviation, offset, round_off);
  EXPECT_NEAR(measure.line.slope, 1, round_off);
  EXPECT_NEAR(measure.line.intercept, -pi / 2 + offset, round_off);
  EXPECT_FALSE(measure.intercept_consistent_with_associative);
  // sum d^2 = 13 offset^2 against the spread of theta*; R^2_assoc below 1.
  double mean = 0;
  for (double t : theta_star)
    mean += t;
  mean /= theta_star.size();
  double sst = 0;
  for (double t : theta_star)
    sst += (t - mean) * (t - mean);
  EXPECT_NEAR(measure.r_squared_associative, 1 - 13 * offset * offset / sst, round_off);
}

TEST(Associativity, DeviationIsTheAngleBetweenDirections)
{
  // Deviations are angles between directions, in [-180, 180] deg: a flow direction of -170 deg
  // (down and backwards) against the associative +20 deg at psi* = 110 deg is -190 deg = +170 deg
  // apart; +175 deg against -90 deg at psi* = 0 is 265 deg = -95 deg apart.
  const double degree = radians_per_degree;
  const AssociativityMeasure measure = measure_associativity(
    {110 * degree, 0, 30 * degree}, {-170 * degree, 175 * degree, -60 * degree});
  EXPECT_NEAR(measure.deviation[0], 170 * degree, round_off);
  EXPECT_NEAR(measure.deviation[1], -95 * degree, round_off);
  EXPECT_NEAR(measure.deviation[2], 0, round_off);
  EXPECT_NEAR(measure.max_abs_deviation_deg, 170, 1e-10);
}

TEST(Associativity, NonAssociativeRuleIsDetected)
{
  // theta* = 0.5 (psi* - pi/2) with 1 deg scatter (fixed seed): the slope's interval must hold 0.5
  // and exclude 1 (with 25 points spread over 3 rad, se(slope) ~ 0.004).
  NormalDeviates noise(3);
  std::vector<double> psi_star, theta_star;
  for (int i = 0; i < 25; ++i)
    {
      psi_star.push_back(0.05 + 3.0 * i / 24);
      theta_star.push_back(0.5 * (psi_star.back() - pi / 2) + radians_per_degree * noise());
    }
  const AssociativityMeasure measure = measure_associativity(psi_star, theta_star);
  EXPECT_NEAR(measure.line.slope, 0.5, 0.02);
  EXPECT_TRUE(measure.line.slope_ci.contains(0.5));
  EXPECT_FALSE(measure.line.slope_ci.contains(1.0));
  EXPECT_FALSE(measure.slope_consistent_with_associative);
  EXPECT_LT(measure.r_squared_associative, 0.9);
  EXPECT_GT(measure.rms_deviation_deg, 10);

  EXPECT_THROW(measure_associativity({0.1, 0.2}, {-1.4, -1.3}), CalibrationError);
  EXPECT_THROW(measure_associativity({0.1, 0.2, 0.3}, {-1.4, -1.3}), CalibrationError);
}

TEST(ObservedTransition, KnownCrossing)
{
  // theta = 0.5 (psi - 67.5 deg) with three realisations per angle offset by +-0.02 rad (mean 0),
  // given out of order: the per-angle means are linear in psi, so interpolation is exact.
  const std::vector<double> angles_deg = {0, 22.5, 45, 60, 75, 90, 135};
  std::vector<double> psi, theta;
  for (int realisation = 0; realisation < 3; ++realisation)
    for (auto it = angles_deg.rbegin(); it != angles_deg.rend(); ++it)
      {
        psi.push_back(*it * radians_per_degree);
        theta.push_back(0.5 * (*it - 67.5) * radians_per_degree + 0.02 * (realisation - 1));
      }
  EXPECT_NEAR(observed_transition_angle(psi, theta), 67.5 * radians_per_degree, round_off);

  // Means -0.2 at 60 deg and +0.1 at 75 deg: 60 + 15 * 0.2/0.3 = 70 deg.
  EXPECT_NEAR(observed_transition_angle({0.5, 60 * radians_per_degree, 75 * radians_per_degree},
                                        {-0.6, -0.2, 0.1}),
              70 * radians_per_degree, round_off);
  // Exact zeros at 60 and 70 deg between -0.1 at 50 deg and +0.1 at 80 deg: middle 65 deg.
  EXPECT_NEAR(observed_transition_angle({50 * radians_per_degree, 60 * radians_per_degree,
                                         70 * radians_per_degree, 80 * radians_per_degree},
                                        {-0.1, 0, 0, 0.1}),
              65 * radians_per_degree, round_off);
}

TEST(ObservedTransition, AssociativeFlowCrossesAtEq7)
{
  // Flow from the associative rule on a 1 deg grid of loading angles changes sign at psi+- (Eq. 7)
  // up to the linear interpolation error ~ h^2/8 |theta''/theta'| with h = 0.017 rad (at most
  // 0.003 deg for these parameter sets); 0.01 deg keeps a margin.
  for (const CamClaySurface &c : parameter_sets)
    {
      std::vector<double> psi, theta;
      for (int degrees = 1; degrees < 180; ++degrees)
        {
          if (c.beta == 0 && degrees >= 90)
            break;
          psi.push_back(degrees * radians_per_degree);
          theta.push_back(associative_flow_angle(psi.back(), c));
        }
      EXPECT_NEAR(observed_transition_angle(psi, theta) / radians_per_degree,
                  transition_loading_angle(c) / radians_per_degree, 0.01)
        << "beta = " << c.beta;
    }
}

TEST(ObservedTransition, RejectsDataWithoutTransition)
{
  const std::vector<double> psi = {0, 0.4, 0.8, 1.2};
  EXPECT_THROW(observed_transition_angle(psi, {-1.5, -1.0, -0.5, -0.1}), CalibrationError);
  EXPECT_THROW(observed_transition_angle(psi, {0.1, 0.5, 1.0, 1.5}), CalibrationError);
  EXPECT_THROW(observed_transition_angle(psi, {0.5, 0.1, -0.1, -0.5}), CalibrationError);
  EXPECT_THROW(observed_transition_angle({0.3, 0.3, 0.3}, {-0.1, 0.0, 0.1}), CalibrationError);
  EXPECT_THROW(observed_transition_angle(psi, {-0.1, 0.1}), CalibrationError);
  try
    {
      observed_transition_angle(psi, {-1.5, -1.0, -0.5, -0.1});
      FAIL() << "all-compaction data accepted";
    }
  catch (const CalibrationError &error)
    {
      EXPECT_NE(std::string(error.what()).find("all compaction"), std::string::npos) << error.what();
    }
}
