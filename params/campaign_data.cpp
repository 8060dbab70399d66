#include "params/campaign_data.h"

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
      if (version < 2)
        throw CalibrationError(file + ": campaign format version " + std::to_string(int(version)) +
                               " has no /microstructures table (materials of the samples); rewrite it with "
                               "this anticrack by `anticrack run SCENE -o DIR --resume` (completed tests are "
                               "not run again)");
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

      const hdf5::Handle g = hdf5::open_group(f.id, "failure_points");
      const auto ids = hdf5::read_strings(g.id, "test");
      const std::size_t n = ids.size();
      const auto status = hdf5::read_strings(g.id, "status");
      if (status.size() != n)
        throw CalibrationError(file + ": /failure_points/status and /failure_points/test differ in length");
      const auto microstructure = column(g.id, "microstructure", n, file);
      const auto realization = column(g.id, "realization", n, file);
      const auto angle = column(g.id, "loading_angle_deg", n, file);
      const auto sigma = column(g.id, "sigma", n, file), tau = column(g.id, "tau", n, file);
      const auto p = column(g.id, "p", n, file), q = column(g.id, "q", n, file);
      const auto flow = column(g.id, "flow_angle_deg", n, file);
      const auto solid = column(g.id, "solid_fraction", n, file);
      const auto coordination = column(g.id, "coordination", n, file);
      const auto height = column(g.id, "specimen_height", n, file);
      const auto thickness = column(g.id, "layer_thickness", n, file);
      const auto love = hdf5::read_doubles(g.id, "love_stress");
      if (love.size() != 9 * n)
        throw CalibrationError(file + ": /failure_points/love_stress is not n x 3 x 3");
      for (std::size_t k = 0; k < n; ++k)
      {
        CampaignTest t;
        t.id = ids[k];
        t.status = status[k];
        t.microstructure = static_cast<int>(microstructure[k]);
        t.realization = static_cast<int>(realization[k]);
        if (t.microstructure < 0 || t.microstructure >= static_cast<int>(data.microstructures.size()))
          throw CalibrationError(file + ": test " + t.id + " refers to microstructure " +
                                 std::to_string(t.microstructure) + ", the file describes " +
                                 std::to_string(data.microstructures.size()));
        t.loading_angle_deg = angle[k];
        t.sigma = sigma[k], t.tau = tau[k], t.p = p[k], t.q = q[k];
        for (int c = 0; c < 9; ++c)
          t.love_stress[c] = love[9 * k + c];
        t.flow_angle_deg = flow[k];
        t.solid_fraction = solid[k];
        t.coordination = coordination[k];
        t.specimen_height = height[k];
        t.layer_thickness = thickness[k];
        if (t.completed() && !(t.specimen_height > 0 && t.layer_thickness > 0))
          throw CalibrationError(file + ": test " + t.id + " has no specimen height or layer thickness (it was "
                                 "run by an anticrack "
                                 "older than campaign format 2); delete its directory tests/" + t.id +
                                 " and resume the campaign to run it again");
        data.tests.push_back(t);
      }
    }
    catch (const CalibrationError &)
    {
      throw;
    }
    catch (const std::exception &e)
    {
      throw CalibrationError(file + ": cannot read the campaign (" + e.what() + ")");
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
      h.normal_strain = hdf5::read_doubles(g.id, "normal_strain");
      h.shear_strain = hdf5::read_doubles(g.id, "shear_strain");
      const double layer_strain_per_history_strain = test.specimen_height / test.layer_thickness;
      for (auto *strain : {&h.normal_strain, &h.shear_strain})
        for (double &value : *strain)
          value *= layer_strain_per_history_strain;
      h.sigma = hdf5::read_doubles(g.id, "base_normal_stress");
      h.tau = hdf5::read_doubles(g.id, "base_shear_stress");
      h.love_xx = hdf5::read_doubles(g.id, "love_stress_xx");
      h.love_yy = hdf5::read_doubles(g.id, "love_stress_yy");
      h.love_zz = hdf5::read_doubles(g.id, "love_stress_zz");
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
