// Tests of params/regression: least-squares lines and power laws with t-intervals, sample
// statistics and the thickness scaling of micro-macro laws. Reference values are computed by hand
// (in the comments) or are the source papers' published coefficients used as synthetic truth.
#include "params/calibration_error.h"
#include "params/regression.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
  using namespace anticrack::params;

  /// Standard normal deviates by Box-Muller from mt19937_64 (whose output the standard fixes, unlike
  /// std::normal_distribution's), so that the "fixed seed" data are the same on every platform.
  class NormalDeviates
  {
  public:
    explicit NormalDeviates(std::uint64_t seed)
      : engine(seed)
    {}

    double operator()()
    {
      const double two_pi = 6.283185307179586;
      // (0, 1]: the logarithm must not see 0.
      const double u1 = (static_cast<double>(engine() >> 11) + 1) * 0x1.0p-53;
      const double u2 = static_cast<double>(engine() >> 11) * 0x1.0p-53;
      return std::sqrt(-2 * std::log(u1)) * std::cos(two_pi * u2);
    }

  private:
    std::mt19937_64 engine;
  };

  std::vector<double> evenly_spaced(double first, double last, int count)
  {
    std::vector<double> values(count);
    for (int i = 0; i < count; ++i)
      values[i] = first + (last - first) * i / (count - 1);
    return values;
  }

  /// Student t quantile for 2 degrees of freedom in closed form: t = (2p - 1)/sqrt(2 p (1 - p)).
  double t_quantile_two_dof(double probability)
  {
    return (2 * probability - 1) / std::sqrt(2 * probability * (1 - probability));
  }

  // Eq. (7) of Bobillier et al. (2020), weak layer: E_wl,macro = beta_0 + beta_1 E_particle.
  constexpr double bobillier_beta0 = 7.3e4;  // [Pa]
  constexpr double bobillier_beta1 = 0.014;
  // Eqs. (2)-(3) of Ritter et al. (2020): sigma_0/sigma_bond = h nu_c^kappa, beta sigma_0/sigma_bond = k nu_c^lambda.
  constexpr double ritter_h = 2.81e-3;
  constexpr double ritter_kappa = 3.59;
  constexpr double ritter_k = 1.38e-3;
  constexpr double ritter_lambda = 3.09;
} // namespace

TEST(StudentT, TableValue)
{
  // t_{0.975, 10} from tables, 12 decimals: a 1e-11 tolerance allows for the table's rounding.
  EXPECT_NEAR(student_t_quantile(0.975, 10), 2.228138851986, 1e-11);
  // Symmetry and the closed form for 2 degrees of freedom (round-off only).
  EXPECT_NEAR(student_t_quantile(0.025, 10), -student_t_quantile(0.975, 10), 1e-13);
  EXPECT_NEAR(student_t_quantile(0.975, 2), t_quantile_two_dof(0.975), 1e-12);
  EXPECT_THROW(student_t_quantile(1.0, 10), CalibrationError);
  EXPECT_THROW(student_t_quantile(0.0, 10), CalibrationError);
  EXPECT_THROW(student_t_quantile(0.975, 0), CalibrationError);
}

TEST(FitLine, ExactBobillierWeakLayerModulusRecovered)
{
  // Nine particle moduli (Bobillier et al. (2020) used nine) on E_macro = 7.3e4 Pa + 0.014 E_particle. Exact data
  // must come back to round-off: 1e-12 relative leaves ~1e3 ulps for the sums over nine points.
  const std::vector<double> particle_modulus = evenly_spaced(1e7, 9e7, 9);
  std::vector<double> macro_modulus;
  for (double e : particle_modulus)
    macro_modulus.push_back(bobillier_beta0 + bobillier_beta1 * e);

  const LinearFit fit = fit_line(particle_modulus, macro_modulus, 0.95, "E_wl,macro vs E_particle");
  EXPECT_NEAR(fit.intercept, bobillier_beta0, 1e-12 * bobillier_beta0);
  EXPECT_NEAR(fit.slope, bobillier_beta1, 1e-12 * bobillier_beta1);
  EXPECT_NEAR(fit.r_squared, 1.0, 1e-12);
  EXPECT_EQ(fit.n, 9);
  // Residuals are round-off of values ~1e6 Pa.
  EXPECT_LT(fit.residual_standard_deviation, 1e-12 * 1.3e6);
  EXPECT_NEAR(fit(5e7), bobillier_beta0 + bobillier_beta1 * 5e7, 1e-12 * 1e6);
}

