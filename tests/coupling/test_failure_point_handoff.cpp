// The hand-over of a DEM test's failure analysis (dem/scene/failure_analysis.h) to the campaign
// and of the campaign's table (dem/campaign/campaign_file.h) to the calibration: what a resumed
// campaign reads back from summary.json is what the test handed over in memory.
#include "dem/campaign/campaign_file.h"
#include "dem/scene/failure_analysis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace
{
  using namespace anticrack::dem;

  RecordedFailurePoint point(double scale)
  {
    RecordedFailurePoint f;
    f.step = 1200 * scale, f.time = 0.0123456789012345 * scale, f.p = 3456.78901234567 * scale;
    f.q = 2345.6789 * scale, f.sigma = 4567.1 * scale, f.tau = -123.456 * scale;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        f.love_stress(r, c) = (r + 1) * (c + 2) * 101.01 * scale;
    return f;
  }

  void expect_same(const RecordedFailurePoint &a, const RecordedFailurePoint &b)
  {
    EXPECT_EQ(a.step, b.step);
    EXPECT_EQ(a.time, b.time);
    EXPECT_EQ(a.p, b.p);
    EXPECT_EQ(a.q, b.q);
    EXPECT_EQ(a.sigma, b.sigma);
    EXPECT_EQ(a.tau, b.tau);
    EXPECT_EQ(a.love_stress, b.love_stress);
  }
} // namespace

TEST(FailureAnalysisRecord, SummaryJsonGivesBackWhatTheRunHandedOver)
{
  for (const ActuatorControl control :
       {ActuatorControl::force, ActuatorControl::shear_displacement, ActuatorControl::normal_displacement})
  {
    TestFailureAnalysis a;
    a.control = control;
    a.failure = point(1), a.peak_q = point(1.1), a.peak_loading = point(1.2);
    a.secant_modulus = 1.23456789e6, a.softening_ratio = 0.3141592653589793, a.flow_angle_deg = -87.654321;
    const nlohmann::ordered_json file = nlohmann::ordered_json::parse(failure_analysis_json(a).dump());
    const TestFailureAnalysis b = failure_analysis_from_json(file);
    EXPECT_TRUE(b.error.empty());
    EXPECT_EQ(b.control, control);
    expect_same(a.failure, b.failure);
    expect_same(a.peak_q, b.peak_q);
    ASSERT_TRUE(b.peak_loading);
    expect_same(*a.peak_loading, *b.peak_loading);
    EXPECT_EQ(b.secant_modulus, a.secant_modulus);
    EXPECT_EQ(b.softening_ratio, a.softening_ratio);
    EXPECT_EQ(b.flow_angle_deg, a.flow_angle_deg);
    EXPECT_TRUE(std::isnan(b.max_inertial_number)); // not in summary.json: from history.h5
  }
  TestFailureAnalysis failed;
  failed.error = "no run-away yet";
  const TestFailureAnalysis back =
    failure_analysis_from_json(nlohmann::ordered_json::parse(failure_analysis_json(failed).dump()));
  EXPECT_EQ(back.error, failed.error);
}

TEST(FailureAnalysisRecord, InertialNumberFromHalfTheFailureStressToFailure)
{
  const std::vector<double> step = {0, 10, 20, 30, 40}, q = {1, 60, 80, 100, 50}, inertial = {9, 1e-4, 3e-4, 2e-4, 7};
  EXPECT_EQ(max_inertial_number_before_failure(step, q, inertial, 30, 100), 3e-4);
  EXPECT_EQ(max_inertial_number_before_failure(step, q, inertial, 10, 100), 1e-4);
}

TEST(FailurePointTable, EveryColumnHasItsOwnNameAndMember)
{
  std::set<std::string> names;
  for (const FailurePointColumn &c : failure_point_columns())
  {
    EXPECT_TRUE(names.insert(c.name).second) << c.name;
    EXPECT_EQ((c.text != nullptr) + (c.number != nullptr) + (c.tensor != nullptr), 1) << c.name;
  }
  EXPECT_STREQ(failure_point_column(&FailurePointRow::sigma).name, "sigma");
  EXPECT_STREQ(failure_point_column(&FailurePointRow::love_stress).name, "love_stress");
  EXPECT_STREQ(failure_point_column(&FailurePointRow::test).name, "test");
  EXPECT_STREQ(failure_point_column(&FailurePointRow::layer_thickness).unit, "m");
}
