#include "params/campaign_data.h"

#include "dem/campaign/campaign_file.h"
#include "dem/scene/history_columns.h"
#include "params/calibration_error.h"
#include "util/hdf5_file.h"
#include "util/sha256.h"

#include <cmath>
#include <filesystem>

namespace anticrack::params
{
  namespace
  {
    /// A column of a table group with exactly `rows` entries.
    std::vector<double> column(hid_t group, const std::string &name, std::size_t rows, const std::string &file)
    {
      std::vector<double> values = hdf5::read_doubles(group, name);
      if (values.size() != rows)
        throw CalibrationError(file + ": " + name + " has " + std::to_string(values.size()) + " rows, expected " +
                               std::to_string(rows));
      return values;
    }

    /// A table of tests (/failure_points, /compaction_tests, /friction_tests, /quasi_static_check) by the names of the
    /// writer's columns (dem/campaign/campaign_file.h).
    std::vector<CampaignTest> read_test_table(hid_t parent, const std::string &table, const CampaignData &data)
    {
      const std::string &file = data.file;
      using Row = dem::FailurePointRow;
      const hdf5::Handle g = hdf5::open_group(parent, table);
      const auto name_of = [](auto member) { return std::string(dem::failure_point_column(member).name); };
      const auto ids = hdf5::read_strings(g.id, name_of(&Row::test));
      const std::size_t n = ids.size();
      const auto status = hdf5::read_strings(g.id, name_of(&Row::status));
      if (status.size() != n)
        throw CalibrationError(file + ": /" + table + "/" + name_of(&Row::status) + " and /" + table + "/" +
                               name_of(&Row::test) + " differ in length");
      std::vector<Row> rows(n);
      std::vector<CampaignTest> tests;
      for (double Row::*member : {&Row::microstructure, &Row::realization, &Row::loading_angle_deg, &Row::sigma,
                                  &Row::tau, &Row::p, &Row::q, &Row::flow_angle_deg, &Row::solid_fraction,
                                  &Row::coordination, &Row::specimen_height, &Row::layer_thickness})
      {
        const auto values = column(g.id, name_of(member), n, file);
        for (std::size_t k = 0; k < n; ++k)
          rows[k].*member = values[k];
      }
      // Since format 4: the grains' size (campaigns of format 3 leave it NaN; the snow units'
      // length needs it and says so); since format 5, the friction tests' steady sliding.
      for (double Row::*member : {&Row::particle_diameter, &Row::steady_shear_stress, &Row::steady_normal_stress,
                                  &Row::steady_stress_ratio})
        if (hdf5::exists(g.id, name_of(member)))
        {
          const auto values = column(g.id, name_of(member), n, file);
          for (std::size_t k = 0; k < n; ++k)
            rows[k].*member = values[k];
        }
      const auto love = hdf5::read_doubles(g.id, name_of(&Row::love_stress));
      if (love.size() != 9 * n)
        throw CalibrationError(file + ": /" + table + "/" + name_of(&Row::love_stress) + " is not n x 3 x 3");
      for (std::size_t k = 0; k < n; ++k)
      {
        const Row &row = rows[k];
        CampaignTest t;
        t.id = ids[k];
        t.status = status[k];
        t.microstructure = static_cast<int>(row.microstructure);
        t.realization = static_cast<int>(row.realization);
        if (t.microstructure < 0 || t.microstructure >= static_cast<int>(data.microstructures.size()))
          throw CalibrationError(file + ": test " + t.id + " refers to microstructure " +
                                 std::to_string(t.microstructure) + ", the file describes " +
                                 std::to_string(data.microstructures.size()));
        t.loading_angle_deg = row.loading_angle_deg;
        t.sigma = row.sigma, t.tau = row.tau, t.p = row.p, t.q = row.q;
        for (int c = 0; c < 9; ++c)
          t.love_stress[c] = love[9 * k + c];
        t.flow_angle_deg = row.flow_angle_deg;
        t.solid_fraction = row.solid_fraction;
        t.coordination = row.coordination;
        t.specimen_height = row.specimen_height;
        t.layer_thickness = row.layer_thickness;
        t.particle_diameter = row.particle_diameter;
        t.steady_shear_stress = row.steady_shear_stress;
        t.steady_normal_stress = row.steady_normal_stress;
        t.steady_stress_ratio = row.steady_stress_ratio;
        if (t.completed() && !(t.specimen_height > 0 && t.layer_thickness > 0))
          throw CalibrationError(file + ": test " + t.id + " has no specimen height or layer thickness (it was "
                                 "run by an anticrack "
                                 "older than campaign format 2); delete its directory tests/" + t.id +
                                 " and resume the campaign to run it again");
        tests.push_back(t);
      }
      return tests;
    }
  } // namespace

