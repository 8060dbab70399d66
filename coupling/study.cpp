#include "coupling/study.h"

#include "coupling/python_script.h"
#include "coupling/study_analysis.h"
#include "coupling/study_scene.h"
#include "fem/analysis/snowpack_command.h"
#include "util/atomic_file.h"
#include "util/format.h"
#include "util/input_error.h"
#include "util/mpi_session.h"
#include "util/parameter_files.h"
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
#include <iostream>
#include <optional>
#include <sstream>
#include <thread>

namespace anticrack::coupling
{
  namespace fs = std::filesystem;
  using Clock = std::chrono::steady_clock;

  namespace
  {
    /// The tolerances of the cheapest settings the study reports.
    constexpr double tolerances[] = {0.05, 0.01};

    struct VariantRun
    {
      StudyVariant variant;
      std::string scene_text;
      std::string scene_sha256;
      std::string status = "not run"; ///< completed, completed earlier, failed, interrupted, not run
      int exit_code = 0;
      double wall_s = 0;
      std::vector<std::optional<double>> results;
      /// An earlier variant with the same scene (a value that is the base scene's own, or that of
      /// Base scene changes): it runs once, and this one takes its run.
      std::optional<std::size_t> same_as;
    };

    std::string changes_text(const StudyVariant &v) { return entry_changes_text(v.changes); }

    /// The study's variants with their scene texts (the base scene, relocatable, and the changes).
    std::vector<VariantRun> variant_runs(const StudyScene &study)
    {
      const std::string base = scene_text_with_changes(relocatable_scene_text(study.base_scene), study.base_changes,
                                                       "by the study " + study.file + ": Study/Base scene changes");
      std::vector<VariantRun> runs;
      for (StudyVariant &v : study_variants(study))
      {
        VariantRun r;
        // A value that is the base scene's own changes nothing: left out, so that variants equal to
        // the base scene (or to each other) have the same text and run once.
        std::vector<EntryChange> changes;
        for (std::size_t e = 0; e < study.entries.size(); ++e)
          if (v.level[e] && study.entries[e].values[*v.level[e]] != study.entries[e].base_value)
            changes.emplace_back(study.entries[e].path, study.entries[e].values[*v.level[e]]);
        r.scene_text = scene_text_with_changes(base, changes, "by the study " + study.file + ": the variant's values");
        r.scene_sha256 = util::sha256_hex(r.scene_text);
        r.variant = std::move(v);
        r.results.resize(study.results.size());
        for (std::size_t j = 0; j < runs.size() && !r.same_as; ++j)
          if (runs[j].scene_sha256 == r.scene_sha256)
            r.same_as = j;
        runs.push_back(std::move(r));
      }
      return runs;
    }

