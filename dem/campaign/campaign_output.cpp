#include "dem/campaign/campaign_output.h"

#include "util/hdf5_file.h"
#include "util/parameter_files.h"
#include "util/run_summary.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace anticrack::dem::campaign
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    using hdf5::Handle;

    /// Copies every dataset of the root of `file` into a new group `name` of `parent`.
    void copy_history(const fs::path &file, hid_t parent, const std::string &name)
    {
      const Handle source(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open " + file.string());
      const Handle group(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                         "create group " + name);
      H5G_info_t info;
      H5Gget_info(source.id, &info);
      for (hsize_t k = 0; k < info.nlinks; ++k)
      {
        char link[256];
        if (H5Lget_name_by_idx(source.id, ".", H5_INDEX_NAME, H5_ITER_INC, k, link, sizeof link, H5P_DEFAULT) < 0)
          throw std::runtime_error("HDF5: cannot list " + file.string());
        if (H5Ocopy(source.id, link, group.id, link, H5P_DEFAULT, H5P_DEFAULT) < 0)
          throw std::runtime_error("HDF5: cannot copy " + std::string(link) + " from " + file.string());
      }
    }

    /// The failure-point table of `rows` into `group`, one dataset per column of campaign_file.h.
    void write_failure_point_table(hid_t group, const std::vector<FailurePointRow> &rows)
    {
      for (const FailurePointColumn &column : failure_point_columns())
      {
        if (column.text)
        {
          std::vector<std::string> values;
          for (const auto &row : rows)
            values.push_back(row.*column.text);
          hdf5::write_strings(group, column.name, values, column.description);
        }
        else if (column.number)
        {
          std::vector<double> values;
          for (const auto &row : rows)
            values.push_back(row.*column.number);
          hdf5::write_doubles(group, column.name, values, column.unit, column.description);
        }
        else
        {
          std::vector<double> values;
          for (const auto &row : rows)
            values.insert(values.end(), (row.*column.tensor).begin(), (row.*column.tensor).end());
          hdf5::write_doubles(group, column.name, values, column.unit, column.description, {rows.size(), 3, 3});
        }
      }
    }

    std::string format_angle(double a)
    {
      std::ostringstream s;
      s << a;
      return s.str();
    }
  } // namespace

  void write_campaign_file(const fs::path &campaign_file, const SceneParameters &scene,
                           const std::vector<SceneParameters> &microstructure_scenes,
                           const std::vector<CampaignTest> &tests, std::map<std::string, TestOutcome> &outcomes)
  {
    const auto &c = scene.campaign;
    const fs::path directory = campaign_file.parent_path();
    std::error_code error;
    hdf5::write_file_atomically(campaign_file.string(), [&](const Handle &f) {
      hdf5::write_string_attribute(f.id, "format", "anticrack-campaign");
      // 3: love_stress, p and q are the specimen's between its platens (docs/physics.md §1.5).
      // 5: the friction tests and their steady_* columns.
      hdf5::write_string_attribute(f.id, "format_version", "5");
      hdf5::write_string_attribute(f.id, "scene_file", scene.file);
      hdf5::write_string_attribute(f.id, "scene_file_sha256", scene.file_sha256);
      hdf5::write_string_attribute(f.id, "parameters_sha256", scene.parameters_sha256);
      hdf5::write_string_attribute(f.id, "microstructures", c.microstructures_text);
      hdf5::write_string_attribute(f.id, "friction_sample", c.friction_sample_text);
      hdf5::write_string_attribute(f.id, "anticrack_version", version_info()["anticrack"].get<std::string>());
      hdf5::write_string_attribute(
        f.id, "conventions",
        "stresses tension positive except sigma (base normal stress) and p, compression positive; "
        "loading angle psi: clump force direction (sin psi, 0, -cos psi)");

      const Handle all(H5Gcreate2(f.id, "tests", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose, "create /tests");
      for (const auto &t : tests)
      {
        const fs::path history = directory / "tests" / t.id / "history.h5";
        const Handle group(H5Gcreate2(all.id, t.id.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                           "create /tests/" + t.id);
        hdf5::write_string_attribute(group.id, "status", outcomes[t.id].row.status);
        hdf5::write_string_attribute(group.id, "loading_angle_deg", format_angle(t.angle_deg));
        hdf5::write_string_attribute(group.id, "microstructure", std::to_string(t.microstructure));
        hdf5::write_string_attribute(group.id, "realization", std::to_string(t.realization));
        hdf5::write_string_attribute(group.id, "rate_divisor", format_angle(t.slowdown));
        hdf5::write_string_attribute(group.id, "loading", t.loading_name());
        if (fs::exists(history, error))
          copy_history(history, group.id, "history");
      }

      // What a calibration needs to know of each microstructure's material (params/ reads it).
      {
        const Handle g = hdf5::create_group(f.id, "microstructures");
        std::vector<std::string> labels;
        std::vector<double> contact_modulus, bond_modulus, particle_modulus, tensile, cohesion, density, periodic;
        for (std::size_t m = 0; m < microstructure_scenes.size(); ++m)
        {
          const auto &d = microstructure_scenes[m].dem;
          const std::string label =
            c.microstructures.empty() ? std::string("scene sample") : entry_changes_text(c.microstructures[m]);
          labels.push_back(label);
          contact_modulus.push_back(d.material.contact.contact_modulus);
          bond_modulus.push_back(d.bond.bond.enabled ? d.bond.bond.modulus : nan);
          particle_modulus.push_back(d.bond.bond.enabled ? d.bond.bond.modulus : d.material.contact.contact_modulus);
          tensile.push_back(d.bond.bond.enabled ? d.bond.bond.tensile_strength : nan);
          cohesion.push_back(d.bond.bond.enabled ? d.bond.bond.cohesion : nan);
          density.push_back(d.material.density);
          periodic.push_back(d.domain.periodic[0] && d.domain.periodic[1] ? 1.0 : 0.0);
        }
        hdf5::write_strings(g.id, "label", labels, "the microstructure variant (Campaign/Microstructures)");
        hdf5::write_doubles(g.id, "contact_modulus", contact_modulus, "Pa", "E_c of the linear contact law");
        hdf5::write_doubles(g.id, "bond_modulus", bond_modulus, "Pa", "E_bar of the parallel bonds (NaN: no bonds)");
        hdf5::write_doubles(g.id, "particle_modulus", particle_modulus, "Pa",
                            "the micro modulus of Bobillier et al.'s (2020) E_macro(E_particle): the bond modulus of bonded "
                            "samples, else the contact modulus");
        hdf5::write_doubles(g.id, "bond_tensile_strength", tensile, "Pa", "sigma_bar_c of the parallel bonds");
        hdf5::write_doubles(g.id, "bond_cohesion", cohesion, "Pa", "c_bar of the parallel bonds");
        hdf5::write_doubles(g.id, "particle_density", density, "kg/m^3", "density of the sphere material");
        hdf5::write_doubles(g.id, "laterally_periodic", periodic, "-",
                            "1: periodic along x and y (laterally confined, uniaxial strain at psi = 0); 0: open sides");
      }

      // The failure-point table: one row per test of the campaign proper (references apart).
      std::vector<const CampaignTest *> main_tests, compaction_tests, friction_tests, references;
      for (const auto &t : tests)
        (!t.reference_for.empty() ? references :
         t.compaction()           ? compaction_tests :
         t.friction()             ? friction_tests :
                                    main_tests)
          .push_back(&t);
      auto table = [&](hid_t group, const std::vector<const CampaignTest *> &tests_of_table) {
        std::vector<FailurePointRow> rows;
        for (const auto *t : tests_of_table)
          rows.push_back(outcomes[t->id].row);
        write_failure_point_table(group, rows);
      };
      {
        const Handle g(H5Gcreate2(f.id, failure_points_group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                       "create /" + std::string(failure_points_group));
        table(g.id, main_tests);
      }
      if (!compaction_tests.empty())
      {
        // The compaction tests: their failure point is the first peak (dem/scene/failure_analysis.h);
        // the calibration reads their curves from /tests/<id>/history.
        const Handle g = hdf5::create_group(f.id, compaction_tests_group);
        table(g.id, compaction_tests);
        hdf5::write_doubles(g.id, "strain_rate", std::vector<double>(compaction_tests.size(), c.compaction_strain_rate),
                            "1/s", "the platen's speed over the specimen height (Campaign/Compaction strain rate)");
      }
      if (!friction_tests.empty())
      {
        // The friction tests: their steady sliding (the steady_* columns) gives the failed layer's
        // friction coefficient; the calibration reads it from this table.
        const Handle g = hdf5::create_group(f.id, friction_tests_group);
        table(g.id, friction_tests);
        hdf5::write_doubles(g.id, "normal_stress", std::vector<double>(friction_tests.size(), c.friction_normal_stress),
                            "Pa", "the constant normal stress of the simple shear (Campaign/Friction normal stress)");
      }
      if (!references.empty())
      {
        const Handle g(H5Gcreate2(f.id, "quasi_static_check", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                       "create /quasi_static_check");
        table(g.id, references);
        std::vector<std::string> checked;
        std::vector<double> difference, base_difference;
        for (const auto *r : references)
        {
          checked.push_back(r->reference_for);
          difference.push_back(relative_difference(outcomes[r->reference_for], outcomes[r->id]));
          base_difference.push_back(base_relative_difference(outcomes[r->reference_for], outcomes[r->id]));
        }
        hdf5::write_strings(g.id, "checks", checked, "the campaign test this slower run is the reference of");
        hdf5::write_doubles(g.id, "relative_difference", difference, "-",
                      "|s - s_ref| / |s_ref| of the failure point s = (p, q) (the checked measure)");
        hdf5::write_doubles(g.id, "base_relative_difference", base_difference, "-",
                      "|s - s_ref| / |s_ref| of the base stresses s = (sigma, tau) at failure (reported)");
      }
    });
  }

  CampaignSummary campaign_summary(const SceneParameters &scene, const std::vector<CampaignTest> &tests,
                                   std::map<std::string, TestOutcome> &outcomes, bool any_failed,
                                   const std::string &command)
  {
    const auto &c = scene.campaign;
    CampaignSummary summary;
    Json &s = summary.json;
    s["status"] = any_failed ? "failed" : "completed";
    s["command"] = command;
    s["scene"] = scene_info(scene);
    Json spec;
    spec["loading_angles_deg"] = c.loading_angles_deg;
    spec["realizations"] = c.realizations;
    spec["microstructures"] = c.microstructures_text;
    spec["quasi_static_slowdown"] = c.quasi_static_slowdown;
    spec["quasi_static_tolerance"] = c.quasi_static_tolerance;
    spec["compaction_strain_rate_per_s"] = c.compaction_strain_rate;
    spec["compaction_final_strain"] = c.compaction_final_strain;
    spec["compaction_curve_strain_interval"] = c.compaction_curve_strain_interval;
    spec["friction_normal_stress_Pa"] = c.friction_normal_stress;
    spec["friction_shear_velocity_m_per_s"] = c.friction_shear_velocity;
    spec["friction_consolidation_time_s"] = c.friction_consolidation_time;
    spec["friction_final_shear_strain"] = c.friction_final_shear_strain;
    spec["friction_sample"] = c.friction_sample_text;
    s["campaign"] = spec;
    Json rows = Json::array();
    double test_wall = 0, largest_inertial = 0;
    for (const auto &t : tests)
    {
      const TestOutcome &o = outcomes[t.id];
      Json r;
      r["test"] = t.id;
      r["status"] = o.row.status;
      r["loading_angle_deg"] = t.angle_deg;
      r["microstructure"] = t.microstructure;
      r["realization"] = t.realization;
      r["rate_divisor"] = t.slowdown;
      r["loading"] = t.loading_name();
      auto finite = [](double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); };
      r["sigma_Pa"] = finite(o.row.sigma);
      r["tau_Pa"] = finite(o.row.tau);
      r["p_Pa"] = finite(o.row.p);
      r["q_Pa"] = finite(o.row.q);
      r["flow_angle_deg"] = finite(o.row.flow_angle_deg);
      r["max_inertial_number"] = finite(o.row.max_inertial_number);
      r["steps"] = finite(o.steps);
      r["wall_s"] = finite(o.wall_s);
      if (!o.analysis_error.empty())
        r["analysis_error"] = o.analysis_error;
      if (!o.message.empty() && o.row.status != "completed")
        r["message"] = o.message;
      rows.push_back(r);
      test_wall += std::isfinite(o.wall_s) ? o.wall_s : 0.0;
      if (t.reference_for.empty() && t.kind == CampaignTest::Kind::load_controlled &&
          std::isfinite(o.row.max_inertial_number))
        largest_inertial = std::max(largest_inertial, o.row.max_inertial_number);
    }
    s["tests"] = rows;
    std::vector<std::string> no_load_path;
    for (const auto &t : tests)
      if (outcomes[t.id].row.status == status_no_load_path)
        no_load_path.push_back(t.id);
    s["tests_without_load_path"] = no_load_path;
    s["largest_inertial_number_before_failure"] = largest_inertial;

    Json check = Json::array();
    double worst = 0;
    bool within = true;
    for (const auto &t : tests)
      if (!t.reference_for.empty())
      {
        const double d = relative_difference(outcomes[t.reference_for], outcomes[t.id]);
        Json r;
        r["test"] = t.reference_for;
        r["reference"] = t.id;
        r["relative_difference"] = std::isfinite(d) ? Json(d) : Json(nullptr);
        const double base = base_relative_difference(outcomes[t.reference_for], outcomes[t.id]);
        r["base_stress_relative_difference"] = std::isfinite(base) ? Json(base) : Json(nullptr);
        r["within_tolerance"] = std::isfinite(d) && d <= c.quasi_static_tolerance;
        within = within && std::isfinite(d) && d <= c.quasi_static_tolerance;
        worst = std::isfinite(d) ? std::max(worst, d) : std::numeric_limits<double>::infinity();
        check.push_back(r);
      }
    if (!check.empty())
    {
      Json q;
      q["measure"] = "|(p, q) - (p, q)_ref| / |(p, q)_ref| at the failure point";
      q["tolerance"] = c.quasi_static_tolerance;
      q["largest_relative_difference"] = std::isfinite(worst) ? Json(worst) : Json(nullptr);
      q["all_within_tolerance"] = within;
      q["pairs"] = check;
      s["quasi_static_check"] = q;
    }
    Json outputs;
    outputs["campaign"] = "campaign.h5";
    outputs["tests"] = "tests/<id>/summary.json, tests/<id>/history.h5";
    s["outputs"] = outputs;
    summary.test_wall_s = test_wall;
    summary.no_load_path = no_load_path;
    summary.quasi_static_checked = !check.empty();
    summary.largest_difference = worst;
    return summary;
  }
} // namespace anticrack::dem::campaign
