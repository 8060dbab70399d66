#include "coupling/pipeline.h"

#include "coupling/calibrate.h"
#include "coupling/calibration_scene.h"
#include "coupling/pipeline_scene.h"
#include "coupling/python_script.h"
#include "fem/analysis/run.h"
#include "fem/material/material_file.h"
#include "util/input_error.h"
#include "util/mpi_session.h"
#include "util/progress.h"
#include "util/run_summary.h"
#include "util/sha256.h"
#include "util/worker_processes.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/multithread_info.h>
#include <deal.II/base/parameter_handler.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <thread>


namespace anticrack::coupling
{
  namespace fs = std::filesystem;
  using Clock = std::chrono::steady_clock;

  namespace
  {
    constexpr const char *weak_layer_directory = "weak_layer";

    struct Stage
    {
      std::string name;          ///< "weak layer", or the snowpack scene's stem
      std::string kind;          ///< calibration | snowpack
      fs::path directory;
      std::string inputs_sha256;
      std::string status = "pending"; ///< pending | completed | completed earlier | failed | interrupted
      double wall_s = 0;
      Json results;              ///< the headline of the stage's summary.json
      std::string scene_file;    ///< the scene the stage runs
    };

    std::string text_of(const fs::path &file)
    {
      std::ifstream in(file);
      std::ostringstream text;
      text << in.rdbuf();
      return text.str();
    }

    Json read_json(const fs::path &file)
    {
      std::ifstream in(file);
      if (!in)
        return Json();
      try
      {
        return Json::parse(in);
      }
      catch (const std::exception &)
      {
        return Json();
      }
    }

    /// The snowpack scene with its weak layer's material set to `material` (the last setting of an
    /// entry wins in a parameter file, so the original text stays as it was, above).
    std::string scene_with_material(const std::string &scene_file, const fs::path &material)
    {
      return text_of(scene_file) + "\n# Added by the pipeline: the weak layer is the calibrated material (the inline\n"
                                   "# weak-layer material entries above are replaced by it).\n"
                                   "subsection Snowpack\n  subsection Weak layer\n    set Material file = " +
             fs::absolute(material).lexically_normal().string() + "\n  end\nend\n";
    }

    /// Stage directories: the scene's stem, numbered if two scenes share one.
    std::vector<std::string> stage_names(const std::vector<std::string> &scenes)
    {
      std::vector<std::string> names;
      for (const std::string &s : scenes)
      {
        std::string name = fs::path(s).stem().string();
        for (int k = 2; std::find(names.begin(), names.end(), name) != names.end(); ++k)
          name = fs::path(s).stem().string() + "_" + std::to_string(k);
        names.push_back(name);
      }
      return names;
    }

    /// The headline of a calibration stage: the material in snow units with its intervals, and how
    /// well the FE point repeats the DEM tests.
    Json calibration_headline(const fs::path &directory)
    {
      const Json summary = read_json(directory / "summary.json");
      Json h;
      if (summary.is_null())
        return h; // the stage did not get as far as its summary
      const Json &m = summary["calibration"]["microstructures"][0];
      const fs::path file = directory / material_file_name(0, 1, true);
      h["material_file"] = file.string();
      const fem::MaterialFile material = fem::read_material_file_text(text_of(file), file.string());
      for (const fem::MaterialEntry &e : fem::material_entries())
        if (e.number)
        {
          Json entry{{"value", material.material.*e.number}};
          if (e.interval)
          {
            const fem::MaterialInterval &i = material.uncertainty.*e.interval;
            entry["interval"] = {i.lower, i.upper};
          }
          h["material"][e.name()] = entry;
        }
      h["confidence"] = material.uncertainty.confidence;
      h["material_point_replay"] = {{"largest_angle_error", m["material_point_replay"]["largest_angle_error"]},
                                    {"fit_relative_rmse", m["material_point_replay"]["fit_relative_rmse"]}};
      h["wall_s"] = summary["timing"]["wall_s"];
      return h;
    }

