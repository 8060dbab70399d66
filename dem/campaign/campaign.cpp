#include "dem/campaign/campaign.h"

#include "dem/campaign/campaign_output.h"
#include "dem/campaign/campaign_tests.h"
#include "dem/core/force_history.h"
#include "dem/scene/history_columns.h"
#include "dem/scene/lab_tests.h"
#include "dem/scene/model.h"
#include "dem/scene/parameters.h"
#include "util/parameter_files.h"
#include "util/console.h"
#include "util/hdf5_file.h"
#include "util/input_error.h"
#include "util/mpi_session.h"
#include "util/phase_timer.h"
#include "util/progress.h"
#include "util/run_summary.h"
#include "util/worker_processes.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>
#include <tuple>

namespace anticrack::dem
{
  namespace fs = std::filesystem;
  using namespace campaign;

  namespace
  {
    /// A sample of the campaign: its microstructure, its realization, and whether it is the friction
    /// tests' own (Campaign/Friction sample).
    using SampleKey = std::tuple<Index, Index, bool>;

    /// The scenes a campaign's samples are built from, validated.
    struct CampaignScenes
    {
      std::vector<SceneParameters> microstructures; ///< the scene itself when Campaign/Microstructures is empty
      std::vector<SceneParameters> friction;        ///< each microstructure's friction sample; empty: none of its own

      /// The scene whose sample test `t` runs on.
      [[nodiscard]] const SceneParameters &of(const CampaignTest &t) const
      {
        return friction_sample(t) ? friction[t.microstructure] : microstructures[t.microstructure];
      }
      [[nodiscard]] SampleKey sample_of(const CampaignTest &t) const
      {
        return {t.microstructure, t.realization, friction_sample(t)};
      }

    private:
      [[nodiscard]] bool friction_sample(const CampaignTest &t) const { return t.friction() && !friction.empty(); }
    };

    /// The name of sample `key` in the console: m<M>_r<R>, and " (friction)" for a friction sample.
    std::string sample_name(const SampleKey &key)
    {
      const auto &[m, r, friction] = key;
      return "m" + std::to_string(m) + "_r" + std::to_string(r) + (friction ? " (friction)" : "");
    }

    /// Every microstructure's scene (the scene itself when Campaign/Microstructures is empty) and,
    /// with Campaign/Friction sample, each one's friction sample (its entries set after the
    /// microstructure's); throws InputError naming the variant.
    CampaignScenes campaign_scenes_of(const SceneParameters &scene)
    {
      const auto &c = scene.campaign;
      // An entry of a variant without a '/' is of DEM/Sample; one with it, a path below DEM.
      const auto add_overrides = [](std::vector<std::pair<std::string, std::string>> &overrides,
                                    const std::vector<std::pair<std::string, std::string>> &entries) {
        for (const auto &[entry, value] : entries)
          overrides.emplace_back((split_parameter_path(entry).size() == 1 ? "DEM/Sample/" : "DEM/") + entry, value);
      };
      const auto read_variant = [&](const std::vector<std::pair<std::string, std::string>> &overrides,
                                    const std::string &what) {
        try
        {
          return read_scene(scene.file, scene.kind, overrides, scene.declare_more);
        }
        catch (const InputError &e)
        {
          throw InputError(what + ": " + e.what());
        }
      };
      CampaignScenes scenes;
      if (c.microstructures.empty())
        scenes.microstructures.push_back(scene);
      for (std::size_t m = 0; m < c.microstructures.size(); ++m)
      {
        std::vector<std::pair<std::string, std::string>> overrides;
        add_overrides(overrides, c.microstructures[m]);
        scenes.microstructures.push_back(read_variant(
          overrides, "Campaign/Microstructures, variant " + std::to_string(m) + " (" + c.microstructures_text + ")"));
      }
      if (!c.friction_sample.empty())
        for (std::size_t m = 0; m < scenes.microstructures.size(); ++m)
        {
          std::vector<std::pair<std::string, std::string>> overrides;
          if (!c.microstructures.empty())
            add_overrides(overrides, c.microstructures[m]);
          add_overrides(overrides, c.friction_sample);
          scenes.friction.push_back(read_variant(overrides, "Campaign/Friction sample (" + c.friction_sample_text +
                                                              ") of microstructure " + std::to_string(m)));
        }
      return scenes;
    }
    /// The output directory: refused if it is a file, or holds a campaign that is neither resumed nor
    /// overwritten. A resumed campaign reads the summaries of the tests that ran before: one that is
    /// not a whole JSON object (cut short by a full disk or a copy; anticrack writes them atomically)
    /// is refused here, naming it, before any test runs, rather than rerun or misread in a worker.
    void refuse_unusable_output(const fs::path &directory, const RunOptions &options, const std::vector<CampaignTest> &tests)
    {
      std::error_code error;
      if (fs::exists(directory, error) && !fs::is_directory(directory, error))
        throw InputError("The output path <" + directory.string() + "> exists and is not a directory.");
      if (!options.resume && !options.overwrite)
        for (const char *name : {"summary.json", "campaign.h5", "tests"})
          if (fs::exists(directory / name, error))
            throw InputError("The output directory <" + directory.string() + "> already holds a campaign (" +
                             name + "). Use --resume to run only the tests that have not completed, "
                             "--overwrite to start again, or another directory.");
      if (options.resume)
        for (const CampaignTest &t : tests)
          if (fs::exists(directory / "tests" / t.id / "summary.json", error))
            read_json_file((directory / "tests" / t.id / "summary.json").string());
    }