TEST(FitLine, HandComputedSmallData)
{
  // x = 1..4, y = {1, 3, 2, 5}: mean x 2.5, mean y 2.75, Sxx = 5, Sxy = 5.5, so slope 1.1 and
  // intercept 0; fitted 1.1, 2.2, 3.3, 4.4, residuals -0.1, 0.8, -1.3, 0.6, SSR = 2.7,
  // SST = 8.75, R^2 = 1 - 2.7/8.75 = 0.691428571428571; s^2 = 2.7/2 = 1.35,
  // se(slope) = sqrt(1.35/5), se(intercept) = sqrt(1.35 (1/4 + 6.25/5)) = sqrt(2.025),
  // cov = -2.5 * 1.35/5 = -0.675; t_{0.975, 2} in closed form.
  const LinearFit fit = fit_line({1, 2, 3, 4}, {1, 3, 2, 5});
  EXPECT_NEAR(fit.slope, 1.1, 1e-14);
  EXPECT_NEAR(fit.intercept, 0.0, 1e-14);
  EXPECT_NEAR(fit.r_squared, 0.691428571428571, 1e-14);
  EXPECT_NEAR(fit.residual_standard_deviation, std::sqrt(1.35), 1e-14);
  EXPECT_NEAR(fit.slope_standard_error, std::sqrt(0.27), 1e-14);
  EXPECT_NEAR(fit.intercept_standard_error, std::sqrt(2.025), 1e-14);
  EXPECT_NEAR(fit.intercept_slope_covariance, -0.675, 1e-14);
  const double t = t_quantile_two_dof(0.975);
  EXPECT_NEAR(fit.slope_ci.lower, 1.1 - t * std::sqrt(0.27), 1e-12);
  EXPECT_NEAR(fit.slope_ci.upper, 1.1 + t * std::sqrt(0.27), 1e-12);
  EXPECT_NEAR(fit.intercept_ci.upper, t * std::sqrt(2.025), 1e-12);
}

TEST(FitLine, NoisyDataTruthInsideInterval)
{
  // Bobillier et al.'s (2020) weak-layer line with 2 % scatter (sd 2e4 Pa on ~1e6 Pa), fixed seed: the 95 %
  // intervals must hold the truth, and the estimates must be close to it (within 4 standard
  // errors, which a correct fit misses with probability 6e-5).
  NormalDeviates noise(20240531);
  const std::vector<double> particle_modulus = evenly_spaced(1e7, 9e7, 9);
  std::vector<double> macro_modulus;
  for (double e : particle_modulus)
    macro_modulus.push_back(bobillier_beta0 + bobillier_beta1 * e + 2e4 * noise());

  const LinearFit fit = fit_line(particle_modulus, macro_modulus);
  EXPECT_TRUE(fit.slope_ci.contains(bobillier_beta1))
    << "[" << fit.slope_ci.lower << ", " << fit.slope_ci.upper << "]";
  EXPECT_TRUE(fit.intercept_ci.contains(bobillier_beta0))
    << "[" << fit.intercept_ci.lower << ", " << fit.intercept_ci.upper << "]";
  EXPECT_NEAR(fit.slope, bobillier_beta1, 4 * fit.slope_standard_error);
  EXPECT_GT(fit.r_squared, 0.99);
  EXPECT_LT(fit.r_squared, 1.0);
}

