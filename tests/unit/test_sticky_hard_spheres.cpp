// Percus-Yevick relations of sticky hard spheres (dem/sticky_hard_spheres.h) against the reference
// values of PHYSICS.md §1.4 and against their own inverse.

#include "dem/sticky_hard_spheres.h"
#include "dem/types.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace anticrack::dem;

// PHYSICS.md §1.4 quotes z = 2.74 at (phi, tau) = (0.3, 0.2) and z = 5.84 at (0.5, 0.1), to the
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