    /// The scene of campaign test `t` of microstructure scene `micro`: its realization's seed, the
    /// clump's force along the loading angle (sin psi, 0, -cos psi), the rates over its slowdown, and
    /// for a friction or compaction test, that lab test's loading.
    SceneParameters test_scene_of(const SceneParameters &micro, const CampaignTest &t, const parameters::Campaign &c)
    {
      SceneParameters test_scene = micro;
      test_scene.dem.seed += static_cast<std::uint64_t>(t.realization);
      const double psi = t.angle_deg * M_PI / 180.0;
      test_scene.dem.boundary.clump_force_direction = Vec3(std::sin(psi), 0.0, -std::cos(psi));
      test_scene.dem.boundary.clump_force_rate /= t.slowdown;
      test_scene.dem.loading.ramp.fast_rate /= t.slowdown;
      test_scene.output.progress_interval = 0;
      if (t.friction())
      {
        // The simple shear of the collapsed layer (dem/lab/simple_shear.h): it collapses under the
        // normal force's ramp, then slides; it ends at its shear strain, not at a stop strain.
        auto &loading = test_scene.dem.loading;
        loading.test = &lab_test("simple shear");
        loading.adaptive = false;
        loading.stop_strain = 0;
        loading.normal_stress = c.friction_normal_stress;
        loading.shear_velocity = c.friction_shear_velocity / t.slowdown;
        loading.consolidation_time = c.friction_consolidation_time * t.slowdown;
        loading.final_shear_strain = c.friction_final_shear_strain;
      }
      if (t.compaction())
      {
        // The displacement-controlled compaction test (dem/lab/compaction_test.h) of this sample.
        auto &loading = test_scene.dem.loading;
        loading.test = &lab_test("compaction");
        loading.adaptive = false; // a force ramp's; the compaction test's rate is constant
        loading.compaction_strain_rate = c.compaction_strain_rate / t.slowdown;
        loading.stop_strain = c.compaction_final_strain;
        loading.curve_strain_interval = c.compaction_curve_strain_interval;
      }
      return test_scene;
    }

    /// The samples of a campaign, one per (microstructure, realization) and one more for its friction
    /// test when it has a sample of its own, each shared by its tests.
    struct CampaignSamples
    {
      std::map<SampleKey, std::unique_ptr<DemModel>> models;
      std::map<SampleKey, std::string> without_load_path; ///< the realizations refused, and why
    };