TEST(FitLine, ConfidenceIntervalCoverage)
{
  // 500 data sets of only 5 points: the t-intervals (3 degrees of freedom, t = 3.18) must cover the
  // truth in 95 % of them; binomial sd sqrt(0.95 * 0.05/500) = 1 %, so 92-98 % is +-3 sd. Normal
  // quantiles (1.96) would give ~85 % and fail.
  NormalDeviates noise(7);
  const std::vector<double> x = evenly_spaced(0.0, 4.0, 5);
  const double true_intercept = 2.0;
  const double true_slope = -0.7;
  int slope_covered = 0;
  int intercept_covered = 0;
  const int sets = 500;
  for (int set = 0; set < sets; ++set)
    {
      std::vector<double> y;
      for (double xi : x)
        y.push_back(true_intercept + true_slope * xi + 0.3 * noise());
      const LinearFit fit = fit_line(x, y, 0.95);
      slope_covered += fit.slope_ci.contains(true_slope);
      intercept_covered += fit.intercept_ci.contains(true_intercept);
    }
  EXPECT_GE(slope_covered, 0.92 * sets);
  EXPECT_LE(slope_covered, 0.98 * sets);
  EXPECT_GE(intercept_covered, 0.92 * sets);
  EXPECT_LE(intercept_covered, 0.98 * sets);
}

TEST(FitLine, RejectsBadData)
{
  EXPECT_THROW(fit_line({1, 2}, {1, 2}), CalibrationError);
  EXPECT_THROW(fit_line({1, 2, 3}, {1, 2}), CalibrationError);
  EXPECT_THROW(fit_line({1, 2, 3}, {1, std::numeric_limits<double>::quiet_NaN(), 3}), CalibrationError);
  EXPECT_THROW(fit_line({1, 2, std::numeric_limits<double>::infinity()}, {1, 2, 3}), CalibrationError);
  EXPECT_THROW(fit_line({2, 2, 2, 2}, {1, 2, 3, 4}), CalibrationError);
  EXPECT_THROW(fit_line({1, 2, 3}, {1, 2, 3}, 1.0), CalibrationError);
  // The message names the data set and the count.
  try
    {
      fit_line({1, 2}, {1, 2}, 0.95, "sigma_macro vs sigma_bond");
      FAIL() << "two points accepted";
    }
  catch (const CalibrationError &error)
    {
      const std::string message = error.what();
      EXPECT_NE(message.find("sigma_macro vs sigma_bond"), std::string::npos) << message;
      EXPECT_NE(message.find("2 points"), std::string::npos) << message;
    }
}

TEST(FitPowerLaw, ExactRitterScalingRecovered)
{
  // Ritter et al. 2020, Eq. 2 (h = 2.81e-3, kappa = 3.59) and Eq. 3 (k = 1.38e-3, lambda = 3.09) on contact
  // densities 0.6-2.4: exact data back to round-off (1e-12 relative; the logs are O(1)).
  const std::vector<double> contact_density = evenly_spaced(0.6, 2.4, 10);
  std::vector<double> compressive, tensile;
  for (double nu : contact_density)
    {
      compressive.push_back(ritter_h * std::pow(nu, ritter_kappa));
      tensile.push_back(ritter_k * std::pow(nu, ritter_lambda));
    }
  const PowerLawFit compressive_fit = fit_power_law(contact_density, compressive, 0.95, "sigma_0");
  EXPECT_NEAR(compressive_fit.prefactor, ritter_h, 1e-12 * ritter_h);
  EXPECT_NEAR(compressive_fit.exponent, ritter_kappa, 1e-12 * ritter_kappa);
  EXPECT_NEAR(compressive_fit.r_squared_log, 1.0, 1e-12);
  EXPECT_NEAR(compressive_fit.r_squared, 1.0, 1e-12);
  EXPECT_NEAR(compressive_fit(2.0), ritter_h * std::pow(2.0, ritter_kappa), 1e-12 * 0.03);

  const PowerLawFit tensile_fit = fit_power_law(contact_density, tensile, 0.95, "beta sigma_0");
  EXPECT_NEAR(tensile_fit.prefactor, ritter_k, 1e-12 * ritter_k);
  EXPECT_NEAR(tensile_fit.exponent, ritter_lambda, 1e-12 * ritter_lambda);
}