    /// The headline of a snowpack stage (the FE's results without the bulky entries).
    Json snowpack_headline(const fs::path &directory)
    {
      const Json summary = read_json(directory / "summary.json");
      if (summary.is_null())
        return Json(); // the stage did not get as far as its summary
      Json h{{"status", summary["status"]}};
      for (const char *key : {"analysis", "critical_cut_length_m", "crack", "arrest_position_m",
                              "propagation_speed_m_per_s", "touchdown_distance_m", "fracture_energy_J_per_m2"})
        if (summary["results"].contains(key))
          h[key] = summary["results"][key];
      return h;
    }

    Json stage_json(const Stage &s)
    {
      return Json{{"name", s.name},       {"kind", s.kind},     {"directory", s.directory.filename().string()},
                  {"scene", s.scene_file}, {"inputs_sha256", s.inputs_sha256},
                  {"status", s.status},   {"wall_s", s.wall_s}, {"results", s.results}};
    }

    /// "about 3 min 20 s left" from the earlier run's wall times of the stages not done yet.
    std::string time_left(const std::vector<Stage> &stages, std::size_t from, const std::map<std::string, Json> &before)
    {
      double left = 0;
      for (std::size_t k = from; k < stages.size(); ++k)
      {
        const auto it = before.find(stages[k].name);
        if (it == before.end() || !it->second.contains("wall_s") || !it->second["wall_s"].is_number() ||
            it->second["wall_s"].get<double>() <= 0)
          return "no estimate of the time left (first run of these stages)";
        left += it->second["wall_s"].get<double>();
      }
      return "about " + format_duration(left) + " left (the earlier run's stage times)";
    }

    std::string number(double v, int digits = 3)
    {
      std::ostringstream s;
      s.precision(digits);
      s << v;
      return s.str();
    }

    /// The short version of the report, printed at the end of the run.
    std::string short_report(const fs::path &dir, const std::vector<Stage> &stages)
    {
      std::ostringstream out;
      out << "anticrack pipeline: " << dir.string() << "\n";
      const Json &w = stages.front().results;
      if (w.contains("material"))
      {
        const auto with_interval = [&](const char *entry, double scale, const char *unit) {
          const Json &e = w["material"][entry];
          std::string text = number(e["value"].get<double>() * scale) + unit;
          if (e.contains("interval") && e["interval"][0].is_number())
            text += " [" + number(e["interval"][0].get<double>() * scale) + ", " +
                    number(e["interval"][1].get<double>() * scale) + "]";
          return text;
        };
        out << "  weak layer (" << fs::path(w["material_file"].get<std::string>()).filename().string() << ", "
            << number(100 * w.value("confidence", 0.95)) << " % intervals): p0 = "
            << with_interval("Compressive strength p0 [Pa]", 1e-3, " kPa")
            << ", beta = " << with_interval("Tensile strength ratio beta", 1, "")
            << ", M = " << with_interval("Critical state slope M", 1, "")
            << ", E = " << with_interval("Young's modulus [Pa]", 1e-6, " MPa")
            << ", xi = " << with_interval("Hardening factor xi", 1, "")
            << ", density " << number(w["material"]["Density [kg/m^3]"]["value"].get<double>()) << " kg/m^3\n"
            << "    the FE point repeats the DEM tests to " << number(100 * w["material_point_replay"]["largest_angle_error"].get<double>(), 2)
            << " % at worst per angle (fit RMSE " << number(100 * w["material_point_replay"]["fit_relative_rmse"].get<double>(), 2) << " %)\n";
      }
      for (std::size_t k = 1; k < stages.size(); ++k)
      {
        const Json &r = stages[k].results;
        out << "  " << stages[k].name << ": " << stages[k].status;
        const auto metres = [&](const char *key, const char *what) {
          if (r.contains(key) && r[key].is_number())
            out << ", " << what << " " << number(r[key].get<double>()) << " m";
        };
        if (r.contains("crack"))
          out << ", crack " << r["crack"].get<std::string>();
        metres("critical_cut_length_m", "critical cut");
        if (r.contains("propagation_speed_m_per_s") && r["propagation_speed_m_per_s"].is_number())
          out << ", speed " << number(r["propagation_speed_m_per_s"].get<double>()) << " m/s";
        metres("touchdown_distance_m", "touchdown distance");
        metres("arrest_position_m", "arrested at");
        out << "\n";
      }
      out << "  wall time per stage:";
      for (const Stage &s : stages)
        out << " " << s.name << " " << format_duration(s.wall_s) << (s.status == "completed earlier" ? " (earlier)" : "") << ";";
      out << "\n  report: " << (dir / "report.md").string() << ", " << (dir / "report.png").string() << "\n";
      return out.str();
    }

