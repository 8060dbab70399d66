#include "coupling/calibrate.h"

#include "coupling/calibration_scene.h"
#include "coupling/material_handoff.h"
#include "coupling/material_point_replay.h"
#include "coupling/python_script.h"

#include "dem/campaign/campaign.h"
#include "dem/scene/parameters.h"
#include "fem/material/material_file.h"
#include "params/calibration_error.h"
#include "params/calibration_output.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/mpi_session.h"
#include "util/parameter_files.h"
#include "util/phase_timer.h"
#include "util/run_summary.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>


namespace anticrack::coupling
{
  namespace fs = std::filesystem;

  namespace
  {
    /// Runs the scene's campaign into DIR/campaign (resuming what an earlier call left) and returns
    /// the campaign file; returns "" on ranks other than 0 or when the campaign failed (exit code set).
    std::string campaign_of_scene(const CalibrateOptions &options, int &exit_code)
    {
      // A calibration scene says so; any other scene with a campaign is read as a campaign.
      const dem::SceneKind kind =
        scene_kind_in_file(options.input) == "calibration" ? dem::SceneKind::calibration : dem::SceneKind::campaign;
      const dem::SceneParameters scene = dem::read_scene(
        options.input, kind, {}, kind == dem::SceneKind::calibration ? CalibrationParameters::declare_parameters : nullptr);
      dem::require_dem_component(scene);
      if (!scene.campaign.enabled())
        throw InputError(options.input + ": the scene has no campaign (Campaign/Loading angles [deg] is empty); "
                         "`anticrack calibrate` needs failure points at several loading angles");
      RunOptions run;
      run.scene_file = options.input;
      run.output_directory = (fs::path(options.output_directory) / "campaign").string();
      run.resume = fs::exists(run.output_directory);
      run.threads = options.threads;
      run.command_line = options.command_line;
      exit_code = dem::run_campaign(scene, run);
      // The campaign ran on every rank; only rank 0 calibrates.
      if (exit_code != exit_success || MpiSession::get().rank() != 0)
        return "";
      return (fs::path(run.output_directory) / "campaign.h5").string();
    }
  } // namespace

  std::string material_file_name(std::size_t m, std::size_t count, bool snow)
  {
    return (count == 1 ? std::string("material") : "material_m" + std::to_string(m)) + (snow ? "_snow" : "") + ".prm";
  }

  params::Calibration calibrate_to_the_fe_points_peaks(const params::CampaignData &campaign,
                                                       params::CalibrationOptions options)
  {
    // The path fit puts the surface's first yield on the DEM's failures divided by the FE point's
    // peak over its first yield on each test's path (coupling/material_point_replay.h), which
    // depends on the surface: fixed-point iterations from 1 until they settle to 1e-5 in ln. The
    // peaks' own noise, from the path dependence of the plastic steps and the fit's tolerance, is
    // ~2e-6 on the default weak layer, but up to ~1e-4 on some microstructures of a scaling
    // campaign, where the iterations then wander at that level: a last change below 1e-4 after the
    // most iterations is accepted (still 100 times below the fits' RMSE) and recorded.
    // Moving the compression
    // points moves M, which moves their factors back (the map's slope is about −1 in ln: plain
    // iterations oscillate), so each step goes half-way in ln (the error then halves; ~15 refits).
    constexpr int most_iterations = 40;
    constexpr double settled = 1e-5, noise_floor = 1e-4;
    constexpr double relaxation = 0.5;
    // The factors need the fits' values only: the bootstrap (intervals) waits for the last fit.
    const int bootstrap_samples = options.bootstrap_samples;
    options.bootstrap_samples = 0;
    params::Calibration calibration = params::calibrate(campaign, options);
    for (int iteration = 0;; ++iteration)
    {
      std::map<std::string, double> factors;
      for (std::size_t m = 0; m < calibration.microstructures.size(); ++m)
      {
        if (!calibration.microstructures[m].material_refused.empty())
        {
          // Refused in this refit: its tests keep their factors (dropping them would move its
          // points back to the first yields and the iterations would cycle).
          for (const params::CampaignTest &t : calibration.microstructures[m].tests)
            if (const auto before = options.path_peak_factors.find(t.id); before != options.path_peak_factors.end())
              factors.insert(*before);
          continue;
        }
        // The hand-off's material before the file rounds it to six digits (a rounded surface makes
        // the map a staircase on which the iterations cycle).
        const MaterialPointReplay replay =
          replay_tests(calibration.microstructures[m], material_handoff(calibration, m, "").material);
        factors.insert(replay.peak_over_first_yield.begin(), replay.peak_over_first_yield.end());
      }
      double change = 0;
      for (const auto &[id, factor] : factors)
      {
        const auto before = options.path_peak_factors.find(id);
        change = std::max(change, std::abs(std::log(factor / (before == options.path_peak_factors.end() ? 1.0 : before->second))));
      }
      if (change < settled || (iteration == most_iterations && change < noise_floor))
      {
        if (bootstrap_samples > 0)
        {
          options.bootstrap_samples = bootstrap_samples;
          calibration = params::calibrate(campaign, options);
        }
        calibration.peak_factor_refits = iteration;
        calibration.peak_factor_last_change = change;
        return calibration;
      }
      if (iteration == most_iterations)
        throw params::CalibrationError(campaign.file + ": the FE material point's peaks over its first yields do not "
                                       "settle in " + std::to_string(most_iterations) + " half-way refits of the surface (last change " +
                                       std::to_string(change) + " in ln)");
      for (auto &[id, factor] : factors)
      {
        const auto before = options.path_peak_factors.find(id);
        const double previous = before == options.path_peak_factors.end() ? 1.0 : before->second;
        factor = previous * std::pow(factor / previous, relaxation);
      }
      options.path_peak_factors = factors;
      calibration = params::calibrate(campaign, options);
    }
  }

