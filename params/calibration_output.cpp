#include "params/calibration_output.h"

#include "util/hdf5_file.h"

#include <cmath>
#include <filesystem>

namespace anticrack::params
{
  namespace
  {
    using Json = nlohmann::ordered_json;
    constexpr double degree = 3.14159265358979323846 / 180.0;

    std::vector<double> to_vector(const Eigen::VectorXd &v) { return {v.data(), v.data() + v.size()}; }

    std::vector<double> in_degrees(const std::vector<double> &radians)
    {
      std::vector<double> d;
      for (const double r : radians)
        d.push_back(r / degree);
      return d;
    }

    Json finite_or_null(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

    Json interval_json(double lower, double upper) { return Json::array({finite_or_null(lower), finite_or_null(upper)}); }

    Json statistics_json(const SampleStatistics &s)
    {
      return Json{{"mean", finite_or_null(s.mean)},
                  {"standard_deviation", s.n > 1 ? finite_or_null(s.standard_deviation) : Json(nullptr)},
                  {"interval", interval_json(s.mean_ci.lower, s.mean_ci.upper)},
                  {"samples", s.n},
                  {"values", s.values}};
    }

    Json fit_json(const EnvelopeFit &f)
    {
      Json parameters = Json::object();
      for (std::size_t k = 0; k < f.parameter_names.size(); ++k)
      {
        const auto i = static_cast<Eigen::Index>(k);
        Json p{{"value", f.parameters[i]},
               {"units", f.parameter_units[k]},
               {"covariance_interval", interval_json(f.ci_lower[i], f.ci_upper[i])}};
        if (f.has_bootstrap)
          p["bootstrap_interval"] = interval_json(f.bootstrap_lower[i], f.bootstrap_upper[i]);
        parameters[f.parameter_names[k]] = p;
      }
      // The covariance of the physical parameters (delta method), for propagating the fit's
      // uncertainty (coupling/pipeline_uncertainty.h): rows and columns in parameter order.
      Json covariance = Json::array();
      for (Eigen::Index r = 0; r < f.covariance.rows(); ++r)
      {
        Json row = Json::array();
        for (Eigen::Index c = 0; c < f.covariance.cols(); ++c)
          row.push_back(finite_or_null(f.covariance(r, c)));
        covariance.push_back(row);
      }
      return Json{{"parameters", parameters},
                  {"covariance", covariance},
                  {"r_squared", finite_or_null(f.r_squared)},
                  {"relative_rmse", f.rmse},
                  {"aicc", finite_or_null(f.aicc)},
                  {"bic", f.bic},
                  {"points", f.n_points},
                  {"identifiable", f.identifiable},
                  {"starts_at_best", std::to_string(f.starts_at_best) + " of " + std::to_string(f.starts)},
                  {"bootstrap_resamples", f.has_bootstrap ? Json(f.bootstrap_samples.rows()) : Json(nullptr)}};
    }

    Json plane_json(const PlaneCalibration &p)
    {
      Json models = Json::object();
      for (std::size_t k = 0; k < p.fits.size(); ++k)
      {
        Json j = fit_json(p.fits[k]);
        j["delta_aicc"] = finite_or_null(p.fits[k].aicc - p.fits[p.best_by_aicc].aicc);
        models[p.fits[k].model] = j;
      }
      Json j{{"best_by_aicc", p.fits[p.best_by_aicc].model}, {"models", models}};
      if (!p.cam_clay_not_determined.empty())
        j["cam_clay_not_determined"] = p.cam_clay_not_determined;
      return j;
    }

    void write_fit(hid_t parent, const EnvelopeFit &f, const EnvelopeBand &band, double best_aicc)
    {
      const hdf5::Handle g = hdf5::create_group(parent, f.model);
      hdf5::write_strings(g.id, "parameter_names", f.parameter_names, "fitted parameters");
      hdf5::write_strings(g.id, "parameter_units", f.parameter_units, "their units");
      hdf5::write_doubles(g.id, "parameters", to_vector(f.parameters), "see parameter_units", "best fit");
      hdf5::write_doubles(g.id, "ci_lower", to_vector(f.ci_lower), "see parameter_units",
                          "lower end of the interval from the covariance of the fit (Student t)");
      hdf5::write_doubles(g.id, "ci_upper", to_vector(f.ci_upper), "see parameter_units",
                          "upper end of the interval from the covariance of the fit (Student t)");
      if (f.has_bootstrap)
      {
        hdf5::write_doubles(g.id, "bootstrap_lower", to_vector(f.bootstrap_lower), "see parameter_units",
                            "percentile interval over resampled realizations");
        hdf5::write_doubles(g.id, "bootstrap_upper", to_vector(f.bootstrap_upper), "see parameter_units",
                            "percentile interval over resampled realizations");
        const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> samples = f.bootstrap_samples;
        hdf5::write_doubles(g.id, "bootstrap_samples", {samples.data(), samples.data() + samples.size()},
                            "see parameter_units", "fitted parameters of every bootstrap resample [resample][parameter]",
                            {static_cast<hsize_t>(samples.rows()), static_cast<hsize_t>(samples.cols())});
      }
      hdf5::write_doubles(g.id, "residuals", to_vector(f.residuals), "-",
                          "relative radial residuals ln r_i - ln R(a_i)");
      const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> covariance = f.covariance;
      hdf5::write_doubles(g.id, "covariance", {covariance.data(), covariance.data() + covariance.size()},
                          "products of parameter_units", "covariance of the parameters (delta method)",
                          {static_cast<hsize_t>(covariance.rows()), static_cast<hsize_t>(covariance.cols())});
      hdf5::write_number_attribute(g.id, "r_squared", f.r_squared);
      hdf5::write_number_attribute(g.id, "rmse", f.rmse);
      hdf5::write_number_attribute(g.id, "aicc", f.aicc);
      hdf5::write_number_attribute(g.id, "delta_aicc", f.aicc - best_aicc);
      hdf5::write_number_attribute(g.id, "bic", f.bic);
      hdf5::write_number_attribute(g.id, "n_points", static_cast<double>(f.n_points));
      hdf5::write_number_attribute(g.id, "has_bootstrap", f.has_bootstrap ? 1.0 : 0.0);
      const hdf5::Handle b = hdf5::create_group(g.id, "band");
      hdf5::write_doubles(b.id, "angle", band.angle, "rad", "polar angle in the (normal, shear) plane");
      hdf5::write_doubles(b.id, "radius", band.radius, "Pa", "envelope of the best fit along the ray");
      hdf5::write_doubles(b.id, "radius_lower", band.lower, "Pa", "lower end of the confidence band");
      hdf5::write_doubles(b.id, "radius_upper", band.upper, "Pa", "upper end of the confidence band");
      hdf5::write_string_attribute(b.id, "source", band.from_bootstrap ? "bootstrap" : "delta method");
    }

    void write_microstructure(hid_t parent, const Calibration &calibration, const MicrostructureCalibration &c)
    {
      const hdf5::Handle g = hdf5::create_group(parent, "m" + std::to_string(c.index));
      hdf5::write_string_attribute(g.id, "label", c.material.label);
      hdf5::write_number_attribute(g.id, "solid_fraction", c.solid_fraction);
      hdf5::write_number_attribute(g.id, "coordination", c.coordination);
      hdf5::write_number_attribute(g.id, "contact_density", c.contact_density);
      hdf5::write_number_attribute(g.id, "layer_thickness", c.layer_thickness);
      hdf5::write_number_attribute(g.id, "grain_diameter", c.grain_diameter);
      hdf5::write_number_attribute(g.id, "bond_tensile_strength", c.material.bond_tensile_strength);
      hdf5::write_number_attribute(g.id, "particle_modulus", c.material.particle_modulus);
      hdf5::write_number_attribute(g.id, "path_lateral_stress_ratio", c.path.lateral_stress_ratio());
      {
        const hdf5::Handle p = hdf5::create_group(g.id, "points");
        std::vector<std::string> ids;
        std::vector<double> angle, realization, sigma, tau, pressure, q, path_p, path_q, flow;
        for (const auto &t : c.tests)
        {
          ids.push_back(t.id), angle.push_back(t.loading_angle_deg), realization.push_back(t.realization);
          sigma.push_back(t.sigma), tau.push_back(std::abs(t.tau)), pressure.push_back(t.p), q.push_back(t.q);
          const StressPoint on_path = c.path.invariants(t.sigma, t.tau);
          path_p.push_back(on_path.normal), path_q.push_back(on_path.shear);
          flow.push_back(t.flow_angle_deg);
        }
        hdf5::write_strings(p.id, "test", ids, "campaign test id");
        hdf5::write_doubles(p.id, "loading_angle_deg", angle, "deg", "psi");
        hdf5::write_doubles(p.id, "realization", realization, "-", "realization");
        hdf5::write_doubles(p.id, "sigma", sigma, "Pa", "base normal stress at failure, compression positive");
        hdf5::write_doubles(p.id, "tau", tau, "Pa", "|base shear stress| at failure");
        hdf5::write_doubles(p.id, "p", pressure, "Pa", "Love-Weber mean pressure at failure, compression positive");
        hdf5::write_doubles(p.id, "q", q, "Pa", "Love-Weber von Mises stress at failure");
        hdf5::write_doubles(p.id, "p_path", path_p, "Pa",
                            "mean pressure of the FE point carrying the base stresses on the test's path");
        hdf5::write_doubles(p.id, "q_path", path_q, "Pa",
                            "von Mises stress of the FE point carrying the base stresses on the test's path");
        hdf5::write_doubles(p.id, "flow_angle_deg", flow, "deg", "atan2(du_z, du_x) after failure");
      }
      {
        const hdf5::Handle fits = hdf5::create_group(g.id, "fits");
        for (const PlaneCalibration *plane : {&c.base_plane, &c.invariant_plane, &c.path_plane})
        {
          const hdf5::Handle pg = hdf5::create_group(fits.id, plane_id(plane->plane));
          for (std::size_t k = 0; k < plane->fits.size(); ++k)
            write_fit(pg.id, plane->fits[k], plane->bands[k], plane->fits[plane->best_by_aicc].aicc);
        }
      }
      {
        const FlowRuleAnalysis &f = c.flow_rule;
        const hdf5::Handle fr = hdf5::create_group(g.id, "flow_rule");
        hdf5::write_doubles(fr.id, "loading_angle_deg", in_degrees(f.loading_angle), "deg", "psi");
        hdf5::write_doubles(fr.id, "flow_angle_deg", in_degrees(f.flow_angle), "deg", "theta");
        hdf5::write_doubles(fr.id, "sigma_star", f.sigma_star, "-", "normalised normal stress (Ritter et al. 2020, Eq. 5)");
        hdf5::write_doubles(fr.id, "tau_star", f.tau_star, "-", "normalised shear stress (Ritter et al. 2020, Eq. 6)");
        hdf5::write_doubles(fr.id, "psi_star_deg", in_degrees(f.psi_star), "deg", "normalised loading angle");
        hdf5::write_doubles(fr.id, "theta_star_deg", in_degrees(f.theta_star), "deg",
                            "normalised flow angle (Ritter et al. 2020, Eq. 18)");
        const CamClaySurface surface = c.base_plane.cam_clay_surface();
        std::vector<double> curve_psi, curve_theta;
        for (int k = 0; k <= 180; ++k)
        {
          curve_psi.push_back(k);
          curve_theta.push_back(associative_flow_angle(k * degree, surface) / degree);
        }
        hdf5::write_doubles(fr.id, "curve_loading_angle_deg", curve_psi, "deg", "psi");
        hdf5::write_doubles(fr.id, "curve_flow_angle_deg", curve_theta, "deg",
                            "associative flow angle for the fitted (sigma, tau) surface");
        const AssociativityMeasure &a = f.associativity;
        hdf5::write_number_attribute(fr.id, "transition_angle_predicted_deg", f.transition_predicted / degree);
        hdf5::write_number_attribute(fr.id, "transition_angle_observed_deg",
                                     f.transition_observed ? *f.transition_observed / degree : std::nan(""));
        hdf5::write_number_attribute(fr.id, "rms_deviation_deg", a.rms_deviation_deg);
        hdf5::write_number_attribute(fr.id, "slope", a.line.slope);
        hdf5::write_number_attribute(fr.id, "intercept_deg", a.line.intercept / degree);
        hdf5::write_number_attribute(fr.id, "r_squared_associative", a.r_squared_associative);
      }
      {
        const hdf5::Handle curves = hdf5::create_group(g.id, "curves");
        for (const auto &t : c.tests)
        {
          const TestHistory h = calibration.campaign.history(t);
          const hdf5::Handle tg = hdf5::create_group(curves.id, t.id);
          // The campaign's strains turned into those of the layer (params/campaign_data.cpp).
          hdf5::write_doubles(tg.id, "normal_strain", h.normal_strain, "-", "-u_z / h of the deformable layer");
          hdf5::write_doubles(tg.id, "shear_strain", h.shear_strain, "-", "u_x / h of the deformable layer");
          hdf5::write_doubles(tg.id, "sigma", h.sigma, "Pa", "base normal stress, compression positive");
          hdf5::write_doubles(tg.id, "tau", h.tau, "Pa", "base shear stress");
          hdf5::write_number_attribute(tg.id, "loading_angle_deg", t.loading_angle_deg);
          hdf5::write_number_attribute(tg.id, "realization", t.realization);
        }
      }
    }

    /// summary.json's softening of one microstructure: the law's parameters and, from compaction
    /// tests, the energies, the lock-up and each test's reading with its rate check.
    Json softening_json(const MicrostructureCalibration &c)
    {
      const SofteningEstimate &s = c.softening;
      if (!c.material_refused.empty())
        return Json{{"source", s.source}};
      Json j{{"law", "collapse"},
             {"source", s.source},
             {"residual_ratio", statistics_json(s.residual_ratio)},
             {"plastic_volumetric_strain", statistics_json(s.plastic_volumetric_strain)},
             {"hardening_factor_xi", statistics_json(s.hardening_factor)},
             {"tests_not_softening", s.excluded}};
      if (c.compaction_tests.empty())
        return j;
      j["peak_stress_Pa"] = statistics_json(s.peak_stress);
      j["fracture_energy_density_J_per_m3"] = statistics_json(s.fracture_energy_density);
      j["collapse_energy_density_J_per_m3"] = statistics_json(s.collapse_energy_density);
      j["fracture_energy_J_per_m2_of_the_dem_layer"] = s.fracture_energy_density.mean * c.layer_thickness;
      j["lock_up_strain"] = statistics_json(s.lock_up_strain);
      j["collapse_height_m_of_the_dem_layer"] = s.lock_up_strain.mean * c.layer_thickness;
      j["lock_up_modulus_Pa"] = statistics_json(s.lock_up_modulus);
      Json tests = Json::array();
      for (const CompactionReading &r : c.compaction_tests)
      {
        Json test = dem::compaction_curve_json(r.fit);
        test["test"] = r.test;
        tests.push_back(test);
      }
      j["compaction_tests"] = tests;
      Json checks = Json::array();
      for (const CompactionRateCheck &r : c.compaction_rate_checks)
        checks.push_back(Json{{"test", r.test},
                              {"reference", r.reference},
                              {"what", "(reference - test) / reference"},
                              {"peak_stress", r.peak_stress},
                              {"residual_ratio", r.residual_ratio},
                              {"plastic_softening_strain", r.plastic_strain},
                              {"fracture_energy", r.fracture_energy},
                              {"lock_up_strain", r.lock_up_strain},
                              {"largest", r.largest()}});
      j["rate_checks"] = checks;
      return j;
    }
  } // namespace