    int cores(const RunOptions &options)
    {
      return options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
    }
  } // namespace

  void declare_pipeline(dealii::ParameterHandler &prm, const std::string &, bool) { declare_pipeline_scene(prm); }

  void check_pipeline_scene(const std::string &file, int)
  {
    const PipelineScene scene = read_pipeline_scene(file);
    std::cout << "pipeline " << file << ":\n  1. weak layer: " << scene.weak_layer_scene
              << " (campaign, calibration, material in snow units: bond tensile strength "
              << scene.snow.bond_tensile_strength << " Pa, grain density " << scene.snow.particle_density << " kg/m^3)\n";
    for (std::size_t k = 0; k < scene.snowpack_scenes.size(); ++k)
      std::cout << "  " << k + 2 << ". " << scene.snowpack_scenes[k] << " with the calibrated weak layer\n";
    std::cout << "  then report.md, report.png and summary.json\n";
  }

  int run_pipeline_scene(const RunOptions &options)
  {
    const auto start = Clock::now();
    const PipelineScene scene = read_pipeline_scene(options.scene_file); // every problem before anything is written
    const fs::path dir(options.output_directory);
    std::error_code error;
    if (fs::exists(dir / "summary.json", error) && !options.resume && !options.overwrite)
      throw InputError("The output directory <" + dir.string() + "> already holds a pipeline (summary.json). Use "
                       "--resume to run only the stages whose inputs changed or did not complete, --overwrite to "
                       "start again, or another directory.");

    // Under mpirun every stage runs on all ranks and MPI is initialised once, here, for all of
    // them (the campaign's session then finds it initialised). Without mpirun nothing in this
    // process initialises MPI: the campaign forks its workers and each FE stage gets a process.
    const bool under_mpirun = launched_by_mpirun();
    std::optional<dealii::Utilities::MPI::MPI_InitFinalize> mpi;
    if (under_mpirun)
    {
      static int argc = 1;
      static char name[] = "anticrack";
      static char *argv_storage[] = {name, nullptr};
      static char **argv = argv_storage;
      mpi.emplace(argc, argv, 1);
    }
    const bool root = !under_mpirun || dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    const auto barrier = [&] {
      if (under_mpirun)
        MPI_Barrier(MPI_COMM_WORLD);
    };

    std::map<std::string, Json> before; // the earlier run's stage records, by name
    if (options.resume)
      for (const Json &s : read_json(dir / "summary.json").value("stages", Json::array()))
        before[s.value("name", "")] = s;
    const std::vector<std::string> names = stage_names(scene.snowpack_scenes);
    if (root)
    {
      // --overwrite starts again: every stage's folder goes too (the campaign's tests included).
      if (options.overwrite && !options.resume)
      {
        for (const char *name : {"summary.json", "report.md", "report.png", weak_layer_directory})
          fs::remove_all(dir / name, error);
        for (const std::string &name : names)
          fs::remove_all(dir / name, error);
      }
      fs::create_directories(dir);
    }
    barrier();

    std::vector<Stage> stages;
    {
      Stage s;
      s.name = "weak layer";
      s.kind = "calibration";
      s.directory = dir / weak_layer_directory;
      s.scene_file = scene.weak_layer_scene;
      std::ostringstream snow;
      snow.precision(17);
      snow << "\nSnow units: " << scene.snow.bond_tensile_strength << " " << scene.snow.particle_density;
      s.inputs_sha256 = util::sha256_hex(text_of(scene.weak_layer_scene) + snow.str());
      stages.push_back(s);
    }
    for (std::size_t k = 0; k < names.size(); ++k)
    {
      Stage s;
      s.name = names[k];
      s.kind = "snowpack";
      s.directory = dir / names[k];
      s.scene_file = (s.directory / "scene.prm").string();
      stages.push_back(s);
    }

    Json summary;
    summary["command"] = options.command_line;
    summary["scene"] = {{"file", scene.file}, {"file_sha256", util::sha256_of_file(scene.file)}};
    const auto write_summary = [&](const std::string &status) {
      if (!root)
        return;
      summary["status"] = status;
      summary["stages"] = Json::array();
      for (const Stage &s : stages)
        summary["stages"].push_back(stage_json(s));
      summary["timing"] = {{"wall_s", std::chrono::duration<double>(Clock::now() - start).count()}};
      summary["versions"] = version_info();
      write_json_atomically((dir / "summary.json").string(), summary);
    };
    const auto unchanged = [&](const Stage &s) {
      const auto it = before.find(s.name);
      return it != before.end() && it->second.value("inputs_sha256", "") == s.inputs_sha256 &&
             (it->second.value("status", "") == "completed" || it->second.value("status", "") == "completed earlier") &&
             fs::exists(s.directory / "summary.json");
    };
    const auto announce = [&](std::size_t k) {
      if (root)
        std::cout << "\npipeline stage " << k + 1 << "/" << stages.size() << ", " << stages[k].name << " ("
                  << stages[k].kind << "): elapsed " << format_duration(std::chrono::duration<double>(Clock::now() - start).count())
                  << ", " << time_left(stages, k, before) << "\n"
                  << std::flush;
    };

    // --- 1. the weak layer: campaign, calibration, material in snow units
    Stage &weak = stages.front();
    const fs::path material = weak.directory / material_file_name(0, 1, true);
    if (unchanged(weak) && fs::exists(material))
    {
      weak.status = "completed earlier";
      weak.wall_s = before[weak.name].value("wall_s", 0.0);
      if (root)
        std::cout << "pipeline stage 1/" << stages.size() << ", weak layer: completed earlier, inputs unchanged\n";
    }
    else
    {
      announce(0);
      CalibrateOptions calibration = read_calibration_scene(scene.weak_layer_scene);
      calibration.output_directory = weak.directory.string();
      calibration.overwrite = true;
      calibration.threads = options.threads;
      calibration.command_line = options.command_line;
      calibration.snow = scene.snow;
      const auto stage_start = Clock::now();
      const int code = run_calibration(calibration);
      weak.wall_s = std::chrono::duration<double>(Clock::now() - stage_start).count();
      barrier();
      weak.status = code == exit_success ? "completed" : code == exit_interrupted ? "interrupted" : "failed";
      if (code != exit_success)
      {
        write_summary(weak.status);
        return code;
      }
    }
    barrier();
    if (!fs::exists(material))
      throw InputError(scene.weak_layer_scene + ": the calibration wrote no " + material.filename().string() +
                       " (a pipeline takes a weak layer of one microstructure: leave Campaign/Microstructures "
                       "empty)");
    weak.results = calibration_headline(weak.directory);
    write_summary("running");

    // --- 2. the snowpack scenes with the calibrated weak layer
    const std::string material_sha256 = util::sha256_of_file(material.string());
    std::vector<std::size_t> to_run;
    for (std::size_t k = 1; k < stages.size(); ++k)
    {
      Stage &s = stages[k];
      const std::string text = scene_with_material(scene.snowpack_scenes[k - 1], material);
      s.inputs_sha256 = util::sha256_hex(text + "\nmaterial " + material_sha256);
      if (unchanged(s))
      {
        s.status = "completed earlier";
        s.wall_s = before[s.name].value("wall_s", 0.0);
        s.results = snowpack_headline(s.directory);
        if (root)
          std::cout << "pipeline stage " << k + 1 << "/" << stages.size() << ", " << s.name
                    << ": completed earlier, inputs unchanged\n";
        continue;
      }
      if (root)
      {
        fs::create_directories(s.directory);
        std::ofstream(s.scene_file) << text;
      }
      to_run.push_back(k);
    }
    barrier();
    const auto run_options_of = [&](const Stage &s) {
      RunOptions o;
      o.scene_file = s.scene_file;
      o.output_directory = s.directory.string();
      o.overwrite = true;
      o.command_line = options.command_line;
      return o;
    };
    const auto finish = [&](Stage &s, int code, double wall) {
      s.wall_s = wall;
      s.status = code == exit_success ? "completed" : code == exit_interrupted ? "interrupted" : "failed";
      s.results = snowpack_headline(s.directory);
      if (root)
        std::cout << "pipeline stage " << s.name << ": " << s.status << " in " << format_duration(wall) << "\n"
                  << std::flush;
    };
    bool interrupted = false, failed = false;
    if (!to_run.empty())
    {
      announce(to_run.front());
      if (under_mpirun)
        for (const std::size_t k : to_run)
        {
          const auto stage_start = Clock::now();
          const int code = fem::run_snowpack_scene_in_mpi(run_options_of(stages[k]));
          finish(stages[k], code, std::chrono::duration<double>(Clock::now() - stage_start).count());
          write_summary("running");
        }
      else
      {
        // Side by side, one process per analysis (each initialises MPI for itself), one core each.
        std::vector<Clock::time_point> started(to_run.size(), Clock::now());
        run_jobs_in_worker_processes(
          static_cast<int>(to_run.size()), std::min<int>(cores(options), static_cast<int>(to_run.size())),
          [&](int job, std::string &) {
            dealii::MultithreadInfo::set_thread_limit(1);
            const Stage &s = stages[to_run[static_cast<std::size_t>(job)]];
            const LineLabel out(std::cout, "[" + s.name + "] "), err(std::cerr, "[" + s.name + "] ");
            return fem::run_snowpack_scene(run_options_of(s));
          },
          [&](int job, const WorkerExit &exit) {
            Stage &s = stages[to_run[static_cast<std::size_t>(job)]];
            finish(s, exit.exit_code, std::chrono::duration<double>(Clock::now() - started[static_cast<std::size_t>(job)]).count());
            if (exit.signal != 0)
              std::cerr << "pipeline stage " << s.name << ": " << describe_worker_exit(job, exit) << "\n";
            write_summary("running");
          });
      }
      for (const std::size_t k : to_run)
      {
        interrupted = interrupted || stages[k].status == "interrupted";
        failed = failed || stages[k].status == "failed";
      }
    }

    // --- 3. the report
    Json results;
    results["weak_layer"] = weak.results;
    for (std::size_t k = 1; k < stages.size(); ++k)
      results["analyses"][stages[k].name] = stages[k].results;
    summary["results"] = results;
    write_summary(interrupted ? "interrupted" : failed ? "failed" : "completed");
    if (!root)
      return interrupted ? exit_interrupted : failed ? exit_numerical_failure : exit_success;
    run_python_script("pipeline_report.py", dir.string(), "summary.json and every stage's outputs");
    std::cout << "\n" << short_report(dir, stages) << std::flush;
    return interrupted ? exit_interrupted : failed ? exit_numerical_failure : exit_success;
  }
} // namespace anticrack::coupling
