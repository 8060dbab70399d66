#include "params/elastic_calibration.h"

#include "dem/lab/failure_point.h"
#include "params/calibration_error.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

namespace anticrack::params
{
  namespace
  {
    /// The completed tests of microstructure m at loading angle ψ, by realization.
    std::map<int, const CampaignTest *> tests_at(const CampaignData &campaign, int m, double angle_deg)
    {
      std::map<int, const CampaignTest *> found;
      for (const auto &t : campaign.tests)
        if (t.microstructure == m && t.completed() && std::abs(t.loading_angle_deg - angle_deg) < 1e-6)
          found[t.realization] = &t;
      return found;
    }

    dem::Index peak_index(const std::vector<double> &values)
    {
      return static_cast<dem::Index>(std::max_element(values.begin(), values.end()) - values.begin());
    }

    struct IsotropicConstants
    {
      double youngs_modulus, poisson_ratio, bulk_modulus;
    };

    /// E, ν, K of an isotropic solid from the axial modulus (constrained if `confined`, else Young's)
    /// and the shear modulus G; with a given ν, E from the axial modulus alone.
    IsotropicConstants isotropic_constants(double axial, double G, bool confined, std::optional<double> given_nu)
    {
      if (given_nu)
      {
        // nu given: E from the axial modulus alone (M = E (1 - nu)/((1 + nu)(1 - 2 nu)) if confined).
        const double nu = *given_nu;
        const double E = confined ? axial * (1 + nu) * (1 - 2 * nu) / (1 - nu) : axial;
        return {E, nu, E / (3.0 * (1.0 - 2.0 * nu))};
      }
      if (confined)
      {
        const double K = axial - 4.0 * G / 3.0;
        return {9.0 * K * G / (3.0 * K + G), (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G)), K};
      }
      const double nu = axial / (2.0 * G) - 1.0;
      return {axial, nu, axial / (3.0 * (1.0 - 2.0 * nu))};
    }

  } // namespace

  SampleStatistics realization_statistics(const std::vector<double> &values, double confidence, const std::string &what)
  {
    if (values.size() >= 2)
      return describe(values, confidence, what);
    SampleStatistics s;
    s.mean = s.minimum = s.maximum = values.at(0);
    s.mean_ci = {values[0], values[0]};
    s.confidence = confidence;
    s.n = 1;
    s.values = values;
    return s;
  }

  ElasticConstants elastic_constants(const CampaignData &campaign, int m, double confidence,
                                     std::optional<double> given_poisson_ratio)
  {
    const auto compression = tests_at(campaign, m, 0.0), shear = tests_at(campaign, m, 90.0);
    const std::string where = campaign.file + ", microstructure " + std::to_string(m);
    if (compression.empty() || shear.empty())
      throw CalibrationError(where + ": the elastic constants need completed tests at loading angles 0 deg "
                             "(compression) and 90 deg (shear); add them to Campaign/Loading angles [deg]");
    ElasticConstants c;
    c.laterally_confined = campaign.microstructures.at(m).laterally_periodic;
    c.poisson_ratio_given = given_poisson_ratio.has_value();
    if (given_poisson_ratio && !(*given_poisson_ratio > -1 && *given_poisson_ratio < 0.5))
      throw CalibrationError("the given Poisson's ratio " + std::to_string(*given_poisson_ratio) +
                             " is not in (-1, 0.5)");
    std::vector<double> axial, shear_moduli, young, poisson, bulk, k0;
    for (const auto &[r, compression_test] : compression)
    {
      const auto s = shear.find(r);
      if (s == shear.end())
        continue;
      const TestHistory h = campaign.history(*s->second);
      const double G = dem::secant_modulus(h.shear_strain, h.tau, peak_index(h.tau), 0.7);
      const TestHistory ch = campaign.history(*compression_test);
      const double M = dem::secant_modulus(ch.normal_strain, ch.sigma, peak_index(ch.sigma), 0.7);
      const auto [E, nu, K] = isotropic_constants(M, G, c.laterally_confined, given_poisson_ratio);
      if (!(K > 0) || !(nu > -1.0 && nu < 0.5) || !(G > 0))
        throw CalibrationError(where + ", tests " + compression_test->id + " and " + s->second->id +
                               ": inadmissible elastic constants (axial modulus " + std::to_string(M) +
                               " Pa, shear modulus " + std::to_string(G) + " Pa give K = " + std::to_string(K) +
                               " Pa, nu = " + std::to_string(nu) + "; need K > 0 and -1 < nu < 0.5): the "
                               "specimen does not respond like an isotropic solid (e.g. the columns of a "
                               "ballistic deposit, stiff in compression, soft in shear); give the Poisson's "
                               "ratio (--poisson-ratio) to take E from the axial modulus alone");
      axial.push_back(M), shear_moduli.push_back(G), young.push_back(E), poisson.push_back(nu), bulk.push_back(K);

      if (c.laterally_confined)
      {
        // K0 in the elastic range: at the first sample where σ reaches 35 % of its peak (half of the
        // secant modulus' 70 %, well before the bond breakage that precedes the peak).
        const double target = 0.35 * ch.sigma[peak_index(ch.sigma)];
        const auto k = static_cast<std::size_t>(
          std::find_if(ch.sigma.begin(), ch.sigma.end(), [&](double v) { return v >= target; }) - ch.sigma.begin());
        const double ratio = 0.5 * (ch.love_xx[k] + ch.love_yy[k]) / ch.love_zz[k];
        k0.push_back(ratio / (1.0 + ratio));
      }
    }
    if (axial.empty())
      throw CalibrationError(where + ": no realization has completed tests at both 0 and 90 deg");
    c.axial_modulus = realization_statistics(axial, confidence, where + " axial modulus");
    c.shear_modulus = realization_statistics(shear_moduli, confidence, where + " shear modulus");
    c.youngs_modulus = realization_statistics(young, confidence, where + " Young's modulus");
    c.poisson_ratio = realization_statistics(poisson, confidence, where + " Poisson's ratio");
    c.bulk_modulus = realization_statistics(bulk, confidence, where + " bulk modulus");
    if (!k0.empty())
      c.k0_poisson_ratio = realization_statistics(k0, confidence, where + " K0 Poisson's ratio");
    const auto [E, nu, K] =
      isotropic_constants(c.axial_modulus.mean, c.shear_modulus.mean, c.laterally_confined, given_poisson_ratio);
    if (!(K > 0) || !(nu > -1.0 && nu < 0.5))
      throw CalibrationError(where + ": the mean axial modulus " + std::to_string(c.axial_modulus.mean) +
                             " Pa and shear modulus " + std::to_string(c.shear_modulus.mean) + " Pa give K = " +
                             std::to_string(K) + " Pa, nu = " + std::to_string(nu) +
                             "; need K > 0 and -1 < nu < 0.5");
    c.continuum_youngs_modulus = E, c.continuum_poisson_ratio = nu, c.continuum_bulk_modulus = K;
    return c;
  }

  double hardening_factor(double p0, double bulk_modulus, double residual_ratio, double plastic_volumetric_strain)
  {
    return (std::asinh(p0 / bulk_modulus) - std::asinh(residual_ratio * p0 / bulk_modulus)) /
           plastic_volumetric_strain;
  }

  SofteningEstimate collapse_softening(const CampaignData &campaign, int m, double p0, double bulk_modulus,
                                       double axial_modulus, double confidence)
  {
    const std::string where = campaign.file + ", microstructure " + std::to_string(m);
    std::vector<double> ratio, strain, xi;
    std::vector<std::string> excluded;
    for (const auto &[r, t] : tests_at(campaign, m, 0.0))
    {
      const TestHistory h = campaign.history(*t);
      const auto peak = static_cast<std::size_t>(peak_index(h.sigma));
      if (static_cast<dem::Index>(h.sigma.size() - 1 - peak) < dem::min_post_peak_samples)
      {
        excluded.push_back(t->id + ": the history ends at the peak");
        continue;
      }
      const double R = dem::softening_ratio(h.sigma, static_cast<dem::Index>(peak)); // docs/physics.md §1.5
      const double residual = R * h.sigma[peak];
      std::size_t k = peak;
      while (k < h.sigma.size() && h.sigma[k] > residual + 1e-9 * h.sigma[peak]) // round-off of R times the peak
        ++k;
      // The falling stress gives back elastic strain (σ_peak − σ_res)/M: the plastic strain is the
      // total strain plus it.
      const double plastic = k < h.sigma.size() ? (h.normal_strain[k] - h.normal_strain[peak]) +
                                                    (h.sigma[peak] - residual) / axial_modulus :
                                                  0.0;
      if (!(R > 0 && R < 1) || !(plastic > 0))
      {
        excluded.push_back(t->id + ": R = " + std::to_string(R) + ", plastic strain " + std::to_string(plastic) +
                           (k < h.sigma.size() ? "" : " (never back at the residual stress)"));
        continue;
      }
      ratio.push_back(R), strain.push_back(plastic);
      xi.push_back(hardening_factor(p0, bulk_modulus, R, plastic));
    }
    if (xi.empty())
    {
      std::string reasons;
      for (const auto &e : excluded)
        reasons += "; " + e;
      throw CalibrationError(where + ": no compression test (0 deg) softens to a residual stress 0 < R < 1 "
                             "with a positive plastic strain" + reasons +
                             "; run the tests further past the peak (DEM/Loading/Stop strain)");
    }
    SofteningEstimate s;
    s.source = "load-controlled post-peak";
    s.residual_ratio = realization_statistics(ratio, confidence, where + " residual ratio");
    s.plastic_volumetric_strain = realization_statistics(strain, confidence, where + " plastic volumetric strain");
    s.hardening_factor = realization_statistics(xi, confidence, where + " hardening factor");
    s.excluded = excluded;
    return s;
  }
} // namespace anticrack::params