  CampaignData read_campaign(const std::string &file)
  {
    if (!std::filesystem::is_regular_file(file))
      throw CalibrationError(file + ": no such campaign file (expected the campaign.h5 that `anticrack run` "
                             "writes for a scene with a Campaign subsection)");
    CampaignData data;
    data.file = file;
    try
    {
      const hdf5::Handle f = hdf5::open_file_read_only(file);
      const std::string format =
        hdf5::has_attribute(f.id, "format") ? hdf5::read_string_attribute(f.id, "format") : "";
      if (format != "anticrack-campaign")
        throw CalibrationError(file + ": not an anticrack campaign file (root attribute format = \"" + format +
                               "\", expected \"anticrack-campaign\")");
      const double version = hdf5::read_number_attribute(f.id, "format_version");
      if (version < 3)
        throw CalibrationError(
          file + ": campaign format version " + std::to_string(int(version)) +
          (version < 2 ? " has no /microstructures table (materials of the samples)"
                       : " records the Love-Weber stress over every sphere, diluted by the platens "
                         "(docs/physics.md §1.5)") +
          "; rewrite it with this anticrack by `anticrack run SCENE -o DIR --resume` (tests whose results are "
          "still valid are not run again)");
      data.scene_file = hdf5::read_string_attribute(f.id, "scene_file");
      data.scene_file_sha256 = hdf5::read_string_attribute(f.id, "scene_file_sha256");
      data.parameters_sha256 = hdf5::read_string_attribute(f.id, "parameters_sha256");
      data.anticrack_version = hdf5::read_string_attribute(f.id, "anticrack_version");

      {
        const hdf5::Handle g = hdf5::open_group(f.id, "microstructures");
        const auto labels = hdf5::read_strings(g.id, "label");
        const std::size_t n = labels.size();
        const auto modulus = column(g.id, "particle_modulus", n, file);
        const auto tensile = column(g.id, "bond_tensile_strength", n, file);
        const auto cohesion = column(g.id, "bond_cohesion", n, file);
        const auto density = column(g.id, "particle_density", n, file);
        const auto periodic = column(g.id, "laterally_periodic", n, file);
        for (std::size_t m = 0; m < n; ++m)
          data.microstructures.push_back({labels[m], modulus[m], tensile[m], cohesion[m], density[m], periodic[m] > 0.5});
      }

      data.tests = read_test_table(f.id, dem::failure_points_group, data);
      if (hdf5::exists(f.id, dem::compaction_tests_group))
        data.compaction_tests = read_test_table(f.id, dem::compaction_tests_group, data);
      if (hdf5::exists(f.id, dem::friction_tests_group))
        data.friction_tests = read_test_table(f.id, dem::friction_tests_group, data);
      if (hdf5::exists(f.id, "quasi_static_check"))
      {
        data.reference_tests = read_test_table(f.id, "quasi_static_check", data);
        const hdf5::Handle g = hdf5::open_group(f.id, "quasi_static_check");
        const auto checks = hdf5::read_strings(g.id, "checks");
        if (checks.size() != data.reference_tests.size())
          throw CalibrationError(file + ": /quasi_static_check/checks and its table differ in length");
        for (std::size_t k = 0; k < checks.size(); ++k)
          data.reference_tests[k].reference_for = checks[k];
      }
    }
    catch (const CalibrationError &)
    {
      throw;
    }
    catch (const std::exception &e)
    {
      throw CalibrationError(file + ": cannot read the campaign (" + e.what() +
                             "): it is torn, cut short or not complete. If a campaign wrote it, run that campaign "
                             "again with --resume: it rewrites campaign.h5 from its tests' results, running only "
                             "the tests that did not complete");
    }
    data.sha256 = util::sha256_of_file(file);
    return data;
  }

  TestHistory CampaignData::history(const CampaignTest &test) const
  {
    const std::string &id = test.id;
    try
    {
      const hdf5::Handle f = hdf5::open_file_read_only(file);
      const std::string path = "tests/" + id + "/history";
      const hdf5::Handle g = hdf5::open_group(f.id, path);
      TestHistory h;
      h.normal_strain = hdf5::read_doubles(g.id, dem::history_column::normal_strain);
      h.shear_strain = hdf5::read_doubles(g.id, dem::history_column::shear_strain);
      const double layer_strain_per_history_strain = test.specimen_height / test.layer_thickness;
      for (auto *strain : {&h.normal_strain, &h.shear_strain})
        for (double &value : *strain)
          value *= layer_strain_per_history_strain;
      h.sigma = hdf5::read_doubles(g.id, dem::history_column::base_normal_stress);
      h.tau = hdf5::read_doubles(g.id, dem::history_column::base_shear_stress);
      h.love_xx = hdf5::read_doubles(g.id, dem::history_column::love_stress("xx"));
      h.love_yy = hdf5::read_doubles(g.id, dem::history_column::love_stress("yy"));
      h.love_zz = hdf5::read_doubles(g.id, dem::history_column::love_stress("zz"));
      const std::size_t n = h.sigma.size();
      for (const auto *c : {&h.normal_strain, &h.shear_strain, &h.tau, &h.love_xx, &h.love_yy, &h.love_zz})
        if (c->size() != n)
          throw CalibrationError("history columns differ in length");
      return h;
    }
    catch (const std::exception &e)
    {
      throw CalibrationError(file + ": history of test " + id + ": " + e.what());
    }
  }
} // namespace anticrack::params