  namespace
  {
    /// summary.json's friction of the failed layer: μ over the realizations and each test's reading.
    Json friction_json(const FrictionEstimate &f)
    {
      if (!f.measured())
        return Json{{"source", "not measured (no friction tests in the campaign)"}, {"excluded", f.excluded}};
      Json tests = Json::array();
      for (const FrictionReading &r : f.readings)
        tests.push_back(Json{{"test", r.test},
                             {"realization", r.realization},
                             {"steady_normal_stress_Pa", r.normal_stress},
                             {"steady_shear_stress_Pa", r.shear_stress},
                             {"friction_coefficient", r.ratio}});
      return Json{{"source", "friction tests: steady shear over normal stress of the collapsed layer's simple shear"},
                  {"friction_coefficient", statistics_json(f.friction_coefficient)},
                  {"tests", tests},
                  {"excluded", f.excluded}};
    }
  } // namespace

  void write_calibration_data(const Calibration &calibration, const std::string &file)
  {
    hdf5::write_file_atomically(file, [&](const hdf5::Handle &f) {
      hdf5::write_string_attribute(f.id, "format", "anticrack-calibration");
      hdf5::write_number_attribute(f.id, "format_version", 2);
      hdf5::write_string_attribute(f.id, "campaign_file", calibration.campaign.file);
      hdf5::write_string_attribute(f.id, "campaign_sha256", calibration.campaign.sha256);
      hdf5::write_string_attribute(f.id, "scene_file", calibration.campaign.scene_file);
      hdf5::write_string_attribute(f.id, "fe_plane", plane_id(StressPlane::path_invariants));
      hdf5::write_number_attribute(f.id, "confidence", calibration.options.confidence);
      hdf5::write_string_attribute(f.id, "conventions",
                                   "sigma and p compression positive; tau, q >= 0; angles in the (normal, shear) "
                                   "plane from the normal axis; loading angle psi: force (sin psi, 0, -cos psi)");
      {
        const hdf5::Handle all = hdf5::create_group(f.id, "microstructures");
        for (const auto &c : calibration.microstructures)
          write_microstructure(all.id, calibration, c);
      }
      if (calibration.scaling)
      {
        const ScalingLaws &s = *calibration.scaling;
        const hdf5::Handle g = hdf5::create_group(f.id, "scaling");
        hdf5::write_doubles(g.id, "contact_density", s.contact_density, "-", "nu_c = z phi");
        hdf5::write_doubles(g.id, "sigma0_over_bond", s.compressive_over_bond, "-", "sigma0 / bond tensile strength");
        hdf5::write_doubles(g.id, "beta_sigma0_over_bond", s.tensile_over_bond, "-",
                            "beta sigma0 / bond tensile strength");
        hdf5::write_doubles(g.id, "M", s.M, "-", "M of the (sigma, tau) fit");
        hdf5::write_number_attribute(g.id, "sigma0_prefactor", s.compressive.prefactor);
        hdf5::write_number_attribute(g.id, "sigma0_exponent", s.compressive.exponent);
        hdf5::write_number_attribute(g.id, "sigma0_r_squared", s.compressive.r_squared_log);
        hdf5::write_number_attribute(g.id, "tensile_prefactor", s.tensile.prefactor);
        hdf5::write_number_attribute(g.id, "tensile_exponent", s.tensile.exponent);
        hdf5::write_number_attribute(g.id, "tensile_r_squared", s.tensile.r_squared_log);
      }
      const MicroMacroRelations &mm = calibration.micro_macro;
      if (mm.modulus || mm.strength)
      {
        const hdf5::Handle g = hdf5::create_group(f.id, "micro_macro");
        hdf5::write_doubles(g.id, "particle_modulus", mm.particle_modulus, "Pa", "micro modulus");
        hdf5::write_doubles(g.id, "macro_modulus", mm.macro_modulus, "Pa", "Young's modulus of the continuum");
        hdf5::write_doubles(g.id, "bond_strength", mm.bond_strength, "Pa", "bond tensile strength");
        hdf5::write_doubles(g.id, "macro_strength", mm.macro_strength, "Pa", "base sigma at failure at psi = 0");
        for (const auto &[name, law] : {std::pair{"modulus", &mm.modulus}, std::pair{"strength", &mm.strength}})
          if (*law)
          {
            hdf5::write_number_attribute(g.id, std::string(name) + "_intercept", (*law)->fit.intercept);
            hdf5::write_number_attribute(g.id, std::string(name) + "_slope", (*law)->fit.slope);
            hdf5::write_number_attribute(g.id, std::string(name) + "_r_squared", (*law)->fit.r_squared);
          }
        hdf5::write_number_attribute(g.id, "reference_thickness", mm.modulus ? mm.modulus->reference_thickness :
                                                                             mm.strength->reference_thickness);
      }
    });
  }