    /// Every variant's scene read and checked by its kind's reader, from a scratch folder, before
    /// anything is written. Without mpirun each check runs in a process of its own (an FE check
    /// initialises MPI, which the study's process must not have done before it forks its variants);
    /// the check's own listing is not shown. Throws InputError naming the variant.
    void check_variants(const StudyScene &study, const std::vector<VariantRun> &runs, const SceneRunner &runner,
                        const int threads)
    {
      const fs::path scratch = fs::temp_directory_path() /
                               ("anticrack-study-" + std::to_string(::getpid()) + "-" +
                                std::to_string(Clock::now().time_since_epoch().count()));
      fs::create_directories(scratch);
      const auto file_of = [&](std::size_t k) { return (scratch / (runs[k].variant.id + ".prm")).string(); };
      for (std::size_t k = 0; k < runs.size(); ++k)
        write_text_atomically(file_of(k), [&](std::ostream &out) { out << runs[k].scene_text; });
      const auto check_one = [&](std::size_t k, std::string &message) {
        std::ostringstream discarded;
        std::streambuf *const cout = std::cout.rdbuf(discarded.rdbuf());
        try
        {
          runner.check(file_of(k), threads);
          std::cout.rdbuf(cout);
          return exit_success;
        }
        catch (const InputError &e)
        {
          message = e.what();
        }
        catch (const std::exception &e)
        {
          message = e.what();
        }
        std::cout.rdbuf(cout);
        return exit_bad_input;
      };
      std::string failures;
      const auto refused = [&](std::size_t k, const std::string &message) {
        failures += "variant " + runs[k].variant.id + " (" + changes_text(runs[k].variant) + "):\n" + message + "\n";
      };
      if (launched_by_mpirun())
      {
        for (std::size_t k = 0; k < runs.size(); ++k)
        {
          std::string message;
          if (check_one(k, message) != exit_success)
            refused(k, message);
        }
      }
      else
      {
        const int n = static_cast<int>(runs.size());
        const std::vector<WorkerExit> exits = run_jobs_in_worker_processes(
          n, std::min(n, std::max(1, static_cast<int>(std::thread::hardware_concurrency()))),
          [&](int job, std::string &report) {
            std::string message;
            const int code = check_one(static_cast<std::size_t>(job), message);
            report = message.substr(0, max_worker_report);
            return code;
          });
        for (std::size_t k = 0; k < runs.size(); ++k)
          if (exits[k].exit_code != exit_success)
            refused(k, exits[k].report.empty() ? describe_worker_exit(static_cast<int>(k), exits[k]) : exits[k].report);
      }
      std::error_code ignored;
      fs::remove_all(scratch, ignored);
      if (!failures.empty())
        throw InputError("Invalid study <" + study.file + ">: the base scene " + study.base_scene +
                         " with the values of Study/Entry k is refused for\n" + failures);
    }

    /// A number at `pointer` of a variant's summary.json, if there is one.
    std::optional<double> result_at(const Json &summary, const std::string &pointer)
    {
      const Json::json_pointer p(pointer);
      if (!summary.contains(p) || !summary.at(p).is_number())
        return std::nullopt;
      return summary.at(p).get<double>();
    }

    Json optional_json(const std::optional<double> &x) { return x ? Json(*x) : Json(nullptr); }

    /// The error of every variant in result r: against the given reference, else against the
    /// finest variant of the variant's line (one at a time) or of the study (product).
    std::vector<std::optional<double>> errors_of_result(const StudyScene &study, const std::vector<VariantRun> &runs,
                                                        const std::vector<std::vector<std::size_t>> &lines,
                                                        std::size_t r, std::vector<std::optional<std::size_t>> &reference_variant_of_line)
    {
      std::vector<std::optional<double>> error(runs.size());
      reference_variant_of_line.assign(lines.size(), std::nullopt);
      for (std::size_t e = 0; e < lines.size(); ++e)
      {
        std::optional<double> reference = study.results[r].reference;
        if (!reference && study.entries[e].refinement != Refinement::none && !lines[e].empty())
        {
          reference_variant_of_line[e] = lines[e].back(); // the line is sorted coarsest first
          reference = runs[lines[e].back()].results[r];
        }
        std::vector<std::optional<double>> y;
        for (std::size_t v : lines[e])
          y.push_back(runs[v].results[r]);
        const std::vector<std::optional<double>> line_error = relative_errors(y, reference);
        for (std::size_t k = 0; k < lines[e].size(); ++k)
          error[lines[e][k]] = line_error[k];
      }
      return error;
    }

