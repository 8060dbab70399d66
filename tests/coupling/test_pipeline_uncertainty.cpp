// The pipeline's first-order intervals (coupling/pipeline_uncertainty.h) on answers that are exactly
// linear in the parameters: the sensitivities, the standard deviation sqrt(g^T Sigma g) with the
// correlations, the variance shares, the dominant parameter, and "not linear" when a perturbed run
// changes the outcome or the interval of a positive answer reaches 0.
#include "coupling/pipeline_uncertainty.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

namespace
{
  using namespace anticrack;
  using Json = nlohmann::ordered_json;

  /// Two correlated parameters (standard errors 2 and 0.5, correlation -0.6) and one independent.
  coupling::UncertainParameters three_parameters()
  {
    coupling::UncertainParameters u;
    u.names = {"p0", "M", "E"};
    for (double fem::ContinuumMaterial::*entry : {&fem::ContinuumMaterial::p0, &fem::ContinuumMaterial::M,
                                                        &fem::ContinuumMaterial::youngs_modulus})
      u.value_in.push_back([entry](fem::MaterialFile &file) -> double & { return file.material.*entry; });
    u.value = Eigen::Vector3d(10, 2, 100);
    u.covariance = Eigen::Matrix3d::Zero();
    u.covariance(0, 0) = 4, u.covariance(1, 1) = 0.25, u.covariance(2, 2) = 9;
    u.covariance(0, 1) = u.covariance(1, 0) = -0.6 * 2 * 0.5;
    u.confidence = 0.95;
    return u;
  }

  /// The results of a run at parameters theta of the exact answer y = a . theta + 1 (in every key).
  Json linear_results(const Eigen::Vector3d &a, const Eigen::Vector3d &theta, const char *outcome = "End")
  {
    Json r{{"outcome", outcome}};
    for (const coupling::PstAnswer &answer : coupling::pst_answers())
      r[answer.key] = a.dot(theta) + 1;
    return r;
  }

  /// The runs with each parameter of `u` raised by one standard error, of the answer y = a . theta + 1.
  std::vector<Json> raised_runs(const coupling::UncertainParameters &u, const Eigen::Vector3d &a)
  {
    std::vector<Json> runs;
    for (int k = 0; k < 3; ++k)
    {
      Eigen::Vector3d theta = u.value;
      theta(k) += std::sqrt(u.covariance(k, k));
      runs.push_back(linear_results(a, theta));
    }
    return runs;
  }
} // namespace

