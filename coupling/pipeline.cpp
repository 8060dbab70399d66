#include "coupling/pipeline.h"

#include "coupling/calibrate.h"
#include "coupling/calibration_scene.h"
#include "coupling/material_cache.h"
#include "coupling/pipeline_scene.h"
#include "coupling/pipeline_uncertainty.h"
#include "coupling/python_script.h"
#include "fem/analysis/snowpack_command.h"
#include "fem/material/material_file.h"
#include "fem/scene/analysis_type.h"
#include "fem/scene/snowpack_scene.h"
#include "util/input_error.h"
#include "util/atomic_file.h"
#include "util/mpi_session.h"
#include "util/parameter_files.h"
#include "util/format.h"
#include "util/progress.h"
#include "util/run_summary.h"
#include "util/sha256.h"
#include "util/worker_processes.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
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
      Json material_cache;       ///< a weak layer: what the material cache gave or took (null: no cache)
      Json weak_layer;           ///< a snowpack stage: its weak layer's stage and, from a pit, the pit's layer and class
    };

    /// What an earlier run of the pipeline recorded of its stages (its summary.json), by name; empty
    /// when it got no further than its first stage (killed before its first summary). A summary that
    /// is not a pipeline's (torn, or another kind's) is refused naming it (UnusableOutputFile).
    std::map<std::string, Json> earlier_stages(const fs::path &dir)
    {
      std::map<std::string, Json> before;
      const fs::path file = dir / "summary.json";
      std::error_code error;
      if (!fs::exists(file, error))
        return before;
      return interpret_json_file(
        file.string(), "a pipeline's summary (a list of stages, each with its name, status and input hash)",
        [&](const Json &summary) {
          for (const Json &s : summary.at("stages"))
          {
            // The types each field must have, checked here: a foreign file is refused now, not
            // misread later.
            s.at("inputs_sha256").get<std::string>();
            s.at("status").get<std::string>();
            s.at("wall_s").get<double>();
            before[s.at("name").get<std::string>()] = s;
          }
          return before;
        },
        "Run again with --overwrite to start afresh, or delete " + file.string() +
          ": every stage then runs again, the weak layer's campaign keeping its completed tests and each "
          "PST that completed with the same inputs.");
    }

    /// A stage's summary.json read by `headline` (null if the stage did not get as far as writing
    /// one); a summary that is not a `kind` is refused naming it, and to delete the stage's folder.
    template <class Headline>
    Json stage_summary_headline(const fs::path &directory, const std::string &kind, Headline &&headline)
    {
      std::error_code error;
      const fs::path file = directory / "summary.json";
      if (!fs::exists(file, error))
        return headline(Json());
      return interpret_json_file(file.string(), kind, headline,
                                 "Delete " + directory.string() + " to run that stage again, or run the pipeline "
                                 "with --overwrite to start afresh.");
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
      return stage_summary_headline(directory, "a calibration's summary", [&](const Json &summary) {
      Json h;
      if (summary.is_null())
        return h; // the stage did not get as far as its summary
      const Json &m = summary.at("calibration").at("microstructures").at(0);
      const fs::path file = directory / material_file_name(0, 1, true);
      h["material_file"] = file.string();
      const fem::MaterialFile material = fem::read_material_file_text(read_text_file((file).string()), file.string());
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
      h["material_point_replay"] = {{"largest_angle_error", m.at("material_point_replay").at("largest_angle_error")},
                                    {"fit_relative_rmse", m.at("material_point_replay").at("fit_relative_rmse")}};
      h["wall_s"] = summary.at("timing").at("wall_s");
      return h;
      });
    }

    /// The headline of a snowpack stage (the FE's results without the bulky entries).
    Json snowpack_headline(const fs::path &directory)
    {
      return stage_summary_headline(directory, "an FE run's summary", [&](const Json &summary) {
        if (summary.is_null())
          return Json::object(); // the stage did not get as far as its summary
        Json h{{"status", summary.at("status").get<std::string>()}};
        const Json results = summary.value("results", Json::object()); // none when the run stopped early
        if (results.contains("mesh"))
          h["element_length_m"] = results.at("mesh").value("element_length_m", 0.0);
        std::vector<const char *> keys = {"analysis",          "outcome",          "arrest_position_m",
                                          "slab_fracture",     "critical_cut_bracket_m", "critical_cut_method",
                                          "tip_lead_onset_m",  "onset",            "series_directory",
                                          "fracture_energy_J_per_m2", "critical_cut_length_interval", "gaume2017"};
        for (const PstAnswer &a : pst_answers())
          keys.push_back(a.key);
        for (const char *key : keys)
          if (results.contains(key))
            h[key] = results.at(key);
        // A snowpack from a real pit: its observed saw test, beside the prediction.
        const Json profile = summary.at("scene").value("profile", Json());
        if (profile.is_object() && profile.contains("observed_saw_test"))
          h["observed_saw_test"] = profile.at("observed_saw_test");
        return h;
      });
    }

    /// For a sensitivity run of a stage whose critical cut is a fixed-cut search (PST/Saw =
    /// practice or bisection): the scene lines that start its trials at the stage's shortest ending
    /// cut, a bisection a few trials from the answer (one parameter moved by one standard error
    /// moves the cut by a few elements), instead of a saw run and its trials. The answer does not
    /// depend on where the trials start (fem/analysis/critical_cut_search.h). Empty otherwise.
    std::string first_trial_near(const Stage &stage)
    {
      const Json bracket = stage.results.value("critical_cut_bracket_m", Json());
      if (!stage.results.contains("onset") || !bracket.is_array() || bracket.size() != 2)
        return "";
      return "\n# Added by the pipeline's uncertainty stage: the fixed-cut trials start at the shortest cut\n"
             "# that ended the test in " + stage.name + " (PST/Saw = bisection, seeded; the answer does not\n"
             "# depend on the seed, the trial count does).\nsubsection PST\n  set Saw = bisection\n"
             "  set First trial cut [m] = " + format_number(bracket[1].get<double>(), 17) + "\nend\n";
    }

    /// The wall time an FE run recorded in its summary.json.
    double snowpack_wall_s(const fs::path &directory)
    {
      return stage_summary_headline(directory, "an FE run's summary", [](const Json &summary) {
        return summary.is_null() ? 0.0 : summary.at("timing").at("wall_s").get<double>();
      });
    }

    Json stage_json(const Stage &s)
    {
      Json j{{"name", s.name},       {"kind", s.kind},     {"directory", s.directory.filename().string()},
             {"scene", s.scene_file}, {"inputs_sha256", s.inputs_sha256},
             {"status", s.status},   {"wall_s", s.wall_s}, {"results", s.results}};
      if (!s.material_cache.is_null())
        j["material_cache"] = s.material_cache;
      if (!s.weak_layer.is_null())
        j["weak_layer"] = s.weak_layer;
      return j;
    }


    /// "about 3 min 20 s left" from the earlier run's wall times of the stages not done yet, or for
    /// stage `from` itself from `estimate` (this run's measure of it) where there is no earlier run.
    std::string time_left(const std::vector<Stage> &stages, std::size_t from, const std::map<std::string, Json> &before,
                          std::optional<double> estimate = std::nullopt)
    {
      double left = 0;
      for (std::size_t k = from; k < stages.size(); ++k)
      {
        const auto it = before.find(stages[k].name);
        if (it != before.end() && it->second.contains("wall_s") && it->second["wall_s"].is_number() &&
            it->second["wall_s"].get<double>() > 0)
          left += it->second["wall_s"].get<double>();
        else if (k == from && estimate)
          left += *estimate;
        else
          return "no estimate of the time left (first run of these stages)";
      }
      return "about " + format_duration(left) + " left" + (estimate ? "" : " (the earlier run's stage times)");
    }

    /// The short version of the report, printed at the end of the run.
    std::string short_report(const fs::path &dir, const std::vector<Stage> &stages, std::size_t weak_layers)
    {
      std::ostringstream out;
      out << "anticrack pipeline: " << dir.string() << "\n";
      for (std::size_t k = 0; k < weak_layers; ++k)
      {
        const Json &w = stages[k].results;
        if (!w.contains("material"))
          continue;
        const auto with_interval = [&](const char *entry, double scale, const char *unit) {
          const Json &e = w["material"][entry];
          std::string text = format_number(e["value"].get<double>() * scale, 3) + unit;
          if (e.contains("interval") && e["interval"][0].is_number() && std::isfinite(e["interval"][0].get<double>()))
            text += " [" + format_number(e["interval"][0].get<double>() * scale, 3) + ", " +
                    format_number(e["interval"][1].get<double>() * scale, 3) + "]";
          return text;
        };
        out << "  " << stages[k].name << " (" << (weak_layers > 1 ? stages[k].directory.filename().string() + "/" : "")
            << fs::path(w["material_file"].get<std::string>()).filename().string() << ", "
            << format_number(100 * w.value("confidence", 0.95), 3) << " % intervals): p0 = "
            << with_interval("Compressive strength p0 [Pa]", 1e-3, " kPa")
            << ", beta = " << with_interval("Tensile strength ratio beta", 1, "")
            << ", M = " << with_interval("Critical state slope M", 1, "")
            << ", E = " << with_interval("Young's modulus [Pa]", 1e-6, " MPa")
            << ", xi = " << with_interval("Hardening factor xi", 1, "")
            << ", density " << format_number(w["material"]["Density [kg/m^3]"]["value"].get<double>(), 3) << " kg/m^3\n"
            << "    the FE point repeats the DEM tests to " << format_number(100 * w["material_point_replay"]["largest_angle_error"].get<double>(), 2)
            << " % at worst per angle (fit RMSE " << format_number(100 * w["material_point_replay"]["fit_relative_rmse"].get<double>(), 2) << " %)\n";
      }
      const Json &uncertainty = stages.back().results;
      for (std::size_t k = weak_layers; k + 1 < stages.size(); ++k)
      {
        const Json &r = stages[k].results;
        const Json intervals = uncertainty.contains(stages[k].name) ? uncertainty[stages[k].name]["answers"] : Json();
        out << "  " << stages[k].name << ": " << stages[k].status;
        // The value, with its interval and dominant parameter when the uncertainty stage has them.
        const auto answer = [&](const char *key, const char *what, const char *unit) {
          if (!r.contains(key) || !r[key].is_number())
            return;
          out << ", " << what << " " << format_number(r[key].get<double>(), 3) << " " << unit;
          if (intervals.contains(key) && intervals[key].contains("interval"))
            out << " [" << format_number(intervals[key]["interval"][0].get<double>(), 3) << ", "
                << format_number(intervals[key]["interval"][1].get<double>(), 3) << "] (mostly "
                << intervals[key]["dominant_parameter"].get<std::string>() << ")";
          else if (intervals.contains(key))
            out << " (" << intervals[key].value("status", std::string()) << ")";
        };
        if (r.contains("outcome"))
          out << ", outcome " << r["outcome"].get<std::string>();
        for (const PstAnswer &a : pst_answers())
          answer(a.key, a.label, a.unit);
        answer("arrest_position_m", "arrested at", "m");
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

    /// An FE analysis of the pipeline: a label for its lines and the run.
    struct FeJob
    {
      std::string label;
      RunOptions options;
    };

    /// Runs `jobs`: without mpirun side by side, one process per analysis (each initialises MPI
    /// for itself) on one core each, `cores` at a time; under mpirun one after another on all
    /// ranks. `done(k, exit code, wall time)` after each (in the parent).
    void run_fe_jobs(const std::vector<FeJob> &jobs, bool under_mpirun, int cores,
                     const std::function<void(std::size_t, int, double)> &done)
    {
      if (jobs.empty())
        return;
      if (under_mpirun)
      {
        for (std::size_t k = 0; k < jobs.size(); ++k)
        {
          const auto start = Clock::now();
          const int code = fem::run_snowpack_scene_in_mpi(jobs[k].options);
          MPI_Barrier(MPI_COMM_WORLD); // rank 0 writes the run's summary.json, which `done` reads
          done(k, code, std::chrono::duration<double>(Clock::now() - start).count());
        }
        return;
      }
      const int n = static_cast<int>(jobs.size());
      run_jobs_in_worker_processes(
        n, std::min(cores, n),
        [&](int job, std::string &) {
          const FeJob &j = jobs[static_cast<std::size_t>(job)];
          const LineLabel out(std::cout, "[" + j.label + "] "), err(std::cerr, "[" + j.label + "] ");
          return fem::run_snowpack_scene(j.options);
        },
        [&](int job, const WorkerExit &exit) {
          const auto k = static_cast<std::size_t>(job);
          if (exit.signal != 0)
            std::cerr << jobs[k].label << ": " << describe_worker_exit(job, exit) << "\n";
          done(k, exit.exit_code, exit.wall_s);
        });
    }

    RunOptions fe_run_options(const std::string &scene_file, const fs::path &directory, const RunOptions &options)
    {
      RunOptions o;
      o.scene_file = scene_file;
      o.output_directory = directory.string();
      o.overwrite = true;
      o.command_line = options.command_line;
      return o;
    }

    std::string status_of(int code)
    {
      return code == exit_success ? "completed" : code == exit_interrupted ? "interrupted" : "failed";
    }
  } // namespace

  void declare_pipeline(dealii::ParameterHandler &prm, const std::string &, bool) { declare_pipeline_scene(prm); }

  void check_pipeline_scene(const std::string &file, int)
  {
    const PipelineScene scene = read_pipeline_scene(file);
    const std::size_t weak_layers = scene.weak_layers.size();
    std::cout << "pipeline " << file << ":\n";
    for (std::size_t k = 0; k < weak_layers; ++k)
    {
      const WeakLayerVariant &v = scene.weak_layers[k];
      std::cout << "  " << k + 1 << ". " << v.name << ": " << scene.weak_layer_scene
                << " (campaign, calibration, material in snow units: bond tensile strength "
                << scene.snow.bond_tensile_strength << " Pa, bond modulus " << scene.snow.bond_modulus
                << " Pa, grain diameter " << scene.snow.grain_diameter << " m, grain density "
                << scene.snow.particle_density << " kg/m^3)\n";
      for (const auto &[path, value] : scene.weak_layer_changes)
        std::cout << "     (with " << path << " = " << value << ")\n";
      if (v.specimen)
      {
        std::cout << "     the specimen of the pits' weak layers of " << v.specimen->name() << " (solid fraction "
                  << format_number(v.specimen->solid_fraction, 4) << ", " << specimen_particle_count(*v.specimen)
                  << " spheres):\n";
        for (const auto &[path, value] : v.specimen_changes)
          std::cout << "     (" << path << " = " << value << ")\n";
      }
      for (const auto &[path, value] : scene.snow_ratio_changes)
        std::cout << "     (at the snow's bond modulus over strength: " << path << " = " << value << ")\n";
    }
    for (std::size_t k = 0; k < scene.snowpack_scenes.size(); ++k)
    {
      const SnowpackWeakLayer &w = scene.snowpack_weak_layers[k];
      std::cout << "  " << k + weak_layers + 1 << ". " << scene.snowpack_scenes[k] << " with the calibrated "
                << scene.weak_layers[w.variant].name;
      if (!w.record.is_null())
        std::cout << " (its pit's layer " << w.record["layer"].get<int>() << ", " << w.record["grain_form"].get<std::string>()
                  << ", " << format_number(w.record["density_kg_m3"].get<double>(), 4) << " kg/m^3, "
                  << format_number(w.record["thickness_in_grains"].get<double>(), 3) << " grains of "
                  << format_number(1e3 * w.grain_diameter, 3) << " mm)";
      std::cout << "\n";
    }
    for (const auto &[path, value] : scene.snowpack_changes)
      std::cout << "     (every snowpack scene with " << path << " = " << value << ")\n";
    if (scene.uncertainty)
      std::cout << "  " << scene.snowpack_scenes.size() + weak_layers + 1
                << ". uncertainty: every snowpack scene again per calibrated parameter raised by one standard error\n";
    std::cout << "  then report.md, report.png and summary.json\n";
  }

  namespace
  {
    /// One run of a pipeline scene, as a sequence of named steps (run()): the output directory, the
    /// stages' plan, the weak layer (campaign, calibration, material in snow units, or the material
    /// cache's), the snowpack scenes with it, the calibration's uncertainty carried to the answers,
    /// and the report. Every step records its stages in summary.json as it goes, so that a killed run
    /// resumes from the last stage it completed.
    class PipelineRun
    {
    public:
      PipelineRun(const RunOptions &options, const PipelineScene &scene)
        : options_(options), scene_(scene), dir_(options.output_directory), start_(Clock::now())
      {}

      int run()
      {
        refuse_an_earlier_pipeline();
        start_mpi();
        // The earlier run's stage records, by name (read, and refused if unusable, before anything is written).
        before_ = options_.resume ? earlier_stages(dir_) : std::map<std::string, Json>();
        names_ = stage_names(scene_.snowpack_scenes);
        prepare_directory();
        plan_stages();
        record_the_scene();
        // One weak layer: its failure ends the pipeline. Several (classes of pits): a class whose
        // campaign or calibration fails takes only its own pits down, the others go on.
        for (std::size_t k = 0; k < scene_.weak_layers.size(); ++k)
          if (const int code = run_weak_layer(k);
              code == exit_interrupted || (code != exit_success && scene_.weak_layers.size() == 1))
            return code;
        run_snowpack_stages();
        run_uncertainty();
        return report();
      }

    private:
      const RunOptions &options_;
      const PipelineScene &scene_;
      const fs::path dir_;
      const Clock::time_point start_;
      // Under mpirun every stage runs on all ranks and MPI is initialised once, here, for all of
      // them (the campaign's session then finds it initialised). Without mpirun nothing in this
      // process initialises MPI: the campaign forks its workers and each FE stage gets a process.
      bool under_mpirun_ = false;
      std::optional<dealii::Utilities::MPI::MPI_InitFinalize> mpi_;
      bool root_ = true;
      std::map<std::string, Json> before_;
      std::vector<std::string> names_;
      std::vector<Stage> stages_; ///< the weak layers, the snowpack scenes, the uncertainty
      Json summary_;
      std::vector<fs::path> materials_;         ///< each weak layer's material in snow units (empty: it failed)
      std::vector<std::string> material_sha256s_;
      bool interrupted_ = false, failed_ = false;

      Stage &weak(std::size_t k) { return stages_.at(k); }
      Stage &uncertainty() { return stages_.back(); }
      /// The stage of snowpack scene 0 (after the weak layers').
      std::size_t first_snowpack() const { return scene_.weak_layers.size(); }
      const std::string &snowpack_scene_of(std::size_t stage) const { return scene_.snowpack_scenes.at(stage - first_snowpack()); }
      const SnowpackWeakLayer &weak_layer_of(std::size_t stage) const
      {
        return scene_.snowpack_weak_layers.at(stage - first_snowpack());
      }

      void refuse_an_earlier_pipeline() const
      {
        std::error_code error;
        if (fs::exists(dir_ / "summary.json", error) && !options_.resume && !options_.overwrite)
          throw InputError("The output directory <" + dir_.string() + "> already holds a pipeline (summary.json). Use "
                           "--resume to run only the stages whose inputs changed or did not complete, --overwrite to "
                           "start again, or another directory.");
      }

      void start_mpi()
      {
        under_mpirun_ = launched_by_mpirun();
        if (under_mpirun_)
          fem::start_fe_mpi(mpi_);
        root_ = !under_mpirun_ || dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
      }

      void barrier() const
      {
        if (under_mpirun_)
          MPI_Barrier(MPI_COMM_WORLD);
      }

      void prepare_directory()
      {
        if (root_)
        {
          // --overwrite starts again: every stage's folder goes too (the campaign's tests included).
          if (options_.overwrite && !options_.resume)
          {
            std::error_code error;
            for (const char *name : {"summary.json", "report.md", "report.png", "uncertainty"})
              fs::remove_all(dir_ / name, error);
            for (const WeakLayerVariant &v : scene_.weak_layers)
              fs::remove_all(dir_ / v.directory, error);
            for (const std::string &name : names_)
              fs::remove_all(dir_ / name, error);
          }
          fs::create_directories(dir_);
        }
        barrier();
      }

      void plan_stages()
      {
        for (std::size_t k = 0; k < scene_.weak_layers.size(); ++k)
        {
          Stage s;
          s.name = scene_.weak_layers[k].name;
          s.kind = "calibration";
          s.directory = dir_ / scene_.weak_layers[k].directory;
          // With changes, the stage runs a copy of the scene that holds them, in its own folder.
          s.scene_file = !scene_.weak_layer_changed(k) ? scene_.weak_layer_scene : (s.directory / "scene.prm").string();
          s.inputs_sha256 = util::sha256_hex(weak_layer_scene_text(scene_, k) + snow_units_text(scene_.snow));
          stages_.push_back(s);
        }
        for (std::size_t k = 0; k < names_.size(); ++k)
        {
          Stage s;
          s.name = names_[k];
          s.kind = "snowpack";
          s.directory = dir_ / names_[k];
          s.scene_file = (s.directory / "scene.prm").string();
          const SnowpackWeakLayer &w = scene_.snowpack_weak_layers[k];
          s.weak_layer = {{"stage", scene_.weak_layers[w.variant].name}};
          if (!w.record.is_null())
            s.weak_layer["from_profile"] = w.record;
          stages_.push_back(s);
        }
        Stage s;
        s.name = "uncertainty";
        s.kind = "uncertainty";
        s.directory = dir_ / "uncertainty";
        stages_.push_back(s);
      }

      void record_the_scene()
      {
        summary_["command"] = options_.command_line;
        summary_["scene"] = {{"file", scene_.file}, {"file_sha256", util::sha256_of_file(scene_.file)}};
        summary_["snow_units"] = {{"bond_tensile_strength_Pa", scene_.snow.bond_tensile_strength},
                                  {"bond_modulus_Pa", scene_.snow.bond_modulus},
                                  {"grain_diameter_m", scene_.snow.grain_diameter},
                                  {"particle_density_kg_per_m3", scene_.snow.particle_density}};
      }

      void write_summary(const std::string &status)
      {
        if (!root_)
          return;
        summary_["status"] = status;
        summary_["stages"] = Json::array();
        for (const Stage &s : stages_)
          summary_["stages"].push_back(stage_json(s));
        summary_["timing"] = {{"wall_s", std::chrono::duration<double>(Clock::now() - start_).count()}};
        summary_["versions"] = version_info();
        write_json_atomically((dir_ / "summary.json").string(), summary_);
      }

      /// The stage completed in the earlier run with the same inputs, and its outputs are there.
      bool unchanged(const Stage &s) const
      {
        const auto it = before_.find(s.name);
        return it != before_.end() && it->second.value("inputs_sha256", "") == s.inputs_sha256 &&
               (it->second.value("status", "") == "completed" || it->second.value("status", "") == "completed earlier") &&
               fs::exists(s.kind == "uncertainty" ? s.directory : s.directory / "summary.json");
      }

      void announce(std::size_t k, std::optional<double> estimate = std::nullopt) const
      {
        if (root_)
          std::cout << "\npipeline stage " << k + 1 << "/" << stages_.size() << ", " << stages_[k].name << " ("
                    << stages_[k].kind << "): elapsed " << format_duration(std::chrono::duration<double>(Clock::now() - start_).count())
                    << ", " << time_left(stages_, k, before_, estimate) << "\n"
                    << std::flush;
      }

      void note(const Stage &st)
      {
        interrupted_ = interrupted_ || st.status == "interrupted";
        failed_ = failed_ || st.status == "failed";
      }

      /// 1. Weak layer k: campaign, calibration, material in snow units (or the material cache's).
      /// Returns the calibration's exit code when it did not succeed.
      int run_weak_layer(std::size_t k)
      {
        Stage &w = weak(k);
        const fs::path material = w.directory / material_file_name(0, 1, true);
        const MaterialCache cache(options_.material_cache);
        const std::string material_inputs_sha256 = util::sha256_hex(weak_layer_material_inputs(scene_, k));
        const std::string cache_key = cache.enabled() ? MaterialCache::key(material_inputs_sha256) : "";
        const std::optional<fs::path> cached = cache.find(cache_key);
        const std::string stage = "pipeline stage " + std::to_string(k + 1) + "/" + std::to_string(stages_.size()) + ", " + w.name;
        if (unchanged(w) && fs::exists(material))
        {
          w.status = "completed earlier";
          w.wall_s = before_.at(w.name).value("wall_s", 0.0);
          if (root_)
            std::cout << stage << ": completed earlier, inputs unchanged\n";
        }
        else if (cached)
          restore_from_cache(w, cache, cache_key, *cached, stage);
        else
        {
          if (const int code = calibrate_weak_layer(k, stage); code != exit_success)
            return code;
          if (cache.enabled() && root_)
            store_in_cache(w, cache, cache_key, material_inputs_sha256);
        }
        barrier();
        if (!fs::exists(material))
          throw InputError(scene_.weak_layer_scene + ": the calibration wrote no " + material.filename().string() +
                           " (a pipeline takes a weak layer of one microstructure: leave Campaign/Microstructures "
                           "empty)");
        w.results = calibration_headline(w.directory);
        write_summary("running");
        materials_.push_back(material);
        material_sha256s_.push_back(util::sha256_of_file(material.string()));
        return exit_success;
      }

      /// The weak-layer stage's folder copied from the material cache's entry `entry` (rank 0).
      void restore_from_cache(Stage &w, const MaterialCache &cache, const std::string &cache_key,
                              const fs::path &entry, const std::string &stage)
      {
        const auto stage_start = Clock::now();
        if (root_)
        {
          const Json record = cache.restore(cache_key, w.directory);
          w.material_cache = {{"used", entry}, {"key", cache_key},
                              {"calibrated_by", record.value("pipeline", "")},
                              {"calibrated_at", record.value("calibrated_at", "")}};
          std::cout << stage << ": from the material cache, " << entry.string() << " (calibrated by "
                    << record.value("pipeline", "?") << " at " << record.value("calibrated_at", "?") << ")\n";
        }
        barrier();
        w.status = "completed";
        w.wall_s = std::chrono::duration<double>(Clock::now() - stage_start).count();
      }

      /// The weak layer `k` calibrated from its DEM campaign into its stage's folder. A class that
      /// the DEM or the calibration refuses is that class's failure when the pipeline has several
      /// (recorded; its pits are not run), the pipeline's bad input when it has one. Returns the
      /// calibration's exit code; on failure the stage is recorded and the summary written.
      int calibrate_weak_layer(std::size_t k, const std::string &stage)
      {
        Stage &w = weak(k);
        announce(k);
        if (scene_.weak_layer_changed(k))
        {
          if (root_)
          {
            fs::create_directories(w.directory);
            write_text_atomically(w.scene_file, [&](std::ostream &out) { out << weak_layer_scene_text(scene_, k); });
          }
          barrier();
        }
        CalibrateOptions calibration = weak_layer_calibration(scene_, w.scene_file);
        calibration.output_directory = w.directory.string();
        calibration.overwrite = true;
        calibration.threads = options_.threads;
        calibration.command_line = options_.command_line;
        calibration.snow = scene_.snow;
        const auto stage_start = Clock::now();
        int code = exit_numerical_failure;
        try
        {
          code = run_calibration(calibration);
        }
        catch (const InputError &e)
        {
          // A class's sample or fit that the DEM or the calibration refuses (a sample that does
          // not percolate, a surface no cohesive Cam-Clay fits): with one weak layer the pipeline's
          // bad input; of several, that class's failure, recorded, the others' pits still run.
          if (scene_.weak_layers.size() == 1)
            throw;
          w.results = {{"error", e.what()}};
          std::cerr << "anticrack: " << stage << " failed; its pits are not run:\n" << e.what() << "\n";
        }
        w.wall_s = std::chrono::duration<double>(Clock::now() - stage_start).count();
        barrier();
        w.status = code == exit_success ? "completed" : code == exit_interrupted ? "interrupted" : "failed";
        if (code != exit_success)
        {
          note(w);
          materials_.emplace_back();
          material_sha256s_.emplace_back();
          write_summary(w.status);
        }
        return code;
      }

      void store_in_cache(Stage &w, const MaterialCache &cache, const std::string &cache_key,
                          const std::string &material_inputs_sha256)
      {
        w.material_cache = {{"stored", (cache.directory() / cache_key).string()}, {"key", cache_key}};
        try
        {
          cache.store(cache_key, material_inputs_sha256, w.directory,
                      {{"pipeline", scene_.file}, {"output", w.directory.string()}});
        }
        catch (const fs::filesystem_error &e)
        {
          // The run's own results stand; only later runs lose the reuse, which they are told.
          w.material_cache = {{"stored", nullptr}, {"key", cache_key}, {"error", e.what()}};
          std::cerr << "anticrack: warning: the calibrated weak layer was not stored in the material cache "
                    << cache.directory().string() << ": " << e.what() << "\n";
        }
      }

      /// The material file snowpack stage `stage` runs with, from its weak layer's `material` (the
      /// calibrated one, or a perturbed one): that file, or, for a pit's grain size other than the
      /// snow units', a copy with the pit's lengths written into `folder` (coupling/snow_units.h).
      fs::path stage_material(std::size_t stage, const fs::path &material, const fs::path &folder) const
      {
        const SnowpackWeakLayer &w = weak_layer_of(stage);
        if (!(w.grain_diameter > 0) || w.grain_diameter == scene_.snow.grain_diameter)
          return fs::absolute(material).lexically_normal();
        const fs::path file = fs::absolute(folder / ("pit_" + material.filename().string())).lexically_normal();
        if (root_)
        {
          fs::create_directories(folder);
          const fem::MaterialFile pit = with_grain_diameter(
            fem::read_material_file_text(read_text_file(material.string()), material.string()), scene_.snow.grain_diameter,
            w.grain_diameter, "the grain size of " + snowpack_scene_of(stage) + "'s pit; the material of " +
                                material.string() + ", whose header says where it came from");
          write_text_atomically(file.string(), [&](std::ostream &out) { out << fem::material_file_text(pit); });
        }
        barrier(); // the file is there before any rank reads it
        return file;
      }

      /// 2. The snowpack scenes with the calibrated weak layer.
      void run_snowpack_stages()
      {
        std::vector<std::size_t> to_run;
        for (std::size_t k = first_snowpack(); k + 1 < stages_.size(); ++k)
        {
          Stage &s = stages_[k];
          const std::size_t w = weak_layer_of(k).variant;
          if (materials_[w].empty())
          {
            s.status = "not run";
            s.results = {{"error", "its weak layer, " + stages_[w].name + ", failed"}};
            continue;
          }
          const fs::path material = stage_material(k, materials_[w], s.directory);
          const std::string text = snowpack_scene_text(scene_, snowpack_scene_of(k), material.string());
          s.inputs_sha256 = util::sha256_hex(text + "\nmaterial " + util::sha256_of_file(material.string()));
          // Completed earlier: recorded so by the pipeline, or by the FE run itself when the pipeline
          // was killed before it could record it.
          const bool recorded = unchanged(s);
          if (recorded || completed_from_scene((s.directory / "summary.json").string(), util::sha256_hex(text)))
          {
            s.status = "completed earlier";
            s.wall_s = recorded ? before_.at(s.name).value("wall_s", 0.0) : snowpack_wall_s(s.directory);
            s.results = snowpack_headline(s.directory);
            if (root_)
              std::cout << "pipeline stage " << k + 1 << "/" << stages_.size() << ", " << s.name
                        << ": completed earlier, inputs unchanged\n";
            continue;
          }
          if (root_)
          {
            fs::create_directories(s.directory);
            write_text_atomically(s.scene_file, [&](std::ostream &out) { out << text; });
          }
          to_run.push_back(k);
        }
        barrier();
        if (to_run.empty())
          return;
        announce(to_run.front());
        std::vector<FeJob> jobs;
        for (const std::size_t k : to_run)
          jobs.push_back({stages_[k].name, fe_run_options(stages_[k].scene_file, stages_[k].directory, options_)});
        run_fe_jobs(jobs, under_mpirun_, cores(options_), [&](std::size_t j, int code, double wall) {
          Stage &st = stages_[to_run[j]];
          st.wall_s = wall;
          st.status = status_of(code);
          st.results = snowpack_headline(st.directory);
          if (root_)
            std::cout << "pipeline stage " << st.name << ": " << st.status << " in " << format_duration(wall) << "\n"
                      << std::flush;
          note(st);
          write_summary("running");
        });
      }

      /// 3. The calibration's uncertainty carried to the answers (coupling/pipeline_uncertainty.h).
      void run_uncertainty()
      {
        Stage &u_stage = uncertainty();
        if (!scene_.uncertainty)
        {
          u_stage.status = "not requested";
          return;
        }
        std::string hashes = material_sha256s_.front();
        for (std::size_t k = first_snowpack(); k + 1 < stages_.size(); ++k)
          hashes += stages_[k].inputs_sha256;
        u_stage.inputs_sha256 = util::sha256_hex(hashes);
        if (unchanged(u_stage))
        {
          u_stage.status = "completed earlier";
          u_stage.wall_s = before_.at(u_stage.name).value("wall_s", 0.0);
          u_stage.results = before_.at(u_stage.name).value("results", Json());
          if (root_)
            std::cout << "pipeline stage " << stages_.size() << "/" << stages_.size()
                      << ", uncertainty: completed earlier, inputs unchanged\n";
          return;
        }
        if (failed_ || interrupted_)
          return;
        // One weak layer (the scene reader refuses an uncertainty stage over several).
        const UncertainParameters u = uncertain_parameters(weak(0).directory);
        const std::vector<UncertainParameters> rerun = reruns_of(u);
        // Its runs are the snowpack stages' again: as many rounds of `cores` runs as there are
        // runs over the cores, each as long as the longest snowpack stage.
        double longest = 0;
        for (std::size_t k = first_snowpack(); k + 1 < stages_.size(); ++k)
          longest = std::max(longest, stages_[k].wall_s);
        std::size_t runs = 0;
        for (const UncertainParameters &r : rerun)
          runs += r.names.size();
        announce(stages_.size() - 1, longest > 0 ? std::optional<double>(longest * std::ceil(double(runs) / cores(options_)))
                                                 : std::nullopt);
        const auto stage_start = Clock::now();
        const UncertaintyJobs runs_of_the_stage = write_uncertainty_jobs(u, rerun);
        const std::vector<FeJob> &to_start = runs_of_the_stage.to_start;
        bool all_completed = true; // the runs completed earlier did
        run_fe_jobs(to_start, under_mpirun_, cores(options_), [&](std::size_t j, int code, double wall) {
          all_completed = all_completed && code == exit_success;
          if (root_)
            std::cout << "pipeline uncertainty " << to_start[j].label << ": " << status_of(code) << " in "
                      << format_duration(wall) << "\n"
                      << std::flush;
        });
        u_stage.results = uncertainty_results(u, rerun, runs_of_the_stage);
        u_stage.wall_s = std::chrono::duration<double>(Clock::now() - stage_start).count();
        u_stage.status = all_completed ? "completed" : "failed";
        note(u_stage);
      }

      /// The analyses of a yielding weak layer (the saw tests, a load to failure) are run again per
      /// parameter. An energy release rate only for E: its layers are elastic, so of the
      /// calibration only E enters it besides G_c, whose interval (the compaction tests' fracture
      /// energy) the stage maps itself, exactly, through its G(a). Indexed like stages_.
      std::vector<UncertainParameters> reruns_of(const UncertainParameters &u) const
      {
        std::vector<UncertainParameters> rerun(stages_.size());
        for (std::size_t j = first_snowpack(); j + 1 < stages_.size(); ++j)
          rerun[j] = fem::read_snowpack_scene_text(read_scene_file(snowpack_scene_of(j)), snowpack_scene_of(j))
                         .analysis.type->yielding_weak_layer ?
                       u :
                       restricted_to(u, {"E"});
        return rerun;
      }

      struct UncertaintyJobs
      {
        std::vector<FeJob> jobs;     ///< every run of the stage, in a fixed order
        std::vector<FeJob> to_start; ///< those not completed in an earlier, interrupted run
        std::vector<std::pair<std::size_t, std::size_t>> job_of; ///< (snowpack stage, parameter) per job
      };

      /// The perturbed material files and the scenes of the stage's runs, written; the runs to start.
      UncertaintyJobs write_uncertainty_jobs(const UncertainParameters &u, const std::vector<UncertainParameters> &rerun)
      {
        Stage &u_stage = uncertainty();
        const fem::MaterialFile calibrated =
          fem::read_material_file_text(read_text_file(materials_.front().string()), materials_.front().string());
        UncertaintyJobs r;
        std::vector<FeJob> &jobs = r.jobs, &to_start = r.to_start;
        std::vector<std::pair<std::size_t, std::size_t>> &job_of = r.job_of;
        for (std::size_t k = 0; k < u.names.size(); ++k)
        {
          const fs::path file = u_stage.directory / ("material_" + u.names[k] + ".prm");
          if (root_)
          {
            fs::create_directories(u_stage.directory);
            write_text_atomically(file.string(), [&](std::ostream &out) {
              out << fem::material_file_text(perturbed_material(calibrated, u, k));
            });
          }
          barrier(); // the material file is there before any rank hashes it
          for (std::size_t j = first_snowpack(); j + 1 < stages_.size(); ++j)
          {
            if (std::find(rerun[j].names.begin(), rerun[j].names.end(), u.names[k]) == rerun[j].names.end())
              continue;
            const std::string name = stages_[j].name + "_" + u.names[k];
            const fs::path run = u_stage.directory / name;
            const std::string text =
              snowpack_scene_text(scene_, snowpack_scene_of(j), stage_material(j, file, run).string()) +
              first_trial_near(stages_[j]);
            jobs.push_back({name, fe_run_options((run / "scene.prm").string(), run, options_)});
            job_of.emplace_back(j, k);
            if (options_.resume && completed_from_scene((run / "summary.json").string(), util::sha256_hex(text)))
            {
              if (root_)
                std::cout << "pipeline uncertainty " << name << ": completed earlier, inputs unchanged\n";
              continue;
            }
            if (root_)
            {
              fs::create_directories(run);
              write_text_atomically((run / "scene.prm").string(), [&](std::ostream &out) { out << text; });
            }
            to_start.push_back(jobs.back());
          }
        }
        barrier();
        return r;
      }

      /// Per snowpack stage, its answers' linearised intervals from the runs; the parameters.
      Json uncertainty_results(const UncertainParameters &u, const std::vector<UncertainParameters> &rerun,
                               const UncertaintyJobs &runs) const
      {
        const std::vector<FeJob> &jobs = runs.jobs;
        const std::vector<std::pair<std::size_t, std::size_t>> &job_of = runs.job_of;
        Json results;
        for (std::size_t j = first_snowpack(); j + 1 < stages_.size(); ++j)
        {
          std::vector<Json> perturbed;
          for (std::size_t n = 0; n < jobs.size(); ++n)
            if (job_of[n].first == j)
              perturbed.push_back(snowpack_headline(jobs[n].options.output_directory));
          Json &answers = results[stages_[j].name] = linearised_intervals(
            rerun[j], stages_[j].results, perturbed, stages_[j].results.value("element_length_m", 0.0));
          // An elastic stage's critical cut also carries G_c's interval, which the stage mapped
          // itself through its G(a) (fem/analysis/energy_release_rate.cpp).
          const Json mapped = stages_[j].results.value("critical_cut_length_interval", Json());
          if (mapped.is_object() && stages_[j].results["critical_cut_length_m"].is_number())
            answers["answers"]["critical_cut_length_m"] = combined_critical_cut_interval(
              mapped, answers["answers"]["critical_cut_length_m"], stages_[j].results["critical_cut_length_m"].get<double>());
        }
        Json parameters = Json::object();
        for (std::size_t k = 0; k < u.names.size(); ++k)
          parameters[u.names[k]] = {{"value", u.value(static_cast<Eigen::Index>(k))},
                                    {"standard_error", std::sqrt(u.covariance(static_cast<Eigen::Index>(k),
                                                                              static_cast<Eigen::Index>(k)))}};
        results["parameters"] = parameters;
        return results;
      }

      /// 4. The report: summary.json's results, report.md and report.png, the short report.
      int report()
      {
        Json results;
        if (scene_.weak_layers.size() == 1)
          results["weak_layer"] = weak(0).results;
        else
          for (std::size_t k = 0; k < first_snowpack(); ++k)
            results["weak_layers"][stages_[k].name] = stages_[k].results;
        for (std::size_t k = first_snowpack(); k + 1 < stages_.size(); ++k)
          results["analyses"][stages_[k].name] = stages_[k].results;
        results["uncertainty"] = uncertainty().results;
        summary_["results"] = results;
        write_summary(interrupted_ ? "interrupted" : failed_ ? "failed" : "completed");
        const int code = interrupted_ ? exit_interrupted : failed_ ? exit_numerical_failure : exit_success;
        if (!root_)
          return code;
        run_python_script("pipeline_report.py", dir_.string(), "summary.json and every stage's outputs");
        std::cout << "\n" << short_report(dir_, stages_, first_snowpack()) << std::flush;
        return code;
      }
    };
  } // namespace

  int run_pipeline_scene(const RunOptions &options)
  {
    const PipelineScene scene = read_pipeline_scene(options.scene_file); // every problem before anything is written
    return PipelineRun(options, scene).run();
  }

} // namespace anticrack::coupling