    /// study.json's analysis of entry e's line: per result the errors, observed orders and cheapest
    /// settings, and where the base scene's value lies.
    Json line_json(const StudyScene &study, const std::vector<VariantRun> &runs, const std::vector<std::size_t> &line,
                   std::size_t e, const std::vector<std::vector<std::optional<double>>> &errors,
                   const std::vector<std::vector<std::optional<std::size_t>>> &reference_variants)
    {
      const StudyEntry &entry = study.entries[e];
      Json j;
      j["entry"] = entry.path;
      j["refinement"] = refinement_name(entry.refinement);
      j["base_value"] = entry.base_value ? Json(*entry.base_value) : Json(nullptr);
      j["variants"] = Json::array();
      j["values"] = Json::array();
      j["wall_s"] = Json::array();
      std::vector<double> h, cost;
      const std::vector<double> numbers = entry.numbers();
      for (std::size_t v : line)
      {
        const std::size_t level = *runs[v].variant.level[e];
        j["variants"].push_back(runs[v].variant.id);
        j["values"].push_back(entry.values[level]);
        if (!entry.measures.empty())
          j["measures"].push_back(numbers[level]);
        j["wall_s"].push_back(runs[v].wall_s);
        cost.push_back(runs[v].wall_s);
        h.push_back(entry.refinement == Refinement::count ? 1 / numbers[level] : numbers[level]);
      }
      j["results"] = Json::object();
      for (std::size_t r = 0; r < study.results.size(); ++r)
      {
        Json jr;
        std::vector<std::optional<double>> y, error;
        for (std::size_t v : line)
        {
          y.push_back(runs[v].results[r]);
          error.push_back(errors[r][v]);
        }
        jr["values"] = Json::array();
        jr["errors"] = Json::array();
        for (std::size_t k = 0; k < line.size(); ++k)
        {
          jr["values"].push_back(optional_json(y[k]));
          jr["errors"].push_back(optional_json(error[k]));
        }
        const std::optional<std::size_t> reference_variant = reference_variants[r][e];
        jr["error_against"] = study.results[r].reference ? "the given reference value " + format_number(*study.results[r].reference)
                              : reference_variant ? "the finest variant, " + runs[*reference_variant].variant.id
                                                  : "nothing (no reference value, and the entry has no finest value)";
        if (entry.refinement == Refinement::size || entry.refinement == Refinement::count)
        {
          // h = value (size) or 1/value (count), decreasing along the line.
          const std::vector<std::optional<double>> orders =
            study.results[r].reference ? observed_orders_against_known(h, error) : observed_orders_from_triples(h, y);
          jr["observed_order"] = Json::array();
          for (const std::optional<double> &p : orders)
            jr["observed_order"].push_back(optional_json(p));
          jr["observed_order_from"] = study.results[r].reference ? "consecutive pairs of errors against the reference"
                                                                 : "consecutive triples (Richardson)";
        }
        std::optional<std::size_t> excluded;
        if (reference_variant)
          excluded = static_cast<std::size_t>(std::find(line.begin(), line.end(), *reference_variant) - line.begin());
        for (const double tolerance : tolerances)
        {
          const std::string key = "cheapest_within_" + format_number(100 * tolerance) + "_percent";
          const std::optional<std::size_t> k = cheapest_within(cost, error, tolerance, excluded);
          jr[key] = k ? Json{{"value", entry.values[*runs[line[*k]].variant.level[e]]},
                             {"variant", runs[line[*k]].variant.id},
                             {"wall_s", cost[*k]},
                             {"error", *error[*k]}}
                      : Json(nullptr);
        }
        j["results"][study.results[r].label] = jr;
      }
      return j;
    }

    /// study.csv: one row per variant.
    void write_csv(const fs::path &file, const StudyScene &study, const std::vector<VariantRun> &runs,
                   const std::vector<std::vector<std::optional<double>>> &errors)
    {
      const auto quoted = [](const std::string &s) {
        std::string q = "\"";
        for (const char c : s)
          q += c == '"' ? std::string("\"\"") : std::string(1, c);
        return q + "\"";
      };
      write_text_atomically(file.string(), [&](std::ostream &out) {
        out.precision(10);
        out << "variant";
        for (const StudyEntry &entry : study.entries)
          out << "," << quoted(entry.path);
        out << ",status,exit_code,wall_s";
        for (const StudyResult &r : study.results)
          out << "," << quoted(r.label) << "," << quoted(r.label + " relative error");
        out << "\n";
        for (std::size_t v = 0; v < runs.size(); ++v)
        {
          const VariantRun &run = runs[v];
          out << run.variant.id;
          for (std::size_t e = 0; e < study.entries.size(); ++e)
            out << ","
                << quoted(run.variant.level[e] ? study.entries[e].values[*run.variant.level[e]]
                                               : study.entries[e].base_value.value_or("(base scene's default)"));
          out << "," << run.status << "," << run.exit_code << "," << run.wall_s;
          for (std::size_t r = 0; r < study.results.size(); ++r)
          {
            out << ",";
            if (run.results[r])
              out << *run.results[r];
            out << ",";
            if (errors[r][v])
              out << *errors[r][v];
          }
          out << "\n";
        }
      });
    }

