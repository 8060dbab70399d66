// The failed weak layer's friction coefficient from the friction tests (equations in the header).
#include "params/friction_calibration.h"

#include "params/calibration_error.h"
#include "params/elastic_calibration.h"
#include "util/format.h"

#include <cmath>

namespace anticrack::params
{
  FrictionEstimate collapsed_friction(const CampaignData &campaign, int m, double compressive_strength,
                                      double confidence)
  {
    const std::string where = campaign.file + ", microstructure " + std::to_string(m);
    FrictionEstimate estimate;
    std::vector<double> ratios;
    bool any = false;
    for (const CampaignTest &t : campaign.friction_tests)
    {
      if (t.microstructure != m)
        continue;
      any = true;
      if (!t.completed())
      {
        estimate.excluded.push_back(t.id + ": " + t.status);
        continue;
      }
      if (!(std::isfinite(t.steady_stress_ratio) && t.steady_normal_stress > 0))
      {
        estimate.excluded.push_back(t.id + ": no steady sliding recorded (the shear ended before its second half)");
        continue;
      }
      if (!(t.steady_normal_stress > compressive_strength))
        throw CalibrationError(where + ": friction test " + t.id + " slid at a normal stress of " +
                               format_number(t.steady_normal_stress) + " Pa, which does not exceed the layer's "
                               "compressive strength " + format_number(compressive_strength) +
                               " Pa: it sheared the intact layer, not the collapsed one. Raise Campaign/Friction "
                               "normal stress [Pa] above " + format_number(compressive_strength) + " Pa");
      estimate.readings.push_back({t.id, t.realization, t.steady_normal_stress, t.steady_shear_stress,
                                   t.steady_stress_ratio});
      ratios.push_back(t.steady_stress_ratio);
    }
    if (!any)
      return estimate;
    if (ratios.empty())
    {
      std::string reasons;
      for (const auto &e : estimate.excluded)
        reasons += "; " + e;
      throw CalibrationError(where + ": no friction test completed with a steady sliding" + reasons);
    }
    estimate.friction_coefficient = realization_statistics(ratios, confidence, where + " friction coefficient");
    // Steady sliding dissipates: the layer's shear stress opposes the sliding, μ > 0. Readings whose
    // mean is not positive beyond its interval have not shown friction: the tests did not slide
    // steadily over their window (a thin, wide specimen's base shear swung through zero,
    // docs/pipeline.md), and a μ near zero would let the FE's failed layer slide freely.
    const SampleStatistics &mu = estimate.friction_coefficient;
    if (!(mu.mean_ci.lower > 0)) // one reading: its interval is the value itself (realization_statistics)
    {
      std::string values;
      for (const FrictionReading &r : estimate.readings)
        values += (values.empty() ? "" : ", ") + r.test + " " + format_number(r.ratio, 3);
      throw CalibrationError(where + ": the friction tests do not show sliding friction: their steady shear over "
                             "normal stress (" + values + ") has a mean of " + format_number(mu.mean, 3) +
                             (mu.n > 1 ? " whose " + format_number(100 * confidence) + " % interval reaches " +
                                           format_number(mu.mean_ci.lower, 3)
                                       : std::string()) +
                             ", not above 0: the layer did not resist the sliding steadily over the window. Shear "
                             "further (Campaign/Friction final shear strain) or check the specimen's shape");
    }
    return estimate;
  }
} // namespace anticrack::params