    /// Builds the samples of `tests` (their (microstructure, realization)s, each once) before any
    /// test runs, `side_by_side` at a time on one thread each (or one at a time on `threads` when
    /// side_by_side is 1). A sample can take minutes (the sticky-hard-sphere sampler near its
    /// critical stickiness) and can be refused (not levelled off, no percolation): built first, a
    /// refusal costs the samples' time, not that of the tests that ran before it, and leaves nothing
    /// written. A sample is the same bits on any number of threads, so the results do not depend on
    /// the order. A realization whose bonds do not connect base and clump is recorded, not thrown;
    /// any other refusal is rethrown, the first in (microstructure, realization) order.
    CampaignSamples build_samples(const CampaignScenes &scenes, const std::vector<const CampaignTest *> &tests,
                                  const parameters::Campaign &c, int side_by_side, int threads)
    {
      std::vector<std::pair<SampleKey, const CampaignTest *>> wanted; // the first test of each sample
      for (const CampaignTest *t : tests)
      {
        const SampleKey key = scenes.sample_of(*t);
        if (std::none_of(wanted.begin(), wanted.end(), [&](const auto &w) { return w.first == key; }))
          wanted.emplace_back(key, t);
      }
      std::sort(wanted.begin(), wanted.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
      side_by_side = std::max(1, std::min(side_by_side, static_cast<int>(wanted.size())));
      if (wanted.size() > 1 || side_by_side > 1)
        root_console() << "  " << wanted.size() << " sample(s) first, " << side_by_side << " side by side\n"
                       << std::flush;

      std::vector<std::unique_ptr<DemModel>> models(wanted.size());
      std::vector<std::string> no_load_path(wanted.size());
      std::vector<std::exception_ptr> refused(wanted.size());
      std::atomic<std::size_t> next{0};
      std::mutex console;
      const auto builder = [&] {
        for (std::size_t k = next++; k < wanted.size(); k = next++)
        {
          const CampaignTest &t = *wanted[k].second;
          try
          {
            models[k] = build_dem_model(test_scene_of(scenes.of(t), t, c), side_by_side > 1 ? 1 : threads);
            models[k]->system.clumps[models[k]->clump].applied_force = {}; // each test sets its own
            const std::lock_guard<std::mutex> lock(console);
            std::cout << "  sample " << sample_name(wanted[k].first) << " built in "
                      << format_duration(models[k]->build_seconds) << "\n"
                      << std::flush;
          }
          catch (const SpecimenWithoutLoadPath &e)
          {
            no_load_path[k] = e.what();
          }
          catch (...)
          {
            refused[k] = std::current_exception();
          }
        }
      };
      if (side_by_side == 1)
        builder();
      else
      {
        // Plain threads, not an OpenMP team: each builder is an initial thread of its own, whose
        // one-thread DEM set-up starts no OpenMP pool (the worker processes fork after these end).
        std::vector<std::thread> team;
        for (int k = 0; k < side_by_side; ++k)
          team.emplace_back(builder);
        for (std::thread &member : team)
          member.join();
      }
      for (const std::exception_ptr &e : refused)
        if (e)
          std::rethrow_exception(e);
      CampaignSamples samples;
      for (std::size_t k = 0; k < wanted.size(); ++k)
        if (models[k])
          samples.models[wanted[k].first] = std::move(models[k]);
        else
          samples.without_load_path[wanted[k].first] = no_load_path[k];
      return samples;
    }

    /// How campaign test `t` runs (DIRECTORY/tests/<id>/, quiet, its progress labelled `label`), and
    /// the labels its summary.json carries (which --resume compares).
    RunOptions test_run_options(const SceneParameters &test_scene, const CampaignTest &t, const fs::path &directory,
                                const std::string &label, int threads, const RunOptions &options)
    {
      RunOptions o;
      o.output_directory = (directory / "tests" / t.id).string();
      o.overwrite = true;
      o.quiet = true;
      o.progress_label = label;
      o.threads = threads;
      o.command_line = options.command_line;
      o.labels = {{"campaign_test", t.id},
                  {"microstructure", t.microstructure},
                  {"realization", t.realization},
                  {"loading_angle_deg", t.angle_deg},
                  {"seed", test_scene.dem.seed},
                  {"rate_divisor", t.slowdown},
                  {"reference_for", t.reference_for}};
      if (t.friction())
      {
        o.labels["friction_normal_stress_Pa"] = test_scene.dem.loading.normal_stress;
        o.labels["friction_shear_velocity_m_per_s"] = test_scene.dem.loading.shear_velocity;
        o.labels["friction_consolidation_time_s"] = test_scene.dem.loading.consolidation_time;
        o.labels["friction_final_shear_strain"] = test_scene.dem.loading.final_shear_strain;
        o.labels["friction_sample"] = test_scene.campaign.friction_sample_text;
      }
      if (t.compaction())
      {
        o.labels["compaction_strain_rate_per_s"] = test_scene.dem.loading.compaction_strain_rate;
        o.labels["compaction_final_strain"] = test_scene.dem.loading.stop_strain;
        o.labels["compaction_curve_strain_interval"] = test_scene.dem.loading.curve_strain_interval;
      }
      return o;
    }

  } // namespace