TEST(PipelineUncertainty, LinearAnswersGetTheirExactStandardDeviationSharesAndDominantParameter)
{
  const coupling::UncertainParameters u = three_parameters();
  const Eigen::Vector3d a(0.01, 0.3, -0.002);
  const std::vector<Json> perturbed = raised_runs(u, a);
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
    arrested.push_back(linear_results(a, u.value, k == 1 ? "Arr" : "End"));
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

// A positive answer whose first-order interval reaches 0 is not linear over it: y = a . theta + 1 with
// a = (0.01, 1, -0.025) is 0.6 at the calibrated theta, Var = a^T Sigma a = 0.244 (sd 0.49), so the
// interval's lower end 0.6 - 1.96 sd lies below 0; M's standard error moves y most (0.5 against
// 0.02 and 0.075). The status says so and names M, and no interval is given.
TEST(PipelineUncertainty, AnIntervalReachingZeroIsNotLinear)
{
  const coupling::UncertainParameters u = three_parameters();
  const Eigen::Vector3d a(0.01, 1, -0.025);
  const std::vector<Json> perturbed = raised_runs(u, a);
  const Json base = linear_results(a, u.value);
  const Json out = coupling::linearised_intervals(u, base, perturbed, 0.01);
  const Json &cut = out["answers"]["critical_cut_length_m"];
  const double y0 = cut["value"].get<double>(), sd = cut["standard_deviation"].get<double>();
  ASSERT_LT(y0 - 1.959963984540054 * sd, 0) << "the case must reach below 0";
  const std::string status = cut["status"];
  EXPECT_EQ(status.rfind("not linear: the first-order interval reaches 0", 0), 0u) << status;
  EXPECT_NE(status.find("M + 1 standard error"), std::string::npos) << status;
  EXPECT_FALSE(cut.contains("interval"));
  EXPECT_EQ(cut["dominant_parameter"], "M");
}

TEST(PipelineUncertainty, AnElasticStagesCutCombinesGcsMappedIntervalWithEsLinearisedOneInQuadrature)
{
  // The energy release rate is rerun for E alone: its restriction keeps E's variance and drops the
  // surface's correlated block.
  const coupling::UncertainParameters u = three_parameters();
  const coupling::UncertainParameters only_E = coupling::restricted_to(u, {"E"});
  ASSERT_EQ(only_E.names, std::vector<std::string>{"E"});
  EXPECT_EQ(only_E.value(0), 100);
  EXPECT_EQ(only_E.covariance(0, 0), 9);
  EXPECT_EQ(coupling::restricted_to(u, {"M", "p0"}).covariance(0, 1), -0.6);

  // a_c = 0.3 m; G_c's interval maps onto [0.2, 0.5] m (asymmetric, as a_c(G_c) is concave);
  // E + 3 (one standard error) moves the cut by -0.01 m, so E's 95 % half-width is 1.96 x 0.01.
  const Eigen::Vector3d a(0, 0, -0.01 / 3);
  Eigen::Vector3d raised = u.value;
  raised(2) += 3;
  Json base = linear_results(a, u.value), perturbed = linear_results(a, raised);
  base["critical_cut_length_m"] = 0.3;
  perturbed["critical_cut_length_m"] = 0.3 - 0.01;
  const Json linearised = coupling::linearised_intervals(only_E, base, {perturbed}, 0.01);
  const Json mapped = {{"critical_cut_length_m", {0.2, 0.5}}, {"carries", "G_c"}};
  const Json c = coupling::combined_critical_cut_interval(mapped, linearised["answers"]["critical_cut_length_m"], 0.3);
  const double e = 1.959963984540054 * 0.01;
  EXPECT_NEAR(c["interval"][0].get<double>(), 0.3 - std::hypot(0.1, e), 1e-12);
  EXPECT_NEAR(c["interval"][1].get<double>(), 0.3 + std::hypot(0.2, e), 1e-12);
  EXPECT_EQ(c["dominant_parameter"], "G_c");
  EXPECT_NEAR(c["parameters"]["E"]["change_per_standard_error"].get<double>(), -0.01, 1e-12);

  // A G_c interval that runs beyond the cuts computed is not carried; without E's rerun, G_c's alone.
  const Json open = {{"critical_cut_length_m", {nullptr, 0.5}}, {"lower_note", "below the first midpoint"}};
  EXPECT_EQ(coupling::combined_critical_cut_interval(open, linearised["answers"]["critical_cut_length_m"], 0.3)["status"]
              .get<std::string>()
              .rfind("not carried", 0),
            0u);
  const Json alone = coupling::combined_critical_cut_interval(mapped, Json{{"status", "no value in the base run"}}, 0.3);
  EXPECT_EQ(alone["interval"], mapped["critical_cut_length_m"]);
}

// ξ, R and the lock-up strain come from the same compaction curves, one of each per realization: the
// covariance of their means is that of the paired values over n (here by hand), E's is its squared
// standard error alone, and the surface's block is the fit's, p0 scaled to snow units.
TEST(PipelineUncertainty, TheSofteningFromOneCurveCarriesTheCovarianceOfItsPairedRealizationValues)
{
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("anticrack_uncertain_parameters_" + std::to_string(::getpid()));
  fs::create_directories(dir);

  fem::MaterialFile dem;
  dem.material = {"layer", "invariants", 1000, 2e8, 0.2, 1e4, 0.4, 2.0, "collapse", 0.6, 0.6, 0.01};
  dem.provenance.fit_plane = std::string(fem::path_fit_plane) + ", lateral stress ratio 0.25 (periodic sides)";
  dem.collapse.lock_up_strain = 0.24, dem.collapse.lock_up_modulus = 1e7;
  dem.collapse.fracture_energy_density = 5, dem.collapse.collapse_energy_density = 2000;
  fem::MaterialFile snow = dem;
  const double S = 0.3; // the stress scale
  snow.material.p0 *= S, snow.material.youngs_modulus *= S;
  {
    std::ofstream(dir / "material.prm") << fem::material_file_text(dem);
    std::ofstream(dir / "material_snow.prm") << fem::material_file_text(snow);
  }
  const std::vector<double> xi = {0.5, 0.6, 0.7}, R = {0.65, 0.6, 0.55}, lock = {0.2, 0.24, 0.28}, E = {1.9e8, 2e8, 2.1e8};
  const auto statistics = [](const std::vector<double> &v) {
    const double mean = (v[0] + v[1] + v[2]) / 3;
    double ss = 0;
    for (double x : v)
      ss += (x - mean) * (x - mean);
    return Json{{"mean", mean}, {"standard_deviation", std::sqrt(ss / 2)}, {"samples", 3}, {"values", v}};
  };
  Json m;
  m["p_q_path_plane"]["models"]["cohesive_cam_clay"]["covariance"] = {{1e4, -2, 3}, {-2, 0.01, 0}, {3, 0, 0.04}};
  m["elastic"]["youngs_modulus_Pa"] = statistics(E);
  m["softening"] = {{"hardening_factor_xi", statistics(xi)}, {"residual_ratio", statistics(R)}, {"lock_up_strain", statistics(lock)}};
  Json summary;
  summary["calibration"]["microstructures"] = Json::array({m});
  std::ofstream(dir / "summary.json") << summary.dump();

  const coupling::UncertainParameters u = coupling::uncertain_parameters(dir);
  fs::remove_all(dir);
  ASSERT_EQ(u.names, (std::vector<std::string>{"p0", "beta", "M", "E", "xi", "R", "lock_up_strain"}));
  // By hand: deviations xi (-0.1, 0, 0.1), R (0.05, 0, -0.05), lock (-0.04, 0, 0.04): the covariance of
  // the means is sum(products) / ((n - 1) n) = sum / 6.
  EXPECT_NEAR(u.covariance(4, 4), 0.02 / 6, 1e-15);
  EXPECT_NEAR(u.covariance(4, 5), -0.01 / 6, 1e-15);
  EXPECT_NEAR(u.covariance(5, 4), -0.01 / 6, 1e-15);
  EXPECT_NEAR(u.covariance(4, 6), 0.008 / 6, 1e-15);
  EXPECT_NEAR(u.covariance(5, 6), -0.004 / 6, 1e-15);
  EXPECT_NEAR(u.covariance(6, 6), 0.0032 / 6, 1e-15);
  // ξ and R here are perfectly anticorrelated: the correlation is -1.
  EXPECT_NEAR(u.covariance(4, 5) / std::sqrt(u.covariance(4, 4) * u.covariance(5, 5)), -1, 1e-12);
  // E: (S x 1e7)^2 / 3 on the diagonal, nothing beside it.
  EXPECT_NEAR(u.covariance(3, 3), std::pow(S * 1e7, 2) / 3, 1e-6 * std::pow(S * 1e7, 2));
  for (Eigen::Index k : {0, 1, 2, 4, 5, 6})
    EXPECT_EQ(u.covariance(3, k), 0) << k;
  // The surface's block: p0's row and column scaled by S.
  EXPECT_NEAR(u.covariance(0, 0), 1e4 * S * S, 1e-9);
  EXPECT_NEAR(u.covariance(0, 1), -2 * S, 1e-12);
  EXPECT_NEAR(u.covariance(2, 2), 0.04, 1e-15);
  for (Eigen::Index a : {0, 1, 2})
    for (Eigen::Index b : {4, 5, 6})
      EXPECT_EQ(u.covariance(a, b), 0) << a << ", " << b;
}