    /// Prints the lines' headline: each result's orders and cheapest settings.
    void print_headline(std::ostream &out, const Json &lines)
    {
      for (const Json &line : lines)
      {
        out << "  " << line["entry"].get<std::string>() << " (" << line["refinement"].get<std::string>() << "):\n";
        for (const auto &[label, r] : line["results"].items())
        {
          out << "    " << label << ":";
          for (std::size_t k = 0; k < line["values"].size(); ++k)
            out << " " << line["values"][k].get<std::string>() << " -> "
                << (r["values"][k].is_null() ? std::string("none") : format_number(r["values"][k].get<double>(), 5))
                << (r["errors"][k].is_null() ? std::string() : " (" + format_number(100 * r["errors"][k].get<double>(), 3) + " %)")
                << ";";
          if (r.contains("observed_order"))
          {
            out << " order";
            for (const Json &p : r["observed_order"])
              out << " " << (p.is_null() ? std::string("-") : format_number(p.get<double>(), 3));
          }
          for (const double tolerance : tolerances)
          {
            const Json &c = r["cheapest_within_" + format_number(100 * tolerance) + "_percent"];
            out << "; within " << format_number(100 * tolerance) << " %: "
                << (c.is_null() ? std::string("none") : c["value"].get<std::string>() + " (" + format_duration(c["wall_s"].get<double>()) + ")");
          }
          out << "\n";
        }
      }
    }
  } // namespace

  void declare_study(dealii::ParameterHandler &prm, const std::string &, bool) { declare_study_scene(prm); }

  void check_study_scene(const std::string &file, const int threads, const SceneRunner &runner)
  {
    const StudyScene study = read_study_scene(file);
    const std::vector<VariantRun> runs = variant_runs(study);
    check_variants(study, runs, runner, threads);
    std::cout << "study " << study.file << ": " << runs.size() << " variants of " << study.base_scene << " (kind "
              << study.base_kind << "), " << (study.product ? "every combination" : "one entry at a time") << "\n";
    for (const VariantRun &r : runs)
      std::cout << "  " << r.variant.id << ": " << changes_text(r.variant)
                << (r.same_as ? " (the same scene as " + runs[*r.same_as].variant.id + ": runs once)" : "") << "\n";
    std::cout << "  results:";
    for (const StudyResult &r : study.results)
      std::cout << " " << r.pointer << (r.reference ? " (reference " + format_number(*r.reference) + ")" : "");
    std::cout << "\n";
  }

  namespace
  {
    /// One run of a study scene, as a sequence of named steps (run()): the variants checked and
    /// their scenes written, the ones to run (with --resume, not those that completed with the same
    /// scene), their runs, the twins' answers, the lines' errors and orders, and the outputs.
    class StudyRun
    {
    public:
      StudyRun(const RunOptions &options, const SceneRunner &runner)
        : options_(options), runner_(runner), start_(Clock::now()), study_(read_study_scene(options.scene_file)),
          runs_(variant_runs(study_)), dir_(options.output_directory)
      {}