  void describe_campaign(std::ostream &out, const SceneParameters &scene)
  {
    const auto &c = scene.campaign;
    const CampaignScenes scenes = campaign_scenes_of(scene);
    const auto tests = enumerate_tests(c, static_cast<Index>(scenes.microstructures.size()));
    std::ostringstream s;
    s << "\nCampaign (the model above is microstructure 0, realization 0; every test is built like it)\n"
      << "  loading angles      ";
    for (std::size_t k = 0; k < c.loading_angles_deg.size(); ++k)
      s << (k ? ", " : "") << c.loading_angles_deg[k];
    s << " deg\n  realizations        " << c.realizations << " (seeds " << scene.dem.seed << " to "
      << scene.dem.seed + c.realizations - 1 << ")\n  microstructures     " << scenes.microstructures.size();
    for (std::size_t m = 0; m < c.microstructures.size(); ++m)
    {
      s << "\n    " << m << ":";
      for (const auto &[entry, value] : c.microstructures[m])
        s << " " << entry << " = " << value << ";";
    }
    const auto references = std::count_if(tests.begin(), tests.end(), [](const CampaignTest &t) { return !t.reference_for.empty(); });
    const auto compactions = std::count_if(tests.begin(), tests.end(),
                                           [](const CampaignTest &t) { return t.compaction() && t.reference_for.empty(); });
    s << "\n  tests               " << tests.size() << " (" << references << " of them quasi-static references, "
      << c.quasi_static_slowdown << "x slower; " << compactions << " compaction test(s)";
    if (c.has_compaction_tests())
      s << " at " << c.compaction_strain_rate << " 1/s to strain " << c.compaction_final_strain << ", a row every "
        << c.compaction_curve_strain_interval << " of strain";
    if (c.has_friction_tests())
      s << "; a friction test per realization: simple shear at " << c.friction_normal_stress << " Pa, "
        << c.friction_shear_velocity << " m/s, to shear strain " << c.friction_final_shear_strain
        << (c.friction_sample.empty() ? std::string(", on the microstructure's sample") :
                                        ", on a sample of its own (" + c.friction_sample_text + ")");
    s << ")\n"
      << "  outputs             summary.json, campaign.h5, tests/<id>/{summary.json, history.h5}\n";
    out << s.str();
  }

