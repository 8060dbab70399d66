#include "coupling/pipeline_uncertainty.h"

#include "coupling/calibrate.h"
#include "params/regression.h"
#include "util/atomic_file.h"
#include "util/format.h"
#include "util/input_error.h"
#include "util/run_summary.h"

#include <Eigen/Dense>
#include <boost/math/distributions/normal.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace anticrack::coupling
{
  namespace fs = std::filesystem;
  using Json = nlohmann::ordered_json;

  namespace
  {
    /// The standard error of a mean over realizations from its summary.json statistics, 0 if none.
    double standard_error(const Json &statistics)
    {
      if (!statistics.is_object() || !statistics["standard_deviation"].is_number() || statistics.value("samples", 0) < 2)
        return 0;
      return statistics["standard_deviation"].get<double>() / std::sqrt(statistics["samples"].get<double>());
    }

    const fem::MaterialEntry &entry_named(const std::string &name)
    {
      for (const fem::MaterialEntry &e : fem::material_entries())
        if (e.name() == name)
          return e;
      throw std::logic_error("no material entry " + name);
    }

    /// The value of an entry of subsection Material in a material file.
    std::function<double &(fem::MaterialFile &)> material_entry(const std::string &name)
    {
      const fem::MaterialEntry *entry = &entry_named(name);
      return [entry](fem::MaterialFile &file) -> double & { return file.material.*(entry->number); };
    }

  } // namespace

  const std::vector<PstAnswer> &pst_answers()
  {
    static const std::vector<PstAnswer> list = {{"critical_cut_length_m", "critical cut", "m"},
                                                {"propagation_speed_m_per_s", "speed", "m/s"},
                                                {"touchdown_distance_m", "touchdown distance", "m"}};
    return list;
  }

  UncertainParameters uncertain_parameters(const fs::path &weak_layer_directory)
  {
    const Json summary = read_json_file((weak_layer_directory / "summary.json").string());
    const Json &m = summary["calibration"]["microstructures"][0];
    const fem::MaterialFile snow = fem::read_material_file_text(read_text_file((weak_layer_directory / material_file_name(0, 1, true)).string()), "material_snow.prm");
    const fem::MaterialFile dem = fem::read_material_file_text(read_text_file((weak_layer_directory / material_file_name(0, 1)).string()), "material.prm");
    const double S = snow.material.p0 / dem.material.p0; // the stress scale of the conversion

    // p0, beta, M from the fit's covariance; p0 in snow units.
    const Json &covariance = m["p_q_path_plane"]["models"]["cohesive_cam_clay"]["covariance"];
    Eigen::Matrix3d surface;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        surface(r, c) = covariance.at(r).at(c).is_number() ? covariance[r][c].get<double>() : std::nan("");
    const Eigen::Vector3d scale(S, 1, 1);
    surface = scale.asDiagonal() * surface * scale.asDiagonal();

    // Where a parameter's spread comes from. The surface's three carry the fit's covariance. ξ, R and
    // the lock-up strain are read from the same compaction curves, one estimate of each per
    // realization, so their means' errors are correlated: their covariance is that of the paired
    // realization values (params::covariance_of_means). E comes from the loading tests' elastic part,
    // μ from the friction tests, each independent of the others.
    enum class Source
    {
      surface_fit,
      elastic_part,
      softening_curves,
      friction_tests
    };
    struct Candidate
    {
      const char *name;
      std::function<double &(fem::MaterialFile &)> value_in;
      double value;
      Source source;
      const Json *statistics; ///< summary.json statistics over the realizations (not for the surface)
      double scale;           ///< the realization values to snow units (the surface is scaled above)
      bool given = true;      ///< the material file carries it
    };
    const auto lock_up_strain = [](fem::MaterialFile &file) -> double & { return file.collapse.lock_up_strain; };
    const auto friction = [](fem::MaterialFile &file) -> double & { return file.collapse.friction_coefficient; };
    // A statistics entry of summary.json, or null where the calibration wrote none (e.g. no lock-up
    // strain without compaction tests).
    static const Json none;
    const auto statistics = [](const Json &parent, const char *key) -> const Json * {
      return parent.is_object() && parent.contains(key) ? &parent[key] : &none;
    };
    const Json &softening = m["softening"];
    // The softening's residual ratio and the collapse's lock-up strain are dimensionless: the same
    // in snow units. The lock-up strain only where the compaction tests gave a collapse.
    const std::vector<Candidate> candidates = {
      {"p0", material_entry("Compressive strength p0 [Pa]"), snow.material.p0, Source::surface_fit, nullptr, 1},
      {"beta", material_entry("Tensile strength ratio beta"), snow.material.beta, Source::surface_fit, nullptr, 1},
      {"M", material_entry("Critical state slope M"), snow.material.M, Source::surface_fit, nullptr, 1},
      {"E", material_entry("Young's modulus [Pa]"), snow.material.youngs_modulus, Source::elastic_part,
       statistics(m["elastic"], "youngs_modulus_Pa"), S},
      {"xi", material_entry("Hardening factor xi"), snow.material.hardening_factor, Source::softening_curves,
       statistics(softening, "hardening_factor_xi"), 1},
      {"R", material_entry("Residual strength ratio"), snow.material.residual_strength_ratio,
       Source::softening_curves, statistics(softening, "residual_ratio"), 1},
      {"lock_up_strain", lock_up_strain, snow.collapse.lock_up_strain, Source::softening_curves,
       statistics(softening, "lock_up_strain"), 1, snow.collapse.given()},
      // The failed layer's friction, a ratio of stresses, where the campaign measured it.
      {"mu", friction, snow.collapse.friction_coefficient, Source::friction_tests,
       statistics(m["friction"], "friction_coefficient"), 1, !std::isnan(snow.collapse.friction_coefficient)}};
    const auto variance = [&](std::size_t k) {
      const Candidate &c = candidates[k];
      if (!c.given)
        return 0.0;
      if (c.source == Source::surface_fit)
        return surface(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k));
      return std::pow(c.scale * standard_error(*c.statistics), 2);
    };
    const auto covariance_between = [&](std::size_t a, std::size_t b) {
      const Candidate &ca = candidates[a], &cb = candidates[b];
      if (a == b)
        return variance(a);
      if (ca.source != cb.source)
        return 0.0;
      if (ca.source == Source::surface_fit)
        return surface(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b));
      if (!ca.statistics->contains("values") || !cb.statistics->contains("values"))
        throw InputError((weak_layer_directory / "summary.json").string() + ": the realization values of " +
                         ca.name + " and " + cb.name + " are missing (written by an older anticrack); run the "
                         "weak layer stage again (--overwrite)");
      return ca.scale * cb.scale *
             params::covariance_of_means((*ca.statistics)["values"].get<std::vector<double>>(),
                                         (*cb.statistics)["values"].get<std::vector<double>>());
    };
    std::vector<std::size_t> kept;
    UncertainParameters u;
    u.confidence = snow.uncertainty.confidence;
    for (std::size_t k = 0; k < candidates.size(); ++k)
      if (const double v = variance(k); std::isfinite(v) && v > 0)
      {
        kept.push_back(k);
        u.names.push_back(candidates[k].name);
        u.value_in.push_back(candidates[k].value_in);
      }
    const auto n = static_cast<Eigen::Index>(kept.size());
    u.value.resize(n);
    u.covariance.resize(n, n);
    for (Eigen::Index a = 0; a < n; ++a)
    {
      u.value(a) = candidates[kept[static_cast<std::size_t>(a)]].value;
      for (Eigen::Index b = 0; b < n; ++b)
        u.covariance(a, b) = covariance_between(kept[static_cast<std::size_t>(a)], kept[static_cast<std::size_t>(b)]);
    }
    return u;
  }

  UncertainParameters restricted_to(const UncertainParameters &u, const std::vector<std::string> &names)
  {
    std::vector<Eigen::Index> kept;
    UncertainParameters r;
    r.confidence = u.confidence;
    for (std::size_t k = 0; k < u.names.size(); ++k)
      if (std::find(names.begin(), names.end(), u.names[k]) != names.end())
      {
        kept.push_back(static_cast<Eigen::Index>(k));
        r.names.push_back(u.names[k]);
        r.value_in.push_back(u.value_in[k]);
      }
    const auto n = static_cast<Eigen::Index>(kept.size());
    r.value.resize(n);
    r.covariance.resize(n, n);
    for (Eigen::Index a = 0; a < n; ++a)
    {
      r.value(a) = u.value(kept[static_cast<std::size_t>(a)]);
      for (Eigen::Index b = 0; b < n; ++b)
        r.covariance(a, b) = u.covariance(kept[static_cast<std::size_t>(a)], kept[static_cast<std::size_t>(b)]);
    }
    return r;
  }

  fem::MaterialFile perturbed_material(const fem::MaterialFile &material, const UncertainParameters &u, std::size_t k)
  {
    fem::MaterialFile file = material;
    const auto i = static_cast<Eigen::Index>(k);
    const double step = std::sqrt(u.covariance(i, i));
    u.value_in[k](file) += step;
    file.material.name += ", " + u.names[k] + " + 1 standard error";
    file.comment.push_back("");
    file.comment.push_back("Sensitivity run of the pipeline: " + u.names[k] + " raised by one standard error, " +
                           fem::material_file_number(step) + " (coupling/pipeline_uncertainty.h).");
    return file;
  }

  Json linearised_intervals(const UncertainParameters &u, const Json &base, const std::vector<Json> &perturbed,
                            double element_length)
  {
    const double z = boost::math::quantile(boost::math::normal(), 0.5 + 0.5 * u.confidence);
    const auto n = static_cast<Eigen::Index>(u.names.size());
    Json out;
    out["confidence"] = u.confidence;
    out["method"] = "first-order sensitivities, one FE run per parameter raised by one standard error "
                    "(coupling/pipeline_uncertainty.h)";
    out["element_length_m"] = element_length;
    for (const auto &[key, label, unit] : pst_answers())
    {
      Json a;
      a["label"] = std::string(label) + " [" + unit + "]";
      if (!base.contains(key) || !base[key].is_number())
      {
        a["status"] = "no value in the base run";
        out["answers"][key] = a;
        continue;
      }
      const double y0 = base[key].get<double>();
      a["value"] = y0;
      Eigen::VectorXd g(n);
      bool linear = true;
      std::string why;
      for (Eigen::Index k = 0; k < n; ++k)
      {
        const Json &r = perturbed[static_cast<std::size_t>(k)];
        if (!r.contains(key) || !r[key].is_number() || r.value("outcome", "") != base.value("outcome", ""))
        {
          linear = false;
          why = u.names[static_cast<std::size_t>(k)] + " + 1 standard error changes the outcome (" +
                r.value("outcome", std::string("?")) + ")";
          g(k) = 0;
          continue;
        }
        g(k) = (r[key].get<double>() - y0) / std::sqrt(u.covariance(k, k));
      }
      if (!linear)
      {
        a["status"] = "not linear: " + why;
        out["answers"][key] = a;
        continue;
      }
      const Eigen::VectorXd sigma_g = u.covariance * g;
      const double variance = g.dot(sigma_g), sd = std::sqrt(std::max(variance, 0.0));
      Json shares = Json::object();
      std::string dominant;
      double largest = -1;
      for (Eigen::Index k = 0; k < n; ++k)
      {
        const double share = variance > 0 ? g(k) * sigma_g(k) / variance : 0;
        const double change = g(k) * std::sqrt(u.covariance(k, k));
        shares[u.names[static_cast<std::size_t>(k)]] = {{"change_per_standard_error", change}, {"variance_share", share}};
        if (std::abs(change) > largest)
          largest = std::abs(change), dominant = u.names[static_cast<std::size_t>(k)];
      }
      a["standard_deviation"] = sd;
      a["parameters"] = shares;
      a["dominant_parameter"] = variance > 0 ? dominant : "none (no parameter moves it)";
      // Every answer is a positive length or speed: a first-order interval that reaches 0 says
      // that the answer is far from linear over it (a standard error moves it by a large part of
      // itself), not that it could vanish; such an interval is not reported.
      if (y0 - z * sd <= 0)
        a["status"] = "not linear: the first-order interval reaches 0 or below (" + dominant +
                      " + 1 standard error moves it by " + format_number(100 * largest / std::abs(y0), 2) +
                      " % of its value)";
      else
      {
        a["status"] = "linearised";
        a["interval"] = {y0 - z * sd, y0 + z * sd};
      }
      out["answers"][key] = a;
    }
    return out;
  }

  Json combined_critical_cut_interval(const Json &mapped, const Json &linearised, const double value)
  {
    Json a;
    a["label"] = linearised.value("label", std::string("critical cut [m]"));
    a["value"] = value;
    const Json &cut = mapped["critical_cut_length_m"];
    if (!cut[0].is_number() || !cut[1].is_number())
    {
      a["status"] = "not carried: G_c's interval reaches beyond the cuts computed (" +
                    mapped.value("lower_note", mapped.value("upper_note", std::string("?"))) + ")";
      return a;
    }
    if (linearised.value("status", "") != "linearised")
    {
      a["status"] = "G_c's interval only: " + linearised.value("status", std::string("no rerun"));
      a["interval"] = cut;
      a["dominant_parameter"] = "G_c";
      return a;
    }
    const double lower = value - cut[0].get<double>(), upper = cut[1].get<double>() - value;
    const double z_sd = 0.5 * (linearised["interval"][1].get<double>() - linearised["interval"][0].get<double>());
    a["status"] = "G_c's interval through the stage's G(a), combined in quadrature with the linearised "
                  "interval of the parameters rerun for it: " + mapped.value("carries", std::string());
    a["interval"] = {value - std::hypot(lower, z_sd), value + std::hypot(upper, z_sd)};
    Json parameters = linearised["parameters"];
    parameters["G_c"] = {{"interval_half_widths_m", {lower, upper}}};
    a["parameters"] = parameters;
    a["dominant_parameter"] = 0.5 * (lower + upper) >= z_sd ? std::string("G_c") : linearised["dominant_parameter"].get<std::string>();
    return a;
  }
} // namespace anticrack::coupling