      int run()
      {
        refuse_an_earlier_study();
        start_mpi();
        check_variants(study_, runs_, runner_, cores_); // every problem before anything is written
        write_variant_scenes();
        const std::vector<std::size_t> to_run = variants_to_run();
        if (root_)
          std::cout << "study " << study_.file << ": " << runs_.size() << " variants of " << study_.base_scene << ", "
                    << to_run.size() << " to run" << (under_mpirun_ ? " on " + std::to_string(session().size()) + " ranks" : "")
                    << "\n"
                    << std::flush;
        if (!to_run.empty())
          run_variants(to_run);
        give_twins_their_runs();
        read_answers();
        analyse_lines();
        return write_outputs();
      }

    private:
      const RunOptions &options_;
      const SceneRunner &runner_;
      const Clock::time_point start_;
      const StudyScene study_;
      std::vector<VariantRun> runs_;
      const fs::path dir_;
      bool under_mpirun_ = false;
      int cores_ = 1;
      // Under mpirun MPI is started once for every variant (an FE analysis finds it started).
      std::optional<dealii::Utilities::MPI::MPI_InitFinalize> mpi_;
      bool root_ = true;
      std::vector<std::vector<std::optional<double>>> errors_;
      Json lines_json_ = Json::array();

      static const MpiSession &session() { return MpiSession::get(); }

      void refuse_an_earlier_study() const
      {
        std::error_code error;
        if (fs::exists(dir_ / "study.json", error) && !options_.resume && !options_.overwrite)
          throw InputError("The output directory <" + dir_.string() + "> already holds a study (study.json). Use --resume "
                           "to run only the variants that changed or did not complete, --overwrite to start again, or "
                           "another directory.");
      }

      void start_mpi()
      {
        under_mpirun_ = launched_by_mpirun();
        cores_ = options_.threads > 0 ? options_.threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
        if (under_mpirun_)
          fem::start_fe_mpi(mpi_);
        root_ = session().rank() == 0;
      }

      void write_variant_scenes() const
      {
        if (root_)
        {
          std::error_code error;
          if (options_.overwrite && !options_.resume)
            for (const char *name : {"variants", "study.json", "study.csv", "summary.json", "work_precision.png", "results.png"})
              fs::remove_all(dir_ / name, error);
          for (const VariantRun &r : runs_)
          {
            const fs::path folder = dir_ / "variants" / r.variant.id;
            fs::create_directories(folder);
            write_text_atomically((folder / "scene.prm").string(), [&](std::ostream &out) { out << r.scene_text; });
          }
        }
        session().barrier();
      }

      /// Which variants run: with --resume not those whose scene is unchanged and whose run completed.
      std::vector<std::size_t> variants_to_run()
      {
        std::vector<std::size_t> to_run;
        for (std::size_t k = 0; k < runs_.size(); ++k)
        {
          if (runs_[k].same_as)
            continue; // takes the run of the variant it equals (give_twins_their_runs)
          const fs::path record = dir_ / "variants" / runs_[k].variant.id / "variant.json";
          if (options_.resume && fs::exists(record))
          {
            const bool completed = interpret_json_file(record.string(), "a study variant's record", [&](const Json &before) {
              if (before.value("scene_sha256", "") != runs_[k].scene_sha256 ||
                  (before.value("status", "") != "completed" && before.value("status", "") != "completed earlier"))
                return false;
              runs_[k].wall_s = before.value("wall_s", 0.0);
              return true;
            });
            if (completed)
            {
              runs_[k].status = "completed earlier";
              continue;
            }
          }
          // A run that completed although the study was killed before it could record it.
          const fs::path run_summary = dir_ / "variants" / runs_[k].variant.id / "run" / "summary.json";
          if (options_.resume && completed_from_scene(run_summary.string(), runs_[k].scene_sha256))
          {
            runs_[k].status = "completed earlier";
            runs_[k].wall_s = interpret_json_file(run_summary.string(), "a run's summary", [](const Json &s) {
              return s.at("timing").at("wall_s").get<double>();
            });
            continue;
          }
          to_run.push_back(k);
        }
        return to_run;
      }

