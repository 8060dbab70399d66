// Failure analysis of a finished run (the virtual lab's yield point, docs/physics.md §1.5): the history's
// Love-Weber stress, actuator motion and base stresses become a dem::TestHistory, and
// dem::analyse_failure picks the failure point (Ritter et al.'s (2020) kinetic-energy window, then max q), the
// peaks, the secant modulus, the softening ratio and the plastic flow angle. The result goes into
// summary.json.
#pragma once

#include "util/time_series.h"

#include <nlohmann/json.hpp>

namespace anticrack::dem
{
  /// Analysis of a clump-driven test (needs the clump and Love-Weber columns); `sample_height` [m]
  /// turns the clump's vertical displacement into the loading strain. Returns a JSON object; if the
  /// history does not allow the analysis (no clump, no run-away yet) it says why in "error".
  /// `shear_controlled`: a displacement-controlled simple shear test; failure is the peak of the
  /// base shear stress, the strain is the shear strain u_x / H.
  nlohmann::json analyse_test_history(const TimeSeries &history, double sample_height, bool shear_controlled = false);
} // namespace anticrack::dem