  int run_campaign(const SceneParameters &scene, const RunOptions &options)
  {
    const auto &c = scene.campaign;
    const fs::path directory(options.output_directory);
    const auto start = std::chrono::steady_clock::now();

    // --- everything is validated before anything is written
    const CampaignScenes scenes = campaign_scenes_of(scene);
    const std::vector<CampaignTest> tests = enumerate_tests(c, static_cast<Index>(scenes.microstructures.size()));

    refuse_unusable_output(directory, options, tests);
    std::error_code error;

    const MpiSession &mpi = MpiSession::get();
    const bool root = mpi.rank() == 0;
    // Every rank has looked at the directory before rank 0 creates `tests` in it: a rank that
    // looked later would take rank 0's new folder for an earlier campaign and refuse (exit 2).
    mpi.barrier();
    PhaseTimer timer; // rank 0's phases: its own tests, then campaign.h5 and summary.json
    // Bad input that only building a sample finds (a sticky-hard-sphere sample that does not
    // percolate or level off) comes after the folders are made, and every sample is built before
    // the first test runs: such an error removes what this run created, so that "nothing was
    // written" holds.
    struct RemoveCreatedOnBadInput
    {
      std::vector<fs::path> created;
      bool armed = true;
      ~RemoveCreatedOnBadInput()
      {
        if (armed && std::uncaught_exceptions() > 0)
          for (const fs::path &path : created)
          {
            std::error_code ignored;
            fs::remove_all(path, ignored);
          }
      }
    } created_on_bad_input;
    if (root)
    {
      // The outermost folder this run creates holds the rest: `tests`, the output folder, or an
      // ancestor of it that does not exist yet.
      fs::path outermost = fs::exists(directory, error) ? directory / "tests" : fs::absolute(directory);
      while (!fs::exists(outermost.parent_path(), error) && outermost.has_parent_path() && outermost.parent_path() != outermost)
        outermost = outermost.parent_path();
      if (!fs::exists(outermost, error))
        created_on_bad_input.created.push_back(outermost);
    }
    if (root)
    {
      if (options.overwrite && !options.resume)
        for (const char *name : {"summary.json", "campaign.h5", "tests"})
          fs::remove_all(directory / name);
      fs::create_directories(directory / "tests");
    }
    mpi.barrier();

    // Who runs which tests (contiguous blocks balanced by expected cost, block_of). Under mpirun
    // the ranks, the cores' threads shared among them. Without it, one worker process per core
    // (util/worker_processes.h), each running its block on one thread: independent tests side by
    // side rather than one test on many threads, which scale poorly on small samples. The cores are
    // --threads, else DEM/Threads, else all; 1 runs the tests one after another in this process.
    // The results do not depend on it: a test's DEM is the same on any number of threads.
    // The process's thread count is put back when the campaign returns: a pipeline runs one campaign
    // per weak-layer class in one process, and each must find the cores the first one found.
    const ThreadCountRestorer restore_thread_count;
    int threads = options.threads >= 0 ? options.threads : scene.dem.threads;
    int members = mpi.size();
    const bool workers = !mpi.active() && std::min<std::size_t>(threads > 0 ? threads : dem::DemSystem::threads(),
                                                                tests.size()) > 1;
    if (workers)
    {
      members = static_cast<int>(
        std::min<std::size_t>(threads > 0 ? threads : dem::DemSystem::threads(), tests.size()));
      threads = 1;
    }
    else if (threads <= 0 && mpi.size() > 1)
      threads = std::max(1, dem::DemSystem::threads() / mpi.size());
    apply_thread_count(threads);

    root_console() << "anticrack campaign: " << scene.file << " -> " << directory.string() << "\n  "
                << c.loading_angles_deg.size() << " loading angles x " << c.realizations << " realizations x "
                << scenes.microstructures.size() << " microstructures = " << tests.size() << " tests"
                << " (compaction and friction tests and quasi-static references included) on " << members
                << (workers ? " worker process(es)" : " rank(s)") << " x " << dem::DemSystem::threads()
                << " thread(s)\n"
                << std::flush;

    // --- the samples, before any test: those of the tests still to run (this rank's block under mpirun)
    std::vector<const CampaignTest *> to_run;
    {
      const auto [first, last] = workers ? std::pair<std::size_t, std::size_t>(0, tests.size())
                                         : block_of(tests, c, mpi.rank(), members);
      for (std::size_t k = first; k < last; ++k)
      {
        const CampaignTest &t = tests[k];
        const RunOptions o =
          test_run_options(test_scene_of(scenes.of(t), t, c), t, directory, "", threads, options);
        if (!(options.resume && completed(o.output_directory, o.labels)))
          to_run.push_back(&t);
      }
    }
    const CampaignSamples samples = [&] {
      const auto phase = timer.scope("samples");
      return build_samples(scenes, to_run, c, workers ? members : threads, threads);
    }();

    // --- the tests of one member, each on a copy of its sample
    struct Share
    {
      bool any_failed = false;
      bool interrupted = false; // Ctrl-C or SIGTERM: the test stopped, the rest of the share is not run
      std::map<std::string, TestOutcome> outcomes; // as they ran (or from their files)
    };
    // `next()`: the index of the member's next test, or tests.size() when there is none; `left()`:
    // how many tests it has left (for the estimate of the time left), NaN when unknown.
    const auto run_share = [&](const std::string &who, const std::function<std::size_t()> &next,
                               const std::function<double()> &left) {
      Share share;
      const auto share_start = std::chrono::steady_clock::now();
      std::size_t run_in_share = 0; // tests this member ran (not those completed earlier)
      for (std::size_t k = next(); k < tests.size(); k = next())
      {
        const CampaignTest &t = tests[k];
        const SceneParameters test_scene = test_scene_of(scenes.of(t), t, c);
        const Vec3 direction = test_scene.dem.boundary.clump_force_direction;
        RunOptions o = test_run_options(test_scene, t, directory, who + " " + t.id, threads, options);
        if (options.resume && completed(o.output_directory, o.labels))
        {
          std::cout << who << " " << t.id << ": completed earlier, skipped\n" << std::flush;
          share.outcomes[t.id] = read_outcome(t, o.output_directory);
          continue;
        }
        const auto sample = samples.models.find(scenes.sample_of(t));
        if (sample == samples.models.end())
        {
          // This realization's bonds do not connect base and clump: its tests are recorded as such
          // (the calibration leaves them out and names them) and the campaign goes on.
          Json summary;
          summary["status"] = status_no_load_path;
          summary["message"] = samples.without_load_path.at(scenes.sample_of(t));
          summary["command"] = options.command_line;
          summary["labels"] = o.labels;
          summary["scene"] = scene_info(test_scene);
          summary["versions"] = version_info();
          fs::create_directories(o.output_directory);
          write_json_atomically((fs::path(o.output_directory) / "summary.json").string(), summary);
          created_on_bad_input.armed = false; // a result, not half-writing
          share.outcomes[t.id] = outcome_of(t, summary, std::nullopt);
          std::cout << who << " test " << k + 1 << "/" << tests.size() << " " << t.id << ": " << status_no_load_path
                    << " (realization " << t.realization << ": the bonds do not connect the base to the clump; "
                    << "left out of the calibration)\n"
                    << std::flush;
          continue;
        }
        auto model = std::make_unique<DemModel>(*sample->second);
        model->build_seconds = 0; // built (and timed) in the campaign's "samples" phase
        model->system.clumps[model->clump].applied_force =
          dem::ForceHistory::ramp(test_scene.dem.boundary.clump_force_rate, direction);
        const DemRunRecord run = [&] {
          const auto phase = timer.scope("tests");
          return run_dem_model(test_scene, std::move(model), o);
        }();
        created_on_bad_input.armed = false; // a test has run: its files are results, not half-writing
        share.any_failed = share.any_failed || run.exit_code != exit_success;
        share.interrupted = run.exit_code == exit_interrupted;
        const TestOutcome &outcome = share.outcomes[t.id] = outcome_of(t, run.summary, run.failure_analysis);
        std::ostringstream line;
        line.precision(4);
        line << who << " test " << k + 1 << "/" << tests.size() << " " << t.id << ": "
             << outcome.row.status;
        if (!std::isnan(outcome.row.sigma))
          line << ", failure sigma = " << outcome.row.sigma << " Pa, tau = " << outcome.row.tau
               << " Pa, q = " << outcome.row.q << " Pa";
        else if (!outcome.analysis_error.empty())
          line << " (" << outcome.analysis_error << ")";
        line << "; " << outcome.steps << " steps in " << format_duration(outcome.wall_s);
        // The time left of this member's share, from its tests so far (their costs differ by angle).
        ++run_in_share;
        const double more = left();
        if (more > 0)
          line << "; " << more << " more here, about "
               << format_duration(std::chrono::duration<double>(std::chrono::steady_clock::now() - share_start).count() /
                                  static_cast<double>(run_in_share) * more)
               << " left";
        line << "\n";
        std::cout << line.str() << std::flush;
        if (share.interrupted)
          break;
      }
      return share;
    };

    bool any_failed = false, interrupted = false;
    std::map<std::string, TestOutcome> outcomes; // this process's tests; the others' are read from their files
    if (workers)
    {
      // The parent's "tests" phase is its wait for the workers.
      const auto wait_start = std::chrono::steady_clock::now();
      // The workers pull tests from one queue as they become free, the longest first (the compaction
      // tests, then the others in the order of their samples, which keeps each worker on few samples):
      // fixed shares leave one worker idle while the other runs a long test.
      std::vector<std::size_t> queue(tests.size());
      for (std::size_t k = 0; k < tests.size(); ++k)
        queue[k] = k;
      std::stable_sort(queue.begin(), queue.end(),
                       [&](std::size_t a, std::size_t b) { return tests[a].cost(c) > tests[b].cost(c); });
      SharedCounter taken;
      const std::vector<WorkerExit> exits = run_in_worker_processes(members, [&](int member, std::string &report) {
        const auto next = [&] {
          const auto k = static_cast<std::size_t>(taken.next());
          return k < queue.size() ? queue[k] : tests.size();
        };
        try
        {
          const Share share = run_share("[worker " + std::to_string(member) + "]", next,
                                        [] { return std::numeric_limits<double>::quiet_NaN(); });
          return static_cast<int>(share.interrupted ? exit_interrupted : share.any_failed ? exit_numerical_failure : exit_success);
        }
        catch (const InputError &e)
        {
          report = e.what();
          return static_cast<int>(exit_bad_input);
        }
      });
      for (const WorkerExit &exit : exits)
        if (exit.exit_code == exit_bad_input)
          throw InputError(exit.report);
      for (std::size_t k = 0; k < exits.size(); ++k)
      {
        interrupted = interrupted || exits[k].exit_code == exit_interrupted;
        if (exits[k].exit_code != exit_success && exits[k].exit_code != exit_interrupted)
        {
          any_failed = true;
          std::cerr << "anticrack campaign: " << describe_worker_exit(static_cast<int>(k), exits[k])
                    << "; its tests are read back as their files left them\n";
        }
      }
      const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - wait_start).count();
      timer.add("tests", waited);
    }
    else
    {
      const auto [first, last] = block_of(tests, c, mpi.rank(), members);
      std::size_t cursor = first;
      Share share = run_share(
        "[rank " + std::to_string(mpi.rank()) + "]", [&, last = last] { return cursor < last ? cursor++ : tests.size(); },
        [&, last = last] { return static_cast<double>(last - cursor); });
      any_failed = share.any_failed;
      interrupted = share.interrupted;
      outcomes = std::move(share.outcomes);
    }
    any_failed = mpi.any(any_failed);
    interrupted = mpi.any(interrupted);
    mpi.barrier();
    if (!root)
      return interrupted ? exit_interrupted : any_failed ? exit_numerical_failure : exit_success;