      RunOptions options_of(std::size_t k, int threads) const
      {
        const fs::path folder = dir_ / "variants" / runs_[k].variant.id;
        RunOptions o;
        o.scene_file = (folder / "scene.prm").string();
        o.output_directory = (folder / "run").string();
        // A variant that ran before (interrupted, or failed) continues from its checkpoint where its
        // kind has one; a new one starts in a clean folder.
        o.resume = options_.resume && fs::exists(folder / "run" / "summary.json");
        o.overwrite = !o.resume;
        o.threads = threads;
        o.command_line = options_.command_line;
        o.labels = {{"study", study_.file}, {"variant", runs_[k].variant.id}};
        return o;
      }

      void record(std::size_t k, int code, double wall_s)
      {
        runs_[k].exit_code = code;
        runs_[k].wall_s = wall_s;
        runs_[k].status = code == exit_success ? "completed" : code == exit_interrupted ? "interrupted" : "failed";
        write_json_atomically((dir_ / "variants" / runs_[k].variant.id / "variant.json").string(),
                              Json{{"variant", runs_[k].variant.id},
                                   {"changes", changes_text(runs_[k].variant)},
                                   {"scene_sha256", runs_[k].scene_sha256},
                                   {"status", runs_[k].status},
                                   {"exit_code", code},
                                   {"wall_s", wall_s}});
        std::cout << "study: " << runs_[k].variant.id << " (" << changes_text(runs_[k].variant) << ") " << runs_[k].status
                  << " in " << format_duration(wall_s) << "\n"
                  << std::flush;
      }

      void run_variants(const std::vector<std::size_t> &to_run)
      {
        if (!under_mpirun_)
          run_in_worker_processes(to_run);
        else if (study_.base_kind == "dem")
          run_dem_variants_over_ranks(to_run);
        else
          run_variants_on_all_ranks(to_run);
      }

      /// Side by side in worker processes, each with its share of the cores.
      void run_in_worker_processes(const std::vector<std::size_t> &to_run)
      {
        const int side_by_side = std::min<int>(study_.side_by_side, static_cast<int>(to_run.size()));
        const int threads = std::max(1, cores_ / side_by_side);
        const std::vector<WorkerExit> exits = run_jobs_in_worker_processes(
          static_cast<int>(to_run.size()), side_by_side,
          [&](int job, std::string &) {
            const std::size_t k = to_run[static_cast<std::size_t>(job)];
            if (side_by_side == 1)
              return runner_.run(options_of(k, threads));
            const LineLabel out(std::cout, "[" + runs_[k].variant.id + "] "), err(std::cerr, "[" + runs_[k].variant.id + "] ");
            return runner_.run(options_of(k, threads));
          },
          [&](int job, const WorkerExit &exit) {
            if (exit.signal != 0)
              std::cerr << "study: " << runs_[to_run[static_cast<std::size_t>(job)]].variant.id << ": "
                        << describe_worker_exit(job, exit) << "\n";
            record(to_run[static_cast<std::size_t>(job)], exit.exit_code, exit.wall_s);
          });
        for (std::size_t j = 0; j < exits.size(); ++j)
          if (!exits[j].started)
            runs_[to_run[j]].status = "not run";
      }

      /// Whole runs per rank, as a campaign's tests: variant j of to_run on rank j mod size.
      void run_dem_variants_over_ranks(const std::vector<std::size_t> &to_run)
      {
        for (std::size_t j = static_cast<std::size_t>(session().rank()); j < to_run.size(); j += static_cast<std::size_t>(session().size()))
        {
          const auto variant_start = Clock::now();
          const int code = runner_.run(options_of(to_run[j], options_.threads));
          record(to_run[j], code, std::chrono::duration<double>(Clock::now() - variant_start).count());
        }
        session().barrier();
        for (std::size_t k : to_run) // every rank reads what the others recorded
        {
          const Json r = read_json_file((dir_ / "variants" / runs_[k].variant.id / "variant.json").string());
          runs_[k].status = r.value("status", "failed");
          runs_[k].exit_code = r.value("exit_code", 1);
          runs_[k].wall_s = r.value("wall_s", 0.0);
        }
      }

