#include "params/collapse_calibration.h"

#include "params/calibration_error.h"

#include <algorithm>
#include <cmath>

namespace anticrack::params
{
  CompactionReading read_compaction_test(const CampaignData &campaign, const CampaignTest &test,
                                         const double axial_modulus)
  {
    const TestHistory h = campaign.history(test); // strains u/h of the layer
    CompactionReading r;
    r.test = test.id;
    r.realization = test.realization;
    r.layer_thickness = test.layer_thickness;
    try
    {
      r.fit = dem::fit_compaction_curve(h.normal_strain, h.sigma, axial_modulus);
    }
    catch (const std::exception &e)
    {
      throw CalibrationError(campaign.file + ", compaction test " + test.id + ": " + e.what());
    }
    return r;
  }

  double CompactionRateCheck::largest() const
  {
    return std::max({std::abs(peak_stress), std::abs(residual_ratio), std::abs(plastic_strain),
                     std::abs(fracture_energy), std::abs(lock_up_strain)});
  }

  SofteningEstimate compaction_softening(const CampaignData &campaign, const int m, const double p0,
                                         const double bulk_modulus, const double axial_modulus,
                                         const double confidence,
                                         std::vector<CompactionReading> &readings,
                                         std::vector<CompactionRateCheck> &rate_checks)
  {
    const std::string where = campaign.file + ", microstructure " + std::to_string(m);
    std::vector<double> ratio, strain, xi, fracture, collapse, lock_strain, lock_modulus, peak;
    SofteningEstimate s;
    s.source = "compaction tests";
    readings.clear();
    for (const CampaignTest &t : campaign.compaction_tests)
    {
      if (t.microstructure != m)
        continue;
      if (!t.completed())
      {
        s.excluded.push_back(t.id + ": " + t.status);
        continue;
      }
      CompactionReading r = read_compaction_test(campaign, t, axial_modulus);
      const dem::CompactionCurveFit &f = r.fit;
      const double R = f.residual_ratio(), plastic = f.plastic_softening_strain();
      if (!(R > 0 && R < 1) || !(plastic > 0))
      {
        s.excluded.push_back(t.id + ": R = " + std::to_string(R) + ", plastic strain " + std::to_string(plastic));
        continue;
      }
      ratio.push_back(R), strain.push_back(plastic);
      xi.push_back(hardening_factor(p0, bulk_modulus, R, plastic));
      fracture.push_back(f.fracture_energy_density), collapse.push_back(f.collapse_energy_density);
      lock_strain.push_back(f.lock_up_strain), lock_modulus.push_back(f.lock_up_modulus);
      peak.push_back(f.peak_stress);
      readings.push_back(std::move(r));
    }
    if (xi.empty())
    {
      std::string reasons;
      for (const auto &e : s.excluded)
        reasons += "; " + e;
      throw CalibrationError(where + ": no compaction test softens to a residual stress 0 < R < 1 with a "
                             "positive plastic strain" + reasons);
    }
    s.residual_ratio = realization_statistics(ratio, confidence, where + " residual ratio");
    s.plastic_volumetric_strain = realization_statistics(strain, confidence, where + " plastic volumetric strain");
    s.hardening_factor = realization_statistics(xi, confidence, where + " hardening factor");
    s.fracture_energy_density = realization_statistics(fracture, confidence, where + " fracture energy");
    s.collapse_energy_density = realization_statistics(collapse, confidence, where + " collapse energy");
    s.lock_up_strain = realization_statistics(lock_strain, confidence, where + " lock-up strain");
    s.lock_up_modulus = realization_statistics(lock_modulus, confidence, where + " lock-up modulus");
    s.peak_stress = realization_statistics(peak, confidence, where + " compaction peak stress");

    // The rate check: each reading against its slower reference's.
    rate_checks.clear();
    for (const CampaignTest &ref : campaign.reference_tests)
    {
      const auto reading = std::find_if(readings.begin(), readings.end(),
                                        [&](const CompactionReading &r) { return r.test == ref.reference_for; });
      if (reading == readings.end() || !ref.completed())
        continue;
      const dem::CompactionCurveFit a = reading->fit, b = read_compaction_test(campaign, ref, axial_modulus).fit;
      const auto relative = [](double x, double reference) { return (reference - x) / reference; };
      CompactionRateCheck c;
      c.test = reading->test, c.reference = ref.id;
      c.peak_stress = relative(a.peak_stress, b.peak_stress);
      c.residual_ratio = relative(a.residual_ratio(), b.residual_ratio());
      c.plastic_strain = relative(a.plastic_softening_strain(), b.plastic_softening_strain());
      c.fracture_energy = relative(a.fracture_energy_density, b.fracture_energy_density);
      c.lock_up_strain = relative(a.lock_up_strain, b.lock_up_strain);
      rate_checks.push_back(c);
    }
    return s;
  }
} // namespace anticrack::params
