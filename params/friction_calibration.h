// The failed weak layer's friction coefficient from the campaign's friction tests (Campaign/Friction
// normal stress [Pa]; dem/lab/simple_shear.h): per realization, the collapsed layer's simple shear at
// constant normal stress, whose steady sliding (the base's mean reactions over the second half of
// the shear strain) gives
//   μ = τ_steady / σ_steady,
// then the mean with its t-interval over the realizations. It is what the FE's failed layer carries
// on its plane, |τ| <= μ σ_n (fem/material/collapsed_layer_friction.h). A test whose normal stress
// does not exceed the layer's compressive strength (the compaction tests' peak, else the ψ = 0
// tests') sheared the intact layer, not the collapsed one: the calibration refuses it, naming the
// entry to raise.
#pragma once

#include "params/campaign_data.h"
#include "params/regression.h"

#include <string>
#include <vector>

namespace anticrack::params
{
  /// One friction test as the calibration read it.
  struct FrictionReading
  {
    std::string test;
    int realization = 0;
    double normal_stress = 0; ///< σ_steady [Pa], compression positive
    double shear_stress = 0;  ///< τ_steady [Pa]
    double ratio = 0;         ///< μ of this realization
  };

  struct FrictionEstimate
  {
    SampleStatistics friction_coefficient; ///< μ over the realizations; n = 0: no friction tests
    std::vector<FrictionReading> readings;
    std::vector<std::string> excluded;     ///< tests not used, "id: why"
    [[nodiscard]] bool measured() const { return friction_coefficient.n > 0; }
  };

  /// μ of microstructure `m` from campaign.friction_tests (none: an estimate with n = 0). Throws
  /// CalibrationError when a test's steady normal stress does not exceed `compressive_strength` [Pa]
  /// (the layer did not collapse: names Campaign/Friction normal stress [Pa] and the value it must
  /// exceed), when friction tests exist but none completed with a steady sliding, or when the
  /// readings do not show friction (their mean, or the lower end of its interval, is not above 0).
  FrictionEstimate collapsed_friction(const CampaignData &campaign, int m, double compressive_strength,
                                      double confidence);
} // namespace anticrack::params