      /// One variant after the other, each on every rank.
      void run_variants_on_all_ranks(const std::vector<std::size_t> &to_run)
      {
        for (std::size_t k : to_run)
        {
          const auto variant_start = Clock::now();
          const int code = runner_.run(options_of(k, options_.threads));
          session().barrier();
          const double wall_s = std::chrono::duration<double>(Clock::now() - variant_start).count();
          if (root_)
            record(k, code, wall_s);
          else
            runs_[k].exit_code = code, runs_[k].status = code == exit_success ? "completed" : "failed";
          if (code == exit_interrupted)
            break;
        }
      }

      /// Variants equal to an earlier one take its run.
      void give_twins_their_runs()
      {
        for (VariantRun &run : runs_)
          if (run.same_as)
          {
            const VariantRun &twin = runs_[*run.same_as];
            run.status = twin.status, run.exit_code = twin.exit_code, run.wall_s = twin.wall_s;
            if (root_)
              write_json_atomically((dir_ / "variants" / run.variant.id / "variant.json").string(),
                                    Json{{"variant", run.variant.id},
                                         {"changes", changes_text(run.variant)},
                                         {"scene_sha256", run.scene_sha256},
                                         {"same_as", twin.variant.id},
                                         {"status", run.status}});
          }
      }

      /// The answers of every variant from its run's summary.json.
      void read_answers()
      {
        for (VariantRun &run : runs_)
        {
          const std::string folder = run.same_as ? runs_[*run.same_as].variant.id : run.variant.id;
          const fs::path summary = dir_ / "variants" / folder / "run" / "summary.json";
          if ((run.status == "completed" || run.status == "completed earlier" || run.status == "failed") && fs::exists(summary))
          {
            const Json s = read_json_file(summary.string());
            for (std::size_t r = 0; r < study_.results.size(); ++r)
              run.results[r] = result_at(s, study_.results[r].pointer);
          }
        }
      }

      /// The answers' errors and each entry's line: orders, the cheapest setting within a tolerance.
      void analyse_lines()
      {
        std::vector<std::vector<std::size_t>> lines;
        for (std::size_t e = 0; e < study_.entries.size(); ++e)
        {
          std::vector<StudyVariant> variants;
          for (const VariantRun &run : runs_)
            variants.push_back(run.variant);
          lines.push_back(line_of_entry(study_, variants, e));
        }
        errors_.assign(study_.results.size(), {});
        std::vector<std::vector<std::optional<std::size_t>>> reference_variants(study_.results.size());
        for (std::size_t r = 0; r < study_.results.size(); ++r)
          errors_[r] = errors_of_result(study_, runs_, lines, r, reference_variants[r]);
        for (std::size_t e = 0; e < study_.entries.size(); ++e)
          lines_json_.push_back(line_json(study_, runs_, lines[e], e, errors_, reference_variants));
      }

      Json variants_json() const
      {
        Json variants = Json::array();
        for (std::size_t v = 0; v < runs_.size(); ++v)
        {
          Json j{{"id", runs_[v].variant.id}, {"changes", Json::object()}};
          for (const auto &[path, value] : runs_[v].variant.changes)
            j["changes"][path] = value;
          j["status"] = runs_[v].status;
          if (runs_[v].same_as)
            j["same_as"] = runs_[*runs_[v].same_as].variant.id;
          j["exit_code"] = runs_[v].exit_code;
          j["wall_s"] = runs_[v].wall_s;
          j["results"] = Json::object();
          j["errors"] = Json::object();
          for (std::size_t r = 0; r < study_.results.size(); ++r)
          {
            j["results"][study_.results[r].label] = optional_json(runs_[v].results[r]);
            j["errors"][study_.results[r].label] = optional_json(errors_[r][v]);
          }
          variants.push_back(j);
        }
        return variants;
      }