TEST(FitPowerLaw, NoisyDataIntervalsAndRSquared)
{
  // Eq. 2 of Ritter et al. (2020) with 10 % multiplicative scatter, three realisations at each of 7 contact
  // densities (Ritter et al. (2020) simulated three per microstructure), fixed seed.
  NormalDeviates noise(42);
  std::vector<double> contact_density, strength;
  for (double nu : evenly_spaced(0.6, 2.4, 7))
    for (int realisation = 0; realisation < 3; ++realisation)
      {
        contact_density.push_back(nu);
        strength.push_back(ritter_h * std::pow(nu, ritter_kappa) * std::exp(0.1 * noise()));
      }
  const PowerLawFit fit = fit_power_law(contact_density, strength, 0.95, "sigma_0/sigma_bond");
  EXPECT_TRUE(fit.exponent_ci.contains(ritter_kappa))
    << "[" << fit.exponent_ci.lower << ", " << fit.exponent_ci.upper << "]";
  EXPECT_TRUE(fit.prefactor_ci.contains(ritter_h))
    << "[" << fit.prefactor_ci.lower << ", " << fit.prefactor_ci.upper << "]";
  // The prefactor interval is exp of a symmetric interval: symmetric in the logarithm, so the
  // prefactor is its geometric mean (round-off only), and asymmetric about the prefactor itself.
  EXPECT_NEAR(fit.prefactor_ci.lower * fit.prefactor_ci.upper, fit.prefactor * fit.prefactor,
              1e-12 * fit.prefactor * fit.prefactor);
  EXPECT_GT(fit.prefactor_ci.upper - fit.prefactor, fit.prefactor - fit.prefactor_ci.lower);

  // R^2 in log space is the line's; R^2 of y by its definition, computed here by hand.
  EXPECT_DOUBLE_EQ(fit.r_squared_log, fit.log_fit.r_squared);
  double mean = 0;
  for (double y : strength)
    mean += y;
  mean /= strength.size();
  double ssr = 0, sst = 0;
  for (std::size_t i = 0; i < strength.size(); ++i)
    {
      const double predicted = fit.prefactor * std::pow(contact_density[i], fit.exponent);
      ssr += (strength[i] - predicted) * (strength[i] - predicted);
      sst += (strength[i] - mean) * (strength[i] - mean);
    }
  EXPECT_NEAR(fit.r_squared, 1 - ssr / sst, 1e-12);
  EXPECT_GT(fit.r_squared, 0.9);
  EXPECT_LT(fit.r_squared, 1.0);
}

TEST(FitPowerLaw, ExponentIntervalCoverage)
{
  // As for the line: 500 sets of 5 points with lognormal scatter; the exponent's t-interval must
  // cover the truth in 92-98 % of them (binomial sd 1 %).
  NormalDeviates noise(11);
  const std::vector<double> x = evenly_spaced(0.6, 2.4, 5);
  int exponent_covered = 0;
  int prefactor_covered = 0;
  const int sets = 500;
  for (int set = 0; set < sets; ++set)
    {
      std::vector<double> y;
      for (double xi : x)
        y.push_back(ritter_h * std::pow(xi, ritter_kappa) * std::exp(0.2 * noise()));
      const PowerLawFit fit = fit_power_law(x, y);
      exponent_covered += fit.exponent_ci.contains(ritter_kappa);
      prefactor_covered += fit.prefactor_ci.contains(ritter_h);
    }
  EXPECT_GE(exponent_covered, 0.92 * sets);
  EXPECT_LE(exponent_covered, 0.98 * sets);
  EXPECT_GE(prefactor_covered, 0.92 * sets);
  EXPECT_LE(prefactor_covered, 0.98 * sets);
}

