// Tests of the failed layer's friction from the friction tests (params/friction_calibration.h), on
// hand-made campaign tables:
//  * μ of each realization is its steady shear over normal stress, and the estimate is their mean
//    with the t-interval of the mean (n − 1 = 2 degrees of freedom: t_0.975 = 4.303, by hand);
//  * another microstructure's tests and a test that did not complete are left out (the latter
//    named), a campaign without friction tests gives no estimate;
//  * a test whose normal stress does not exceed the layer's compressive strength is refused,
//    naming the entry to raise; friction tests none of which slid are refused;
//  * readings that do not show friction are refused: the ratios of pit 65798's own-layer run (0.077,
//    -0.087, 0.197; mean 0.062, interval [-0.29, 0.42] by hand: s = 0.142, t s / sqrt 3 = 0.353).
#include "params/calibration_error.h"
#include "params/friction_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace
{
  using namespace anticrack::params;

  CampaignTest friction_test(int microstructure, int realization, double sigma, double tau,
                             const std::string &status = "completed")
  {
    CampaignTest t;
    t.id = "m" + std::to_string(microstructure) + "_r" + std::to_string(realization) + "_friction";
    t.status = status;
    t.microstructure = microstructure;
    t.realization = realization;
    t.steady_normal_stress = sigma;
    t.steady_shear_stress = tau;
    t.steady_stress_ratio = tau / sigma;
    return t;
  }

  CampaignData campaign_with(std::vector<CampaignTest> tests)
  {
    CampaignData c;
    c.file = "campaign.h5";
    c.microstructures.resize(2);
    c.friction_tests = std::move(tests);
    return c;
  }

  TEST(FrictionCalibration, MeanOfTheRealizationsWithItsTInterval)
  {
    // μ = 0.40, 0.43, 0.39 (the ratios measured at 20, 30 and 45 kPa, docs/physics.md).
    const CampaignData c = campaign_with({friction_test(0, 0, 3e4, 0.40 * 3e4), friction_test(0, 1, 3e4, 0.43 * 3e4),
                                          friction_test(0, 2, 3e4, 0.39 * 3e4), friction_test(1, 0, 3e4, 0.9 * 3e4),
                                          friction_test(0, 3, 3e4, 0.1 * 3e4, "failed")});
    const FrictionEstimate f = collapsed_friction(c, 0, 1e4, 0.95);
    ASSERT_TRUE(f.measured());
    EXPECT_EQ(f.friction_coefficient.n, 3);
    const double mean = (0.40 + 0.43 + 0.39) / 3;
    const double sd = std::sqrt((std::pow(0.40 - mean, 2) + std::pow(0.43 - mean, 2) + std::pow(0.39 - mean, 2)) / 2);
    EXPECT_NEAR(f.friction_coefficient.mean, mean, 1e-12);
    // t_{0.975, 2} = 4.30265 (tables).
    EXPECT_NEAR(f.friction_coefficient.mean_ci.upper - mean, 4.30265 * sd / std::sqrt(3.0), 1e-5);
    ASSERT_EQ(f.readings.size(), 3u);
    EXPECT_DOUBLE_EQ(f.readings[1].ratio, 0.43);
    ASSERT_EQ(f.excluded.size(), 1u);
    EXPECT_NE(f.excluded[0].find("m0_r3_friction: failed"), std::string::npos);
  }

  TEST(FrictionCalibration, NoFrictionTestsNoEstimate)
  {
    EXPECT_FALSE(collapsed_friction(campaign_with({}), 0, 1e4, 0.95).measured());
  }

  TEST(FrictionCalibration, AnIntactLayerIsRefusedNamingTheEntry)
  {
    const CampaignData c = campaign_with({friction_test(0, 0, 8e3, 0.5 * 8e3)});
    try
    {
      collapsed_friction(c, 0, 1e4, 0.95);
      FAIL() << "a test below the compressive strength was accepted";
    }
    catch (const CalibrationError &e)
    {
      const std::string what = e.what();
      EXPECT_NE(what.find("Campaign/Friction normal stress [Pa]"), std::string::npos) << what;
      EXPECT_NE(what.find("m0_r0_friction"), std::string::npos) << what;
      EXPECT_NE(what.find("10000"), std::string::npos) << what;
    }
  }

  TEST(FrictionCalibration, ReadingsThatDoNotShowFrictionAreRefused)
  {
    const std::vector<CampaignTest> swinging = {friction_test(0, 0, 4.4e4, 0.077 * 4.4e4),
                                                friction_test(0, 1, 4.4e4, -0.087 * 4.4e4),
                                                friction_test(0, 2, 4.5e4, 0.197 * 4.5e4)};
    try
    {
      collapsed_friction(campaign_with(swinging), 0, 2e4, 0.95);
      FAIL() << "readings whose interval reaches below 0 gave a friction coefficient";
    }
    catch (const CalibrationError &e)
    {
      const std::string message = e.what();
      EXPECT_NE(message.find("do not show sliding friction"), std::string::npos) << message;
      EXPECT_NE(message.find("m0_r1_friction -0.087"), std::string::npos) << message;
      EXPECT_NE(message.find("interval reaches -0.29"), std::string::npos) << message;
      EXPECT_NE(message.find("Campaign/Friction final shear strain"), std::string::npos) << message;
    }
    // One reading at or below zero, with no spread to judge: refused too; one above zero is kept.
    EXPECT_THROW(collapsed_friction(campaign_with({friction_test(0, 0, 3e4, -0.01 * 3e4)}), 0, 1e4, 0.95),
                 CalibrationError);
    EXPECT_NEAR(collapsed_friction(campaign_with({friction_test(0, 0, 3e4, 0.3 * 3e4)}), 0, 1e4, 0.95)
                  .friction_coefficient.mean,
                0.3, 1e-12);
  }

  TEST(FrictionCalibration, NoSteadySlidingIsRefused)
  {
    CampaignTest t = friction_test(0, 0, 3e4, 0.4 * 3e4);
    t.steady_stress_ratio = NAN;
    EXPECT_THROW(collapsed_friction(campaign_with({t}), 0, 1e4, 0.95), CalibrationError);
  }
} // namespace