      Json study_json() const
      {
        Json entries = Json::array();
        for (const StudyEntry &entry : study_.entries)
          entries.push_back({{"path", entry.path},
                             {"values", entry.values},
                             {"refinement", refinement_name(entry.refinement)},
                             {"base_value", entry.base_value ? Json(*entry.base_value) : Json(nullptr)}});
        Json results = Json::array();
        for (const StudyResult &r : study_.results)
          results.push_back({{"pointer", r.pointer}, {"label", r.label}, {"reference_value", optional_json(r.reference)}});
        return Json{{"study", study_.file},
                    {"base_scene", study_.base_scene},
                    {"base_kind", study_.base_kind},
                    {"combination", study_.product ? "product" : "one at a time"},
                    {"cost", "wall time of each variant's run [s], " +
                               std::string(under_mpirun_ ? "on " + std::to_string(session().size()) + " ranks"
                                                         : std::to_string(std::min(study_.side_by_side, static_cast<int>(runs_.size()))) +
                                                             " side by side on " + std::to_string(cores_) + " cores")},
                    {"entries", entries},
                    {"results", results},
                    {"variants", variants_json()},
                    {"lines", lines_json_}};
      }

      /// study.json, study.csv, summary.json, the plots and the printed headline (root only).
      int write_outputs() const
      {
        int failed = 0, interrupted = 0;
        for (const VariantRun &run : runs_)
        {
          failed += run.status == "failed";
          interrupted += run.status == "interrupted" || run.status == "not run";
        }
        const std::string status = interrupted ? "interrupted" : failed ? "completed with failed variants" : "completed";
        if (root_)
        {
          write_json_atomically((dir_ / "study.json").string(), study_json());
          write_csv(dir_ / "study.csv", study_, runs_, errors_);
          Json summary;
          summary["command"] = options_.command_line;
          summary["scene"] = {{"file", study_.file},
                              {"file_sha256", util::sha256_of_file(study_.file)},
                              {"base_scene", study_.base_scene},
                              {"base_scene_sha256", util::sha256_of_file(study_.base_scene)}};
          summary["status"] = status;
          summary["results"] = {{"variants", runs_.size()}, {"failed", failed}, {"not_completed", interrupted}, {"lines", lines_json_}};
          summary["timing"] = {{"wall_s", std::chrono::duration<double>(Clock::now() - start_).count()}};
          summary["versions"] = version_info();
          write_json_atomically((dir_ / "summary.json").string(), summary);
          if (!interrupted)
            run_python_script("plot_study.py", dir_.string(), "study.json and study.csv");
          print_end(status, failed, summary["timing"]["wall_s"].get<double>());
        }
        return interrupted ? exit_interrupted : failed ? exit_numerical_failure : exit_success;
      }

      void print_end(const std::string &status, int failed, double wall_s) const
      {
        std::cout << "\nstudy " << status << ": " << runs_.size() << " variants";
        if (failed)
        {
          std::cout << ", failed:";
          for (const VariantRun &run : runs_)
            if (run.status == "failed")
              std::cout << " " << run.variant.id << " (" << changes_text(run.variant) << ", exit " << run.exit_code
                        << ", see variants/" << run.variant.id << "/run/summary.json)";
        }
        std::cout << " in " << format_duration(wall_s) << "\n";
        print_headline(std::cout, lines_json_);
        std::cout << "  " << (dir_ / "study.json").string() << ", study.csv, work_precision.png, results.png\n";
      }
    };
  } // namespace

  int run_study_scene(const RunOptions &options, const SceneRunner &runner)
  {
    return StudyRun(options, runner).run();
  }
} // namespace anticrack::coupling