TEST(FitPowerLaw, RejectsBadData)
{
  EXPECT_THROW(fit_power_law({1, 2}, {1, 2}), CalibrationError);
  EXPECT_THROW(fit_power_law({0, 1, 2}, {1, 2, 3}), CalibrationError);
  EXPECT_THROW(fit_power_law({-1, 1, 2}, {1, 2, 3}), CalibrationError);
  EXPECT_THROW(fit_power_law({1, 2, 3}, {1, 0, 3}), CalibrationError);
  EXPECT_THROW(fit_power_law({1.5, 1.5, 1.5}, {1, 2, 3}), CalibrationError);
  EXPECT_THROW(fit_power_law({1, 2, 3}, {1, 2}), CalibrationError);
  try
    {
      fit_power_law({0.6, -0.25, 2.4}, {1, 2, 3}, 0.95, "sigma_0 vs nu_c");
      FAIL() << "negative x accepted";
    }
  catch (const CalibrationError &error)
    {
      const std::string message = error.what();
      EXPECT_NE(message.find("sigma_0 vs nu_c"), std::string::npos) << message;
      EXPECT_NE(message.find("-0.25"), std::string::npos) << message;
    }
}

TEST(Describe, SpreadOfM)
{
  // M of three microstructures, 0.6, 0.8 and 1.0 (Ritter et al.'s (2020) range and mean): mean 0.8, sample sd
  // sqrt((0.04 + 0 + 0.04)/2) = 0.2, 95 % interval 0.8 +- t_{0.975,2} 0.2/sqrt(3).
  const SampleStatistics statistics = describe({0.6, 0.8, 1.0}, 0.95, "M");
  EXPECT_NEAR(statistics.mean, 0.8, 1e-15);
  EXPECT_NEAR(statistics.standard_deviation, 0.2, 1e-15);
  EXPECT_DOUBLE_EQ(statistics.minimum, 0.6);
  EXPECT_DOUBLE_EQ(statistics.maximum, 1.0);
  EXPECT_EQ(statistics.n, 3);
  const double half_width = t_quantile_two_dof(0.975) * 0.2 / std::sqrt(3.0);
  EXPECT_NEAR(statistics.mean_ci.lower, 0.8 - half_width, 1e-12);
  EXPECT_NEAR(statistics.mean_ci.upper, 0.8 + half_width, 1e-12);

  EXPECT_THROW(describe({0.8}), CalibrationError);
  EXPECT_THROW(describe({0.8, std::numeric_limits<double>::quiet_NaN()}), CalibrationError);
}

TEST(ThicknessScaling, BobillierHomotheticLayers)
{
  // value/(h_ref/h): a layer half as thick as the 3 cm reference has half the value.
  EXPECT_DOUBLE_EQ(scale_to_thickness(1e5, 0.015, 0.03), 5e4);
  EXPECT_DOUBLE_EQ(scale_to_thickness(1e5, 0.03, 0.03), 1e5);
  EXPECT_THROW(scale_to_thickness(1e5, 0.0, 0.03), CalibrationError);
  EXPECT_THROW(scale_to_thickness(1e5, -0.01, 0.03), CalibrationError);
  EXPECT_THROW(scale_to_thickness(1e5, 0.01, 0.0), CalibrationError);

  // Bobillier et al.'s (2020) weak-layer modulus law fitted on exact data, used at 6 cm:
  // (7.3e4 + 0.014 * 5e7)/(0.03/0.06) = 7.73e5 * 2 = 1.546e6 Pa.
  const std::vector<double> particle_modulus = evenly_spaced(1e7, 9e7, 9);
  std::vector<double> macro_modulus;
  for (double e : particle_modulus)
    macro_modulus.push_back(bobillier_beta0 + bobillier_beta1 * e);
  MicroMacroLaw law;
  law.fit = fit_line(particle_modulus, macro_modulus);
  law.reference_thickness = 0.03;
  EXPECT_NEAR(law.predict(5e7, 0.06), 1.546e6, 1e-12 * 1.546e6);
  EXPECT_NEAR(law.predict(5e7, 0.03), law.fit(5e7), 1e-12 * 1e6);

  MicroMacroLaw without_reference;
  without_reference.fit = law.fit;
  EXPECT_THROW(static_cast<void>(without_reference.predict(5e7, 0.03)), CalibrationError);
}
