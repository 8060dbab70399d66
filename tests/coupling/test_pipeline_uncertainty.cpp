// The pipeline's first-order intervals (coupling/pipeline_uncertainty.h) on answers that are exactly
// linear in the parameters: the sensitivities, the standard deviation sqrt(g^T Sigma g) with the
// correlations, the variance shares, the dominant parameter, and "not linear" when a perturbed run
// changes the outcome.
#include "coupling/pipeline_uncertainty.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
  using namespace anticrack;
  using Json = nlohmann::ordered_json;

  /// Two correlated parameters (standard errors 2 and 0.5, correlation -0.6) and one independent.
  coupling::UncertainParameters three_parameters()
  {
    coupling::UncertainParameters u;
    u.names = {"p0", "M", "E"};
    u.value = Eigen::Vector3d(10, 2, 100);
    u.covariance = Eigen::Matrix3d::Zero();
    u.covariance(0, 0) = 4, u.covariance(1, 1) = 0.25, u.covariance(2, 2) = 9;
    u.covariance(0, 1) = u.covariance(1, 0) = -0.6 * 2 * 0.5;
    u.confidence = 0.95;
    return u;
  }

  /// The results of a run at parameters theta of the exact answer y = a . theta + 1 (in every key).
  Json linear_results(const Eigen::Vector3d &a, const Eigen::Vector3d &theta, const char *crack = "reached the column end")
  {
    Json r{{"crack", crack}};
    for (const coupling::PstAnswer &answer : coupling::pst_answers())
      r[answer.key] = a.dot(theta) + 1;
    return r;
  }
} // namespace

TEST(PipelineUncertainty, LinearAnswersGetTheirExactStandardDeviationSharesAndDominantParameter)
{
  const coupling::UncertainParameters u = three_parameters();
  const Eigen::Vector3d a(0.01, 0.3, -0.002);
  std::vector<Json> perturbed;
  for (int k = 0; k < 3; ++k)
  {
    Eigen::Vector3d theta = u.value;
    theta(k) += std::sqrt(u.covariance(k, k));
    perturbed.push_back(linear_results(a, theta));
  }
  const Json out = coupling::linearised_intervals(u, linear_results(a, u.value), perturbed, 0.01);
  // Var = a^T Sigma a by hand (Sigma_12 = -0.6 x 2 x 0.5).
  const double variance = 0.01 * 0.01 * 4 + 0.3 * 0.3 * 0.25 + 0.002 * 0.002 * 9 + 2 * 0.01 * 0.3 * (-0.6);
  for (const coupling::PstAnswer &answer : coupling::pst_answers())
  {
    const Json &r = out["answers"][answer.key];
    ASSERT_EQ(r["status"], "linearised") << answer.key;
    EXPECT_NEAR(r["standard_deviation"].get<double>(), std::sqrt(variance), 1e-12);
    EXPECT_NEAR(r["interval"][1].get<double>() - r["value"].get<double>(), 1.959963984540054 * std::sqrt(variance), 1e-9);
    EXPECT_NEAR(r["parameters"]["p0"]["change_per_standard_error"].get<double>(), 0.02, 1e-12);
    EXPECT_NEAR(r["parameters"]["M"]["change_per_standard_error"].get<double>(), 0.15, 1e-12);
    EXPECT_NEAR(r["parameters"]["E"]["change_per_standard_error"].get<double>(), -0.006, 1e-12);
    // The shares g_i (Sigma g)_i / Var add up to 1; M's own change is the largest.
    double sum = 0;
    for (const char *p : {"p0", "M", "E"})
      sum += r["parameters"][p]["variance_share"].get<double>();
    EXPECT_NEAR(sum, 1, 1e-12);
    EXPECT_NEAR(r["parameters"]["E"]["variance_share"].get<double>(), 0.002 * 0.002 * 9 / variance, 1e-12);
    EXPECT_EQ(r["dominant_parameter"], "M");
  }
}

TEST(PipelineUncertainty, AChangedOutcomeIsNotLinearisedAndAnUnmovedAnswerHasNoDominantParameter)
{
  const coupling::UncertainParameters u = three_parameters();
  const Eigen::Vector3d a(0.01, 0.3, -0.002), none(0, 0, 0);
  std::vector<Json> arrested, unmoved;
  for (int k = 0; k < 3; ++k)
  {
    arrested.push_back(linear_results(a, u.value, k == 1 ? "arrested" : "reached the column end"));
    unmoved.push_back(linear_results(none, u.value));
  }
  const Json out = coupling::linearised_intervals(u, linear_results(a, u.value), arrested, 0.01);
  const std::string status = out["answers"]["critical_cut_length_m"]["status"];
  EXPECT_EQ(status.rfind("not linear", 0), 0u) << status;
  EXPECT_NE(status.find("M + 1 standard error"), std::string::npos) << status;
  EXPECT_FALSE(out["answers"]["critical_cut_length_m"].contains("interval"));

  const Json flat = coupling::linearised_intervals(u, linear_results(none, u.value), unmoved, 0.01);
  EXPECT_EQ(flat["answers"]["propagation_speed_m_per_s"]["standard_deviation"].get<double>(), 0.0);
  EXPECT_EQ(flat["answers"]["propagation_speed_m_per_s"]["dominant_parameter"].get<std::string>().rfind("none", 0), 0u);
}