  nlohmann::ordered_json calibration_summary(const Calibration &calibration)
  {
    Json microstructures = Json::array();
    for (const auto &c : calibration.microstructures)
    {
      const FlowRuleAnalysis &f = c.flow_rule;
      const AssociativityMeasure &a = f.associativity;
      Json flow{{"rms_deviation_from_associative_deg", a.rms_deviation_deg},
                {"max_deviation_deg", a.max_abs_deviation_deg},
                {"mean_deviation_deg", a.mean_deviation_deg},
                {"slope", a.line.slope},
                {"slope_interval", interval_json(a.line.slope_ci.lower, a.line.slope_ci.upper)},
                {"slope_consistent_with_associative", a.slope_consistent_with_associative},
                {"r_squared_associative", finite_or_null(a.r_squared_associative)},
                {"transition_angle_predicted_deg", f.transition_predicted / degree},
                {"transition_angle_observed_deg",
                 f.transition_observed ? Json(*f.transition_observed / degree) : Json(nullptr)}};
      if (!f.transition_observed)
        flow["transition_angle_observed_note"] = f.transition_observed_note;
      if (!f.excluded.empty())
        flow["tests_without_a_flow_angle"] = f.excluded;
      if (!f.associativity_note.empty())
        flow["associativity_note"] = f.associativity_note;
      microstructures.push_back(Json{
        {"index", c.index},
        {"label", c.material.label},
        {"completed_tests", c.tests.size()},
        {"tests_left_out", c.tests_left_out},
        {"realizations", c.realizations.size()},
        {"solid_fraction", c.solid_fraction},
        {"coordination", c.coordination},
        {"contact_density", c.contact_density},
        {"density_kg_per_m3", c.density},
        {"layer_thickness_m", c.layer_thickness},
        {"grain_diameter_m", std::isfinite(c.grain_diameter) ? Json(c.grain_diameter) : Json(nullptr)},
        {"sigma_tau_plane", plane_json(c.base_plane)},
        {"p_q_plane", plane_json(c.invariant_plane)},
        {"p_q_path_plane", plane_json(c.path_plane)},
        {"test_path",
         Json{{"laterally_confined", c.path.laterally_confined},
              {"lateral_stress_ratio", c.path.lateral_stress_ratio()},
              {"dem_lateral_stress_ratio_at_failure", c.lateral_stress_ratio_at_failure.n > 0 ?
                                                        statistics_json(c.lateral_stress_ratio_at_failure) :
                                                        Json(nullptr)}}},
        {"flow_rule", flow},
        {"elastic",
         Json{{"laterally_confined", c.elastic.laterally_confined},
              {"poisson_ratio_given", c.elastic.poisson_ratio_given},
              {"axial_secant_modulus_Pa", statistics_json(c.elastic.axial_modulus)},
              {"shear_modulus_Pa", statistics_json(c.elastic.shear_modulus)},
              {"continuum",
               Json{{"what", "E, nu, K of the mean axial and shear moduli: the material file's, which reproduce "
                             "both mean stiffnesses"},
                    {"youngs_modulus_Pa", c.elastic.continuum_youngs_modulus},
                    {"poisson_ratio", c.elastic.continuum_poisson_ratio},
                    {"bulk_modulus_Pa", c.elastic.continuum_bulk_modulus}}},
              {"youngs_modulus_Pa", statistics_json(c.elastic.youngs_modulus)},
              {"poisson_ratio", statistics_json(c.elastic.poisson_ratio)},
              {"bulk_modulus_Pa", statistics_json(c.elastic.bulk_modulus)},
              {"poisson_ratio_from_K0", c.elastic.k0_poisson_ratio.n > 0 ? statistics_json(c.elastic.k0_poisson_ratio) :
                                                                            Json(nullptr)}}},
        {"softening", softening_json(c)},
        {"friction", friction_json(c.friction)},
        {"material_refused", c.material_refused.empty() ? Json(nullptr) : Json(c.material_refused)}});
    }
    Json s{{"confidence", calibration.options.confidence},
           {"bootstrap_samples", calibration.options.bootstrap_samples},
           {"bootstrap_seed", calibration.options.seed},
           {"fe_plane", plane_id(StressPlane::path_invariants)},
           {"campaign", Json{{"file", calibration.campaign.file},
                             {"sha256", calibration.campaign.sha256},
                             {"scene_file", calibration.campaign.scene_file},
                             {"scene_file_sha256", calibration.campaign.scene_file_sha256}}},
           {"microstructures", microstructures},
           {"fit_through_the_fe_points_peaks",
            Json{{"refits", calibration.peak_factor_refits},
                 {"last_change_of_a_peak_factor_ln", calibration.peak_factor_last_change}}}};
    if (calibration.scaling)
    {
      auto law = [](const PowerLawFit &p) {
        return Json{{"prefactor", p.prefactor},
                    {"prefactor_interval", interval_json(p.prefactor_ci.lower, p.prefactor_ci.upper)},
                    {"exponent", p.exponent},
                    {"exponent_interval", interval_json(p.exponent_ci.lower, p.exponent_ci.upper)},
                    {"r_squared_log", p.r_squared_log}};
      };
      s["scaling"] = Json{{"sigma0_over_bond", law(calibration.scaling->compressive)},
                          {"beta_sigma0_over_bond", law(calibration.scaling->tensile)},
                          {"M", statistics_json(calibration.scaling->M_statistics)}};
    }
    const MicroMacroRelations &mm = calibration.micro_macro;
    for (const auto &[name, law] : {std::pair{"macro_modulus_vs_particle_modulus", &mm.modulus},
                                    std::pair{"macro_strength_vs_bond_strength", &mm.strength}})
      if (*law)
        s["micro_macro"][name] = Json{{"intercept", (*law)->fit.intercept},
                                      {"slope", (*law)->fit.slope},
                                      {"slope_interval", interval_json((*law)->fit.slope_ci.lower, (*law)->fit.slope_ci.upper)},
                                      {"r_squared", (*law)->fit.r_squared},
                                      {"reference_thickness_m", (*law)->reference_thickness}};
    return s;
  }
} // namespace anticrack::params