  int run_calibration(const CalibrateOptions &options)
  {
    const auto start = std::chrono::steady_clock::now();
    const fs::path directory(options.output_directory);
    const bool from_scene = fs::path(options.input).extension() == ".prm";
    const std::vector<std::string> outputs = {"calibration.h5", "summary.json"};
    if (!options.overwrite)
      for (const auto &name : outputs)
        if (fs::exists(directory / name))
          throw InputError((directory / name).string() + " exists: an earlier calibration is in " +
                           directory.string() + "; choose another directory or pass --overwrite");

    PhaseTimer timer;
    int exit_code = exit_success;
    std::string campaign_file = options.input;
    if (from_scene)
    {
      const auto phase = timer.scope("campaign");
      campaign_file = campaign_of_scene(options, exit_code);
    }
    if (campaign_file.empty())
      return exit_code;

    params::Calibration calibration;
    try
    {
      params::CalibrationOptions calibration_options;
      calibration_options.confidence = options.confidence;
      if (options.poisson_ratio > -1)
        calibration_options.poisson_ratio = options.poisson_ratio;
      calibration_options.bootstrap_samples = options.bootstrap_samples;
      calibration_options.seed = options.seed;
      params::CampaignData campaign;
      {
        const auto phase = timer.scope("read campaign");
        campaign = params::read_campaign(campaign_file);
      }
      const auto phase = timer.scope("fits and intervals");
      calibration = calibrate_to_the_fe_points_peaks(campaign, calibration_options);
    }
    catch (const params::CalibrationError &e)
    {
      throw InputError(e.what());
    }

    // Everything is computed and every material file is read back as the FE solver reads it; only
    // then are files written, each through a temporary name.
    std::optional<PhaseTimer::Scope> output_phase;
    output_phase.emplace(timer, "output");
    const std::string version = version_info()["anticrack"].get<std::string>();
    std::vector<std::string> material_names, material_texts;
    std::map<std::size_t, MaterialPointReplay> replays; // per microstructure with a material
    for (std::size_t m = 0; m < calibration.microstructures.size(); ++m)
    {
      if (!calibration.microstructures[m].material_refused.empty())
      {
        std::cerr << "anticrack calibrate: no material file for microstructure " << m << ": "
                  << calibration.microstructures[m].material_refused << "\n";
        continue;
      }
      const fem::MaterialFile file = material_handoff(calibration, m, version);
      material_names.push_back(material_file_name(m, calibration.microstructures.size()));
      material_texts.push_back(fem::material_file_text(file));
      // The material as the solver reads it, driven along the DEM tests' paths.
      replays.emplace(m, replay_tests(calibration.microstructures[m],
                                      fem::read_material_text(material_texts.back(), material_names.back())));
      if (options.snow)
      {
        material_names.push_back(material_file_name(m, calibration.microstructures.size(), true));
        material_texts.push_back(
          fem::material_file_text(in_snow_units(file, calibration.microstructures[m], *options.snow)));
        fem::read_material_text(material_texts.back(), material_names.back());
      }
    }
    fs::create_directories(directory);
    for (std::size_t m = 0; m < material_names.size(); ++m)
    {
      write_text_atomically((directory / material_names[m]).string(),
                            [&](std::ostream &out) { out << material_texts[m]; });
    }
    params::write_calibration_data(calibration, (directory / "calibration.h5").string());

    Json summary;
    summary["status"] = "completed";
    summary["command"] = options.command_line;
    summary["input"] = options.input;
    summary["calibration"] = params::calibration_summary(calibration);
    for (const auto &[m, replay] : replays)
      summary["calibration"]["microstructures"][m]["material_point_replay"] = replay_json(replay);
    summary["outputs"] = Json{{"data", "calibration.h5"}, {"materials", material_names}, {"summary", "summary.json"}};
    output_phase.reset();
    const auto now = std::chrono::steady_clock::now();
    // The plots (a Python script, after summary.json) are not among the phases.
    summary["timing"] = Json{{"wall_s", std::chrono::duration<double>(now - start).count()},
                             {"calibration_s", timer.seconds("read campaign") + timer.seconds("fits and intervals")},
                             {"phases", timer.to_json()}};
    summary["versions"] = version_info();
    write_json_atomically((directory / "summary.json").string(), summary);

    // The first microstructure with a material (calibrate refuses a campaign where none has one).
    const auto &[shown, shown_replay] = *replays.begin();
    const params::MicrostructureCalibration &shown_calibration = calibration.microstructures[shown];
    const params::PlaneCalibration &first = shown_calibration.material_plane();
    const params::CamClaySurface surface = first.cam_clay_surface();
    const params::SofteningEstimate &softening = shown_calibration.softening;
    std::cout << "anticrack calibrate: " << calibration.microstructures.size() << " microstructure(s) from "
              << campaign_file << " (" << replays.size() << " with a material file)\n  microstructure " << shown
              << ", FE point on the tests' paths (lateral stress ratio "
              << shown_calibration.path.lateral_stress_ratio() << "): p0 = " << surface.p0 << " Pa, beta = " << surface.beta << ", M = " << surface.M
              << ", R^2 = " << first.cam_clay().r_squared
              << "\n  the FE point repeats the DEM tests: largest error of an angle's mean failure stress "
              << 100 * shown_replay.largest_angle_error() << " % (fit RMSE " << 100 * shown_replay.fit_rmse
              << " %)\n  softening from the " << softening.source << ": R = " << softening.residual_ratio.mean
              << ", xi = " << softening.hardening_factor.mean;
    if (softening.lock_up_strain.n > 0)
      std::cout << ", lock-up strain " << softening.lock_up_strain.mean << ", fracture energy density "
                << softening.fracture_energy_density.mean << " J/m^3";
    if (const params::FrictionEstimate &friction = shown_calibration.friction; friction.measured())
      std::cout << "\n  friction of the collapsed layer (" << friction.readings.size()
                << " friction test(s)): mu = " << friction.friction_coefficient.mean << " ["
                << friction.friction_coefficient.mean_ci.lower << ", " << friction.friction_coefficient.mean_ci.upper
                << "]";
    // A surface that explains little of the failure stresses is still written (its intervals say how
    // little is known), but never without saying so.
    constexpr double poor_fit_r_squared = 0.5;
    for (const params::MicrostructureCalibration &c : calibration.microstructures)
      if (c.material_plane().cam_clay().r_squared < poor_fit_r_squared)
        std::cout << "\n  WARNING: microstructure " << c.index << "'s surface explains R^2 = "
                  << c.material_plane().cam_clay().r_squared << " of its failure stresses (< " << poor_fit_r_squared
                  << "): the campaign's scatter dominates; see the intervals in the material file's subsection "
                     "Material/Uncertainty, or run more realizations";
    for (const params::MicrostructureCalibration &c : calibration.microstructures)
      if (!c.tests_left_out.empty())
      {
        std::cout << "\n  microstructure " << c.index << ": " << c.tests_left_out.size() << " test(s) left out:";
        for (const std::string &t : c.tests_left_out)
          std::cout << "\n    " << t;
      }
    std::cout << "\n  wrote " << directory.string() << "/{"
              << material_names.front() << (material_names.size() > 1 ? ", ..." : "")
              << ", calibration.h5, summary.json}" << std::endl; // before the plot script's lines

    // A failed plot fails the run (the plots are among its outputs); --no-plots skips them.
    if (options.plots && !run_python_script("plot_calibration.py", directory.string(), "the data files"))
      return exit_numerical_failure;
    return exit_success;
  }
} // namespace anticrack::coupling