    // --- rank 0: campaign.h5 and summary.json; the other ranks' tests from their files
    std::optional<PhaseTimer::Scope> output_phase;
    output_phase.emplace(timer, "output");
    for (const auto &t : tests)
      if (!outcomes.count(t.id))
        outcomes[t.id] = read_outcome(t, directory / "tests" / t.id);

    write_campaign_file(directory / "campaign.h5", scene, scenes.microstructures, tests, outcomes);

    CampaignSummary summary = campaign_summary(scene, tests, outcomes, any_failed, options.command_line);
    Json &s = summary.json;
    Json timing;
    timing["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    timing["sum_of_test_wall_s"] = summary.test_wall_s;
    timing["ranks"] = mpi.size();
    timing["worker_processes"] = workers ? members : 0;
    timing["threads_per_rank"] = dem::DemSystem::threads();
    output_phase.reset();
    timing["phases"] = timer.to_json();
    s["timing"] = timing;
    s["versions"] = version_info();
    write_json_atomically((directory / "summary.json").string(), s);

    std::cout << "campaign done in " << format_duration(timing["wall_s"].get<double>()) << ": "
              << tests.size() << " tests, campaign.h5 and summary.json in " << directory.string() << "\n";
    if (!summary.no_load_path.empty())
    {
      std::cout << "  " << summary.no_load_path.size() << " test(s) without a load path (their realization's bonds do not "
                << "connect the base to the clump), recorded as such:";
      for (const std::string &id : summary.no_load_path)
        std::cout << " " << id;
      std::cout << "\n";
    }
    if (summary.quasi_static_checked)
      std::cout << "  quasi-static check: largest difference of the failure point (p, q) to the "
                << c.quasi_static_slowdown << "x slower runs " << 100 * summary.largest_difference << " % (tolerance "
                << 100 * c.quasi_static_tolerance << " %)\n";
    if (interrupted)
    {
      std::cout << "  interrupted: the tests not completed are recorded as they stopped; --resume runs them\n";
      return exit_interrupted;
    }
    return any_failed ? exit_numerical_failure : exit_success;
  }
} // namespace anticrack::dem
