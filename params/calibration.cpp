#include "params/calibration.h"

#include "params/calibration_error.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <sstream>

namespace anticrack::params
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    constexpr double degree = pi / 180.0;
    constexpr int band_angles = 361;

    double mean_of(const std::vector<CampaignTest> &tests, double CampaignTest::*member)
    {
      double sum = 0;
      for (const auto &t : tests)
        sum += t.*member;
      return sum / static_cast<double>(tests.size());
    }

    /// Refuses what no fit can answer, before any fitting (messages name the file, microstructure,
    /// what is missing and what would do).
    void check_microstructure_data(const std::vector<CampaignTest> &tests, const std::string &where)
    {
      const std::size_t needed = 4; // three surface parameters + the noise variance
      if (tests.size() < needed)
        throw CalibrationError(where + ": " + std::to_string(tests.size()) +
                               " completed tests, at least 4 are needed to fit the 3 parameters (p0, beta, M) "
                               "with a residual; run more loading angles or realizations");
      std::set<double> angles;
      for (const auto &t : tests)
        angles.insert(t.loading_angle_deg);
      if (angles.size() < 3)
        throw CalibrationError(where + ": all failure points lie at " + std::to_string(angles.size()) +
                               " loading angle(s); a yield surface needs at least 3 distinct angles between "
                               "0 (compression) and 180 deg (tension)");
      const bool tensile = std::any_of(tests.begin(), tests.end(), [](const CampaignTest &t) { return t.sigma < 0; });
      if (!tensile)
        throw CalibrationError(where + ": no tensile failure point (every base normal stress sigma >= 0); the "
                               "tensile tip -beta p0 would be an extrapolation; add loading angles above 90 deg");
    }

    /// Why the Cam-Clay fit of `c` does not determine the surface, or "" (see calibration.h).
    std::string undetermined_cam_clay(const PlaneCalibration &c)
    {
      double largest = 0, smallest_angle = pi, largest_angle = 0;
      for (const StressPoint &point : c.points)
      {
        largest = std::max(largest, polar_radius(point));
        smallest_angle = std::min(smallest_angle, polar_angle(point));
        largest_angle = std::max(largest_angle, polar_angle(point));
      }
      const CamClaySurface p = c.cam_clay_surface();
      const double limit = tip_extrapolation_limit * largest;
      std::ostringstream why;
      why.precision(3);
      if (!c.cam_clay().identifiable)
        why << "the covariance of the fit is singular";
      else if (p.p0 > limit || p.beta * p.p0 > limit)
        why << "the fitted tips (p0 = " << p.p0 << " Pa, -beta p0 = " << -p.beta * p.p0 << " Pa) lie more than "
            << tip_extrapolation_limit << " times the largest failure stress (" << largest
            << " Pa) from the origin: the points (polar angles " << smallest_angle / degree << "-"
            << largest_angle / degree << " deg) do not bend over towards the tips";
      return why.str();
    }

    PlaneCalibration fit_plane(StressPlane plane, const std::vector<CampaignTest> &tests, const TestPath &path,
                               const CalibrationOptions &options, const std::string &where)
    {
      PlaneCalibration c;
      c.plane = plane;
      for (const auto &t : tests)
      {
        // Shear is a magnitude in both planes: q >= 0 by definition, τ's sign only says along ±x.
        const auto factor = options.path_peak_factors.find(t.id);
        const double peak_factor = factor == options.path_peak_factors.end() ? 1.0 : factor->second;
        c.points.push_back(plane == StressPlane::base_stresses ? StressPoint{t.sigma, std::abs(t.tau)} :
                           plane == StressPlane::invariants    ? StressPoint{t.p, t.q} :
                                                                 path.invariants(t.sigma / peak_factor, t.tau / peak_factor));
        c.realizations.push_back(t.realization);
      }
      EnvelopeFitOptions fit_options;
      fit_options.confidence = options.confidence;
      fit_options.bootstrap_samples = options.bootstrap_samples;
      fit_options.seed = options.seed;
      c.models = all_envelope_kinds();
      for (const EnvelopeKind kind : c.models)
      {
        const auto model = make_envelope(kind);
        check_envelope_data(c.points, model->n_parameters(), where + ", " + plane_id(plane) + " plane");
        c.fits.push_back(fit_envelope(*model, c.points, c.realizations, fit_options));
        c.bands.push_back(envelope_band(*model, c.fits.back(), band_angles));
      }
      for (std::size_t k = 1; k < c.fits.size(); ++k)
        if (c.fits[k].aicc < c.fits[c.best_by_aicc].aicc)
          c.best_by_aicc = k;
      c.cam_clay_not_determined = undetermined_cam_clay(c);
      return c;
    }

    /// The DEM's (σ_xx + σ_yy)/(2 σ_zz) of the Love–Weber stress at failure over the tests with
    /// |σ| >= half the largest |σ| of the microstructure (the lateral ratio of shear-dominated tests
    /// is a ratio of small numbers).
    SampleStatistics lateral_stress_ratio_at_failure(const std::vector<CampaignTest> &tests, double confidence,
                                                     const std::string &where)
    {
      double largest = 0;
      for (const auto &t : tests)
        largest = std::max(largest, std::abs(t.sigma));
      std::vector<double> ratios;
      for (const auto &t : tests)
        if (std::abs(t.sigma) >= 0.5 * largest && t.love_stress[8] != 0)
          ratios.push_back(0.5 * (t.love_stress[0] + t.love_stress[4]) / t.love_stress[8]);
      if (ratios.size() < 2)
        return {};
      return describe(ratios, confidence, where + " lateral stress ratio at failure");
    }

    /// Why no isotropic surface on the tests' paths follows the failure points, or "" (calibration.h:
    /// the chord test of stress_path.h on the (σ, τ) fit's strengths, then path_misfit_factor).
    std::string isotropic_misfit(const MicrostructureCalibration &c)
    {
      const double base_rmse = c.base_plane.cam_clay().rmse, path_rmse = c.path_plane.cam_clay().rmse;
      // The (σ, τ) fit's strengths in compression, shear (at σ = 0) and tension.
      const CamClaySurface s = c.base_plane.cam_clay_surface();
      const double shear = s.M * s.p0 * std::sqrt(s.beta / (1 + 2 * s.beta));
      const double deficit = chord_shear_deficit(c.path, s.p0, shear, -s.beta * s.p0);
      const double shear_ratio = s.M / std::sqrt(1 + 2 * s.beta), least = least_cam_clay_shear_ratio(c.path);
      if (shear_ratio > least && !(deficit > 0) && path_rmse <= path_misfit_factor * base_rmse + path_misfit_margin)
        return "";
      std::ostringstream why;
      why.precision(3);
      why << "no isotropic invariant-plane surface fails where the DEM failed on the tests' paths ("
          << (c.path.laterally_confined ? "periodic sides, lateral stress ratio " : "open sides, lateral stress ratio ")
          << c.path.lateral_stress_ratio() << "). The (sigma, tau) fit's strengths are " << s.p0
          << " Pa in compression, " << shear << " Pa in shear and " << s.beta * s.p0 << " Pa in tension";
      if (!(shear_ratio > least))
        why << "; its peak shear strength over half its compressive-tensile range, M/sqrt(1 + 2 beta) = "
            << shear_ratio << ", is at most " << least << " = (1 - k)/sqrt(3), the least any cohesive Cam-Clay "
            << "surface of the invariants has on these paths (a uniaxial load there already carries q = (1 - k) "
            << "sigma; params/stress_path.h)";
      if (deficit > 0)
        why << "; on the paths the shear point lies " << 100 * deficit << " % below the chord between the "
            << "uniaxial points, so no convex surface reaches it (the layer is weaker in shear than an "
            << "isotropic material of its uniaxial strengths can be: an anisotropic microstructure, or too "
            << "few or too scattered points)";
      why << ". The cohesive Cam-Clay fit of the FE point misses the failure points by RMSE " << 100 * path_rmse
          << " % where the (sigma, tau) fit misses them by " << 100 * base_rmse << " %. "
          << (c.path.laterally_confined ? "" : "Calibrate a laterally periodic specimen of the layer, or add ")
          << (c.path.laterally_confined ? "Add" : "add")
          << " realizations and loading angles (if the strengths' scatter is the cause), or model the layer with a "
             "material the FE solver does not have yet (a yield surface on the layer-plane traction)";
      return why.str();
    }

    FlowRuleAnalysis analyse_flow_rule(const std::vector<CampaignTest> &tests, const CamClaySurface &surface,
                                       double confidence)
    {
      FlowRuleAnalysis f;
      for (const auto &t : tests)
      {
        if (!std::isfinite(t.flow_angle_deg))
        {
          f.excluded.push_back(t.id);
          continue;
        }
        const double psi = t.loading_angle_deg * degree, theta = t.flow_angle_deg * degree;
        const NormalisedStress n = normalise(t.sigma, std::abs(t.tau), surface);
        f.loading_angle.push_back(psi);
        f.flow_angle.push_back(theta);
        f.sigma_star.push_back(n.sigma);
        f.tau_star.push_back(n.tau);
        f.psi_star.push_back(normalised_loading_angle(psi, surface));
        f.theta_star.push_back(normalised_flow_angle(theta, surface));
      }
      f.transition_predicted = transition_loading_angle(surface);
      if (f.psi_star.size() < 3)
      {
        f.associativity_note = std::to_string(f.psi_star.size()) + " tests with a finite flow angle: the associativity "
                               "needs at least 3";
        f.transition_observed_note = f.associativity_note;
        return f;
      }
      f.associativity = measure_associativity(f.psi_star, f.theta_star, confidence);
      try
      {
        f.transition_observed = observed_transition_angle(f.loading_angle, f.flow_angle);
      }
      catch (const CalibrationError &e)
      {
        f.transition_observed_note = e.what();
      }
      return f;
    }

    /// Distinct values (relative tolerance 1e-9), for deciding whether a relation across
    /// microstructures can be fitted.
    std::size_t distinct(std::vector<double> values)
    {
      std::sort(values.begin(), values.end());
      std::size_t count = 0;
      for (std::size_t k = 0; k < values.size(); ++k)
        if (k == 0 || std::abs(values[k] - values[k - 1]) > 1e-9 * std::abs(values[k]))
          ++count;
      return count;
    }
  } // namespace

  std::string plane_id(StressPlane plane)
  {
    switch (plane)
    {
      case StressPlane::base_stresses:
        return "sigma_tau";
      case StressPlane::invariants:
        return "p_q";
      case StressPlane::path_invariants:
        break;
    }
    return "p_q_path";
  }

  const PlaneCalibration &MicrostructureCalibration::plane(StressPlane which) const
  {
    switch (which)
    {
      case StressPlane::base_stresses:
        return base_plane;
      case StressPlane::invariants:
        return invariant_plane;
      case StressPlane::path_invariants:
        break;
    }
    return path_plane;
  }

  const EnvelopeFit &PlaneCalibration::cam_clay() const
  {
    const auto k = std::find(models.begin(), models.end(), EnvelopeKind::cohesive_cam_clay) - models.begin();
    return fits.at(static_cast<std::size_t>(k));
  }

  CamClaySurface PlaneCalibration::cam_clay_surface() const { return params::cam_clay_surface(cam_clay().parameters); }

  CamClaySurfaceInterval PlaneCalibration::cam_clay_interval() const
  {
    return {params::cam_clay_surface(cam_clay().ci_lower), params::cam_clay_surface(cam_clay().ci_upper)};
  }

  Calibration calibrate(const CampaignData &campaign, const CalibrationOptions &options)
  {
    if (!(options.confidence > 0 && options.confidence < 1))
      throw CalibrationError("confidence level " + std::to_string(options.confidence) + " is not in (0, 1)");
    if (options.bootstrap_samples < 0)
      throw CalibrationError("bootstrap samples " + std::to_string(options.bootstrap_samples) + " < 0");
    Calibration result;
    result.campaign = campaign;
    result.options = options;

    // Every microstructure's data is checked before anything is fitted.
    std::vector<std::vector<CampaignTest>> tests_of(campaign.microstructures.size());
    std::vector<std::vector<std::string>> left_out_of(campaign.microstructures.size());
    for (const auto &t : campaign.tests)
    {
      const auto m = static_cast<std::size_t>(t.microstructure);
      if (!t.completed())
        left_out_of[m].push_back(t.id + ": " + t.status);
      else if (!(std::isfinite(t.sigma) && std::isfinite(t.p) && std::isfinite(t.q)))
        left_out_of[m].push_back(t.id + ": completed without a failure point");
      else
        tests_of[m].push_back(t);
    }
    for (std::size_t m = 0; m < tests_of.size(); ++m)
    {
      std::string left_out;
      for (const std::string &t : left_out_of[m])
        left_out += (left_out.empty() ? ", tests left out: " : "; ") + t;
      check_microstructure_data(tests_of[m], campaign.file + ", microstructure " + std::to_string(m) + " (" +
                                               campaign.microstructures[m].label + ")" + left_out);
    }

    for (std::size_t m = 0; m < tests_of.size(); ++m)
    {
      const std::string where = campaign.file + ", microstructure " + std::to_string(m);
      MicrostructureCalibration c;
      c.index = static_cast<int>(m);
      c.material = campaign.microstructures[m];
      c.tests = tests_of[m];
      c.tests_left_out = left_out_of[m];
      std::set<int> realizations;
      for (const auto &t : c.tests)
        realizations.insert(t.realization);
      c.realizations.assign(realizations.begin(), realizations.end());
      c.solid_fraction = mean_of(c.tests, &CampaignTest::solid_fraction);
      c.coordination = mean_of(c.tests, &CampaignTest::coordination);
      if (!(c.solid_fraction > 0 && c.solid_fraction < 1) || !(c.coordination > 0))
        throw CalibrationError(where + ": the campaign records solid fraction " + std::to_string(c.solid_fraction) +
                               " and coordination " + std::to_string(c.coordination) +
                               " for the samples; the density and the contact density need 0 < phi < 1 and z > 0");
      c.contact_density = c.solid_fraction * c.coordination; // ν_c = z φ (Ritter et al. 2020)
      c.layer_thickness = mean_of(c.tests, &CampaignTest::layer_thickness);
      c.grain_diameter = mean_of(c.tests, &CampaignTest::particle_diameter); // NaN before format 4
      c.density = c.solid_fraction * c.material.particle_density;

      // The FE elasticity first: it sets the lateral stresses of the tests' paths (stress_path.h).
      c.elastic = elastic_constants(campaign, c.index, options.confidence, options.poisson_ratio);
      c.path = TestPath{c.material.laterally_periodic, c.elastic.continuum_poisson_ratio};
      c.lateral_stress_ratio_at_failure = lateral_stress_ratio_at_failure(c.tests, options.confidence, where);
      c.base_plane = fit_plane(StressPlane::base_stresses, c.tests, c.path, options, where);
      c.invariant_plane = fit_plane(StressPlane::invariants, c.tests, c.path, options, where);
      c.path_plane = fit_plane(StressPlane::path_invariants, c.tests, c.path, options, where);
      // A surface that cannot follow the points first: its fit may also be undetermined, but the
      // misfit says why.
      const std::string misfit = isotropic_misfit(c);
      const PlaneCalibration &fe = c.material_plane();
      if (!misfit.empty())
        c.material_refused = where + ": " + misfit;
      else if (!fe.cam_clay_not_determined.empty())
        c.material_refused = where + ", " + plane_id(fe.plane) + " plane (the FE point on the tests' paths): the "
                             "cohesive Cam-Clay fit does not determine the surface for the material file: " +
                             fe.cam_clay_not_determined + ". Add loading angles near 0 and 180 deg, or realizations";
      if (!c.material_refused.empty() && campaign.microstructures.size() == 1)
        throw CalibrationError(c.material_refused);
      c.flow_rule = analyse_flow_rule(c.tests, c.base_plane.cam_clay_surface(), options.confidence);
      if (!c.material_refused.empty())
      {
        c.softening.source = "not estimated: no material for this microstructure";
        result.microstructures.push_back(std::move(c));
        continue;
      }
      const bool has_compaction_tests =
        std::any_of(campaign.compaction_tests.begin(), campaign.compaction_tests.end(),
                    [&](const CampaignTest &t) { return t.microstructure == c.index; });
      c.softening =
        has_compaction_tests ?
          compaction_softening(campaign, c.index, fe.cam_clay_surface().p0, c.elastic.continuum_bulk_modulus,
                               c.elastic.axial_modulus.mean, options.confidence, c.compaction_tests,
                               c.compaction_rate_checks) :
          collapse_softening(campaign, c.index, fe.cam_clay_surface().p0, c.elastic.continuum_bulk_modulus,
                             c.elastic.axial_modulus.mean, options.confidence);
      // The friction tests must have crushed the layer: beyond the largest compaction peak, or
      // without compaction tests beyond the surface's compressive tip.
      const double compressive_strength =
        c.softening.peak_stress.n > 0 ? c.softening.peak_stress.maximum : fe.cam_clay_surface().p0;
      c.friction = collapsed_friction(campaign, c.index, compressive_strength, options.confidence);
      result.microstructures.push_back(std::move(c));
    }
    if (std::all_of(result.microstructures.begin(), result.microstructures.end(),
                    [](const MicrostructureCalibration &c) { return !c.material_refused.empty(); }))
      throw CalibrationError("no microstructure gets a material file: " + result.microstructures.front().material_refused);

    // Across microstructures.
    std::vector<double> nu_c;
    for (const auto &c : result.microstructures)
      nu_c.push_back(c.contact_density);
    if (result.microstructures.size() >= 3 && distinct(nu_c) >= 3)
    {
      ScalingLaws s;
      for (const auto &c : result.microstructures)
      {
        const CamClaySurface p = c.base_plane.cam_clay_surface();
        s.contact_density.push_back(c.contact_density);
        s.compressive_over_bond.push_back(p.p0 / c.material.bond_tensile_strength);
        s.tensile_over_bond.push_back(p.beta * p.p0 / c.material.bond_tensile_strength);
        s.M.push_back(p.M);
      }
      s.compressive = fit_power_law(s.contact_density, s.compressive_over_bond, options.confidence,
                                    "sigma0/sigma_bond against contact density (Ritter et al. 2020, Eq. 2)");
      s.tensile = fit_power_law(s.contact_density, s.tensile_over_bond, options.confidence,
                                "beta sigma0/sigma_bond against contact density (Ritter et al. 2020, Eq. 3)");
      s.M_statistics = describe(s.M, options.confidence, "M across microstructures");
      result.scaling = s;
    }

    // Eqs. 5-8 of Bobillier et al. (2020): the macro modulus (Young's, from the secant moduli) and the compressive
    // strength (base sigma at failure at psi = 0) of every microstructure against its micro values.
    auto &mm = result.micro_macro;
    double reference_thickness = 0;
    for (const auto &c : result.microstructures)
    {
      double strength = 0;
      int count = 0;
      for (const auto &t : c.tests)
        if (std::abs(t.loading_angle_deg) < 1e-6)
          strength += t.sigma, ++count;
      mm.particle_modulus.push_back(c.material.particle_modulus);
      mm.macro_modulus.push_back(c.elastic.continuum_youngs_modulus);
      mm.bond_strength.push_back(c.material.bond_tensile_strength);
      mm.macro_strength.push_back(strength / count); // count > 0: elastic_constants needs psi = 0
      reference_thickness += c.layer_thickness / static_cast<double>(result.microstructures.size());
    }
    if (distinct(mm.particle_modulus) >= 3)
      mm.modulus = MicroMacroLaw{fit_line(mm.particle_modulus, mm.macro_modulus, options.confidence,
                                          "macro modulus against particle modulus (Bobillier et al. 2020, Eqs. 5, 7)"),
                                 reference_thickness};
    if (distinct(mm.bond_strength) >= 3)
      mm.strength = MicroMacroLaw{fit_line(mm.bond_strength, mm.macro_strength, options.confidence,
                                           "macro strength against bond strength (Bobillier et al. 2020, Eqs. 6, 8)"),
                                  reference_thickness};
    return result;
  }
} // namespace anticrack::params
