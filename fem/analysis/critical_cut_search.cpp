// The critical cut as PST practice reads it: fixed-cut trials that bracket the shortest cut from
// which the test ends by itself (fem/analysis/critical_cut_search.h, docs/fem.md "The critical cut").
#include "fem/analysis/critical_cut_search.h"

#include "fem/analysis/outputs.h"
#include "fem/scene/layers.h"
#include "util/atomic_file.h"
#include "util/format.h"
#include "util/input_error.h"
#include "util/run_summary.h"

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace anticrack::fem
{
  CutBracket bracket_critical_cut(const std::optional<double> seed, const double longest, const double resolution,
                                  const std::function<bool(double)> &ends_test)
  {
    if (!(resolution > 0) || !(longest > 0))
      throw std::invalid_argument("bracket_critical_cut: the resolution (" + format_number(resolution) +
                                  " m) and the longest cut (" + format_number(longest) + " m) must be > 0");
    CutBracket b;
    const auto trial = [&](double cut) {
      const bool ends = ends_test(cut);
      b.trials.push_back({cut, ends});
      if (ends)
        b.shortest_ending = cut;
      else
        b.longest_holding = cut;
      return ends;
    };
    const double tolerance = resolution * (1 + 1e-9);
    if (seed)
    {
      // From the seed, steps of resolution, 2 resolution, 4 ... away from it until the answer
      // changes; below the first holding cut is 0 (the intact column), above the last the longest.
      const double first = std::clamp(*seed, std::min(resolution, longest), longest);
      const bool ends = trial(first);
      double step = resolution;
      for (;;)
      {
        const double next = ends ? b.shortest_ending.value() - step : b.longest_holding + step;
        if (ends && next <= 0)
          break; // the bracket is (0, the shortest ending cut]
        if (!ends && next >= longest - 0.5 * resolution)
        {
          if (longest > b.longest_holding)
            trial(longest);
          break;
        }
        if (trial(next) != ends)
          break;
        step *= 2;
      }
    }
    else if (!trial(longest))
      return b; // no cut up to the longest ends the test
    if (!b.shortest_ending)
      return b;
    while (*b.shortest_ending - b.longest_holding > tolerance)
      trial(0.5 * (b.longest_holding + *b.shortest_ending));
    return b;
  }

  namespace
  {
    namespace fs = std::filesystem;

    /// A trial's folder under DIR: its cut, to 0.1 mm below a resolution of 1 mm (unique per cut).
    std::string trial_folder(double cut)
    {
      char name[48];
      std::snprintf(name, sizeof name, "fixed_cuts/cut_%.5f", cut);
      return name;
    }

    /// Whether a trial's (or the saw run's) results end the test: the crack ran by itself (a
    /// critical cut detected), or the slab broke.
    bool results_end_test(const Json &r)
    {
      return !r.value("critical_cut_length_m", Json()).is_null() || !r.value("slab_fracture", Json()).is_null();
    }

    /// How far the crack ran ahead of the cut (its tip at the end of the trial; the tip is read per
    /// element, so a tip inside the cut's element counts as none).
    double crack_run(const Json &r)
    {
      return std::max(0., r.at("final_crack_tip_m").get<double>() - r.at("trial").at("cut_length_m").get<double>());
    }

    /// Results of completed runs of this search kept under DIR (each run's results.json, written
    /// when it completed), reused by a run with --resume; a run killed while running continues
    /// from its last checkpoint (Output/Checkpoint interval), or restarts.
    class CompletedRuns
    {
    public:
      CompletedRuns(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
        : scene_(scene)
        , options_(options)
        , comm_(comm)
      {}

      /// The results of the run in `folder` (under DIR), run by `run` unless a run with --resume
      /// finds them complete there for the same scene.
      Json get(const std::string &folder, const std::function<Json(const SnowpackRunOptions &)> &run) const
      {
        const fs::path directory = fs::path(options_.output_directory) / folder;
        const std::string file = (directory / "results.json").string();
        if (options_.resume && fs::exists(file))
        {
          const Json kept = interpret_json_file(file, "a fixed-cut trial's results", [&](const Json &j) {
            return j.at("resume_key_sha256").get<std::string>() == scene_.resume_key_sha256 ? j.at("results") : Json();
          }, "Run again with --overwrite (without --resume), or delete " + directory.string() + ".");
          if (!kept.is_null())
          {
            root_log(options_.log, comm_).line("[fem] ", folder, ": completed earlier, its results reused");
            return kept;
          }
        }
        SnowpackRunOptions run_options = options_;
        run_options.output_directory = directory.string();
        // A run killed after one of its checkpoints continues from it; any other starts afresh.
        run_options.resume = options_.resume && fs::exists(directory / "checkpoint.json");
        if (!run_options.resume && dealii::Utilities::MPI::this_mpi_process(comm_) == 0)
        {
          fs::remove_all(directory);
          fs::create_directories(directory);
        }
        MPI_Barrier(comm_);
        const Json results = run(run_options);
        if (dealii::Utilities::MPI::this_mpi_process(comm_) == 0)
          write_json_atomically(file, Json{{"resume_key_sha256", scene_.resume_key_sha256}, {"results", results}});
        MPI_Barrier(comm_);
        return results;
      }

    private:
      const SnowpackScene &scene_;
      const SnowpackRunOptions &options_;
      MPI_Comm comm_;
    };
  } // namespace

  namespace
  {
    /// The advancing saw's run (DIR/saw/, practice only), whose crack runs by itself near the
    /// answer: its results, and the cut the fixed-cut trials start from (where its crack ran, or
    /// where it broke the slab, else the longest cut).
    std::pair<Json, std::optional<double>> advancing_saw(const SnowpackScene &scene, const CompletedRuns &completed,
                                                         const PstInTime &run_in_time, ConditionalStream &log)
    {
      SnowpackScene advancing = scene;
      advancing.pst.saw = SawTest::Saw::advancing;
      log.line("[fem] practice critical cut: the saw advances at ", format_number(scene.pst.saw_speed), " m/s (DIR/saw/)");
      const Json saw_results = completed.get("saw", [&](const SnowpackRunOptions &o) {
        return run_in_time(advancing, o, std::nullopt);
      });
      if (!saw_results["critical_cut_bracket_m"].is_null())
        return {saw_results, saw_results["critical_cut_bracket_m"][1].get<double>()}; // the saw's cut when the crack ran
      if (!saw_results["slab_fracture"].is_null())
        return {saw_results, saw_results["slab_fracture"]["cut_length_m"].get<double>()};
      return {saw_results, scene.pst.cut_length}; // the saw's crack never ran: the search starts at the longest cut
    }

    /// Whether the onset the bracket reads is sharp. Whether a trial "ends the test" is read at a
    /// threshold, the tip's lead (the crack runs by itself once it leads the cut by
    /// Analysis/Self-propagation lead). The answer is the snowpack's only where the onset is sharp:
    /// the longest holding cut's crack stays well short of the lead, the shortest ending cut's runs
    /// well past it. Where the run grows smoothly with the cut, the bracket moves with the threshold:
    /// said (a warning appended), not hidden.
    Json onset_record(const SnowpackScene &scene, const CutBracket &bracket,
                      const std::map<double, Json> &trials_results, Json &warnings)
    {
      const double lead = self_propagation_lead(scene);
      const Json &ending = trials_results.at(*bracket.shortest_ending);
      const double ran = crack_run(ending),
                   held = bracket.longest_holding > 0 ? crack_run(trials_results.at(bracket.longest_holding)) : 0.;
      const bool through = ending["outcome"] == pst_outcome_names().name(PstOutcome::end);
      const bool sharp = held < 0.5 * lead && (through || ran > 2 * lead);
      if (!sharp)
        warnings.push_back("the onset of propagation is not sharp: the crack of the longest cut that holds ran " +
                           format_number(held, 3) + " m ahead of it, that of the shortest cut that ends the test " +
                           format_number(ran, 3) + " m (" + std::string(through ? "to the end" : "and stopped") +
                           "), against the self-propagation lead of " + format_number(lead, 3) +
                           " m: the crack grows with the cut, and the critical cut moves with Analysis/Self-propagation "
                           "lead [m] (docs/fem.md \"The critical cut\")");
      return {{"sharp", sharp},
              {"self_propagation_lead_m", lead},
              {"longest_holding_cut_crack_run_m", held},
              {"shortest_ending_cut_crack_run_m", ran}};
    }

    /// The advancing saw's own answers, a second and named figure: where the tip began to lead the
    /// saw (depends on the saw speed and the element length), and where its crack ran by itself.
    Json saw_run_record(const SnowpackScene &scene, const Json &saw_results)
    {
      const Json &bracket_of_saw = saw_results["critical_cut_bracket_m"];
      return {{"directory", "saw"},
              {"saw_speed_m_per_s", scene.pst.saw_speed},
              {"outcome", saw_results["outcome"]},
              {"tip_lead_onset_m", saw_results["critical_cut_length_m"]},
              {"crack_runs_by_itself_at_cut_m", bracket_of_saw.is_null() ? Json(nullptr) : bracket_of_saw[1]},
              {"propagation_speed_m_per_s", saw_results["propagation_speed_m_per_s"]},
              {"explicit_wall_time_s", saw_results["explicit_wall_time_s"]}};
    }
  } // namespace

  Json run_critical_cut_search(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm,
                               const PstInTime &run_in_time)
  {
    ConditionalStream log = root_log(options.log, comm);
    const CompletedRuns completed(scene, options, comm);
    const double dx = scene.pst.column_length / column_count(scene);
    const bool practice = scene.pst.saw == SawTest::Saw::practice;

    // Practice: the advancing saw first (DIR/saw/), whose crack runs by itself near the answer.
    Json saw_results;
    std::optional<double> seed = scene.pst.first_trial_cut;
    if (practice)
      std::tie(saw_results, seed) = advancing_saw(scene, completed, run_in_time, log);

    std::map<double, Json> trials_results;
    Json trials = Json::array();
    const CutBracket bracket = bracket_critical_cut(seed, scene.pst.cut_length, dx, [&](double cut) {
      const std::string folder = trial_folder(cut);
      log.line("[fem] fixed-cut trial ", trials.size() + 1, ": cut ", format_number(cut, 4), " m (DIR/", folder, "/)");
      const Json r = completed.get(folder, [&](const SnowpackRunOptions &o) {
        return run_in_time(scene, o, cut);
      });
      const bool ends = results_end_test(r);
      trials.push_back({{"cut_length_m", cut},
                        {"ends_test", ends},
                        {"outcome", r["outcome"]},
                        {"crack_run_m", crack_run(r)},
                        {"gravity_ramp_failed_at_load_factor", r["trial"]["gravity_ramp_failed_at_load_factor"]},
                        {"directory", folder}});
      log.line("[fem] fixed-cut trial ", trials.size(), ": cut ", format_number(cut, 4), " m ",
               ends ? "ends the test" : "holds", " (", r["outcome"].get<std::string>(), ")");
      trials_results[cut] = r;
      return ends;
    });

    Json r;
    Json warnings = Json::array();
    if (bracket.shortest_ending)
    {
      r = trials_results.at(*bracket.shortest_ending);
      r["series_directory"] = trial_folder(*bracket.shortest_ending);
      warnings = r.value("warnings", Json::array());
      r["onset"] = onset_record(scene, bracket, trials_results, warnings);
    }
    else
    {
      r["analysis"] = scene.analysis.type->name;
      r["outcome"] = pst_outcome_names().name(PstOutcome::no_propagation);
      warnings.push_back("no fixed cut up to PST/Cut length [m] = " + format_number(scene.pst.cut_length) +
                         " m ends the test: increase it");
    }
    r["warnings"] = warnings;
    r.erase("trial");
    r["critical_cut_method"] =
      practice ? "practice: the shortest of fixed cuts (saw stopped) from which the test ends by itself, the trials "
                 "started where an advancing saw's crack ran"
               : "bisection over fixed cuts (saw stopped), each loaded by gravity after the cut";
    r["critical_cut_length_m"] =
      bracket.shortest_ending ? Json(0.5 * (bracket.longest_holding + *bracket.shortest_ending)) : Json(nullptr);
    r["critical_cut_bracket_m"] = bracket.shortest_ending
                                    ? Json::array({bracket.longest_holding, *bracket.shortest_ending})
                                    : Json(nullptr);
    r["fixed_cut_trials"] = {{"resolution_m", dx}, {"seed_m", seed ? Json(*seed) : Json(nullptr)}, {"trials", trials}};
    if (practice)
    {
      r["tip_lead_onset_m"] = saw_results["critical_cut_length_m"];
      r["saw_run"] = saw_run_record(scene, saw_results);
    }
    log.line("[fem] critical cut: ", bracket.shortest_ending ? format_number(r["critical_cut_length_m"].get<double>(), 4) + " m, bracket [" +
                                                                 format_number(bracket.longest_holding, 4) + ", " +
                                                                 format_number(*bracket.shortest_ending, 4) + "] m"
                                                             : std::string("none up to the longest cut"),
             " after ", trials.size(), " fixed-cut trials");
    return r;
  }

} // namespace anticrack::fem
