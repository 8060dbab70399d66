#include "coupling/calibration_scene.h"

#include "dem/campaign/campaign.h"
#include "dem/scene/parameters.h"
#include "dem/scene/dem_run.h"
#include "util/parameter_files.h"
#include "util/parameter_input.h"
#include "util/input_error.h"
#include "util/problems.h"

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <fstream>
#include <iostream>
#include <sstream>

namespace anticrack::coupling
{
  namespace Patterns = dealii::Patterns;

  void CalibrationParameters::declare_parameters(dealii::ParameterHandler &prm)
  {
    prm.enter_subsection("Calibration");
    prm.declare_entry("Poisson's ratio", "", Patterns::Anything(),
                      "nu: Poisson's ratio to use instead of the one measured from the 0 and 90 degree tests "
                      "(E then comes from the axial modulus alone), in (-1, 0.5); empty = measured. For "
                      "specimens that are not isotropic. Dimensionless.");
    prm.declare_entry("Bootstrap resamples", "1000", Patterns::Integer(0, 100000),
                      "Bootstrap resamples of the realizations for the intervals (0: covariance intervals "
                      "only).");
    prm.declare_entry("Bootstrap seed", "1", Patterns::Integer(0), "Seed of the bootstrap resampling.");
    prm.declare_entry("Confidence", "0.95", Patterns::Double(0.5, 0.999),
                      "Level of every interval of the calibration, in [0.5, 0.999]. Dimensionless.");
    prm.declare_entry("Plots", "true", Patterns::Bool(), "Draw the calibration's plots (scripts/plot_calibration.py).");
    prm.leave_subsection();
  }

  void CalibrationParameters::parse_parameters(dealii::ParameterHandler &prm, CalibrateOptions &options)
  {
    prm.enter_subsection("Calibration");
    const std::string nu = dealii::Utilities::trim(prm.get("Poisson's ratio"));
    options.poisson_ratio = nu.empty() ? -2 : dealii::Utilities::string_to_double(nu);
    options.bootstrap_samples = static_cast<int>(prm.get_integer("Bootstrap resamples"));
    options.seed = static_cast<std::uint64_t>(prm.get_integer("Bootstrap seed"));
    options.confidence = prm.get_double("Confidence");
    options.plots = prm.get_bool("Plots");
    prm.leave_subsection();
  }

  namespace
  {
    /// The DEM campaign of a calibration scene, read and checked (its Calibration entries are
    /// declared beside the DEM's so that the reader accepts them).
    dem::SceneParameters read_campaign(const std::string &file,
                                       const std::vector<std::pair<std::string, std::string>> &overrides = {})
    {
      dem::SceneParameters scene =
        dem::read_scene(file, dem::SceneKind::calibration, overrides, CalibrationParameters::declare_parameters);
      dem::require_dem_component(scene);
      return scene;
    }

    /// The options that subsection Calibration of `file` sets, with those of `overrides` (checked by
    /// read_campaign) set after them; throws InputError naming the entry.
    CalibrateOptions calibration_options(const std::string &file,
                                         const std::vector<std::pair<std::string, std::string>> &overrides = {})
    {
      dealii::ParameterHandler prm;
      CalibrationParameters::declare_parameters(prm);
      CalibrateOptions options;
      try
      {
        parse_parameter_text(prm, read_scene_file(file), file, "scene file", /*skip_undefined=*/true);
        for (const auto &[path, value] : overrides)
        {
          const std::vector<std::string> parts = split_parameter_path(path);
          if (parts.size() != 2 || parts.front() != "Calibration")
            continue; // the DEM's and the campaign's: read_campaign's
          prm.enter_subsection(parts.front());
          prm.set(parts.back(), value);
          prm.leave_subsection();
        }
        CalibrationParameters::parse_parameters(prm, options);
      }
      catch (const dealii::ExceptionBase &e)
      {
        std::ostringstream info;
        e.print_info(info);
        throw InputError("Invalid scene file <" + file + ">:\n" + info.str());
      }
      catch (const InputError &)
      {
        throw;
      }
      catch (const std::exception &e)
      {
        throw InputError("Invalid scene file <" + file + ">: Calibration/Poisson's ratio: " + e.what());
      }
      Problems problems("scene file <" + file + ">");
      if (options.poisson_ratio != -2 && !(options.poisson_ratio > -1 && options.poisson_ratio < 0.5))
        problems.add("Calibration/Poisson's ratio", options.poisson_ratio, "must be in (-1, 0.5), or empty (measured)");
      problems.throw_if_any();
      return options;
    }
  } // namespace

  void declare_calibration_scene(dealii::ParameterHandler &prm, const std::string &file, const bool every_variant)
  {
    dem::Declaration declaration;
    if (!file.empty())
      declaration = dem::scene_declaration(file, dem::SceneKind::calibration);
    else if (!every_variant)
      declaration.sample_type = declaration.loading_test = 0; // the first of each: the entries' defaults
    declaration.kind = dem::SceneKind::calibration;
    declaration.declare_more = CalibrationParameters::declare_parameters;
    dem::declare_dem_scene(prm, declaration);
  }

  void check_calibration_scene(const std::string &file, const int threads)
  {
    const dem::SceneParameters scene = read_campaign(file);
    const CalibrateOptions options = calibration_options(file);
    dem::check_dem_scene(scene, threads);
    dem::describe_campaign(std::cout, scene);
    std::cout << "\nCalibration: Cam-Clay surface of the FE point on the tests' paths into the material file, " << options.bootstrap_samples << " bootstrap resamples, "
              << options.confidence * 100 << " % intervals\n";
  }

  CalibrateOptions read_calibration_scene(const std::string &file,
                                          const std::vector<std::pair<std::string, std::string>> &overrides)
  {
    read_campaign(file, overrides); // every problem of the scene before anything is written
    CalibrateOptions options = calibration_options(file, overrides);
    options.input = file;
    return options;
  }

  int run_calibration_scene(const RunOptions &run)
  {
    CalibrateOptions options = read_calibration_scene(run.scene_file);
    options.output_directory = run.output_directory;
    options.overwrite = run.overwrite;
    options.threads = run.threads;
    options.command_line = run.command_line;
    return run_calibration(options);
  }
} // namespace anticrack::coupling
