#include "dem/campaign/campaign.h"

#include "dem/campaign/campaign_file.h"
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

  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();

    // ---------------------------------------------------------------------------- tests
    struct CampaignTest
    {
      std::string id;
      Index microstructure = 0;
      Index realization = 0;
      double angle_deg = 0;
      double slowdown = 1;       ///< > 1: a quasi-static reference run
      std::string reference_for; ///< the test a reference run checks
      /// The loading: a load-controlled mixed-mode test at the angle, the displacement-controlled
      /// compaction test (psi = 0), or the simple shear of the collapsed layer.
      enum class Kind
      {
        load_controlled,
        compaction,
        friction
      };
      Kind kind = Kind::load_controlled;

      [[nodiscard]] bool compaction() const { return kind == Kind::compaction; }
      [[nodiscard]] bool friction() const { return kind == Kind::friction; }
      /// As campaign.h5 and summary.json name the loading.
      [[nodiscard]] const char *loading_name() const
      {
        return compaction() ? "compaction" : friction() ? "friction" : "load-controlled";
      }

      /// Expected cost in units of a load-controlled test at the campaign's rate (block_of).
      [[nodiscard]] double cost(const parameters::Campaign &c) const
      {
        return slowdown * (compaction() ? compaction_cost_factor * c.compaction_final_strain :
                           friction()   ? friction_cost_factor :
                                          1.0);
      }
      /// A compaction test to strain 1 costs about this many load-controlled tests, a friction test
      /// about that many (measured on the SHS weak layer of scenes/shs_weak_layer.prm; only the
      /// balance of the ranks' shares depends on them).
      static constexpr double compaction_cost_factor = 10;
      static constexpr double friction_cost_factor = 6;
    };

    std::string compaction_test_id(Index m, Index r)
    {
      return "m" + std::to_string(m) + "_r" + std::to_string(r) + "_compaction";
    }

    std::string friction_test_id(Index m, Index r)
    {
      return "m" + std::to_string(m) + "_r" + std::to_string(r) + "_friction";
    }

    std::string test_id(Index m, Index r, double angle)
    {
      char text[64];
      std::snprintf(text, sizeof text, "m%lld_r%lld_psi%05.1f", static_cast<long long>(m),
                    static_cast<long long>(r), angle);
      return text;
    }

    /// Every test of the campaign, grouped by sample (microstructure, realization): first the
    /// angles, then the compaction test, then the friction test, then the sample's quasi-static
    /// references (of the angles and the compaction test; the friction test's rate is checked by
    /// hand, docs/calibration.md).
    std::vector<CampaignTest> enumerate_tests(const parameters::Campaign &c, Index microstructures)
    {
      using Check = parameters::Campaign::QuasiStaticCheck;
      using Kind = CampaignTest::Kind;
      std::vector<CampaignTest> tests;
      for (Index m = 0; m < microstructures; ++m)
        for (Index r = 0; r < c.realizations; ++r)
        {
          for (const double angle : c.loading_angles_deg)
            tests.push_back({test_id(m, r, angle), m, r, angle, 1.0, "", Kind::load_controlled});
          if (c.has_compaction_tests())
            tests.push_back({compaction_test_id(m, r), m, r, 0.0, 1.0, "", Kind::compaction});
          if (c.has_friction_tests())
            tests.push_back({friction_test_id(m, r), m, r, 0.0, 1.0, "", Kind::friction});
          const bool checked = c.quasi_static_check == Check::all ||
                               (c.quasi_static_check == Check::first_realization && r == 0);
          if (!checked)
            continue;
          char suffix[32];
          std::snprintf(suffix, sizeof suffix, "_slow%g", c.quasi_static_slowdown);
          for (const double angle : c.loading_angles_deg)
            tests.push_back(
              {test_id(m, r, angle) + suffix, m, r, angle, c.quasi_static_slowdown, test_id(m, r, angle),
               Kind::load_controlled});
          if (c.has_compaction_tests())
            tests.push_back({compaction_test_id(m, r) + suffix, m, r, 0.0, c.quasi_static_slowdown,
                             compaction_test_id(m, r), Kind::compaction});
        }
      return tests;
    }

    /// Contiguous block [begin, end) of `tests` for `rank`, balanced by the expected cost
    /// (CampaignTest::cost).
    std::pair<std::size_t, std::size_t> block_of(const std::vector<CampaignTest> &tests, const parameters::Campaign &c,
                                                 int rank, int size)
    {
      double total = 0;
      for (const auto &t : tests)
        total += t.cost(c);
      std::size_t begin = tests.size(), end = 0;
      double before = 0;
      for (std::size_t k = 0; k < tests.size(); ++k)
      {
        const double middle = before + 0.5 * tests[k].cost(c);
        const int owner = std::min(size - 1, static_cast<int>(middle / total * size));
        if (owner == rank)
          begin = std::min(begin, k), end = k + 1;
        before += tests[k].cost(c);
      }
      return begin < end ? std::pair{begin, end} : std::pair{std::size_t(0), std::size_t(0)};
    }

    /// The status of the tests of a realization whose bonds do not connect base and clump
    /// (SpecimenWithoutLoadPath): not run, recorded, left out of the calibration.
    constexpr const char *status_no_load_path = "no load path";

    /// The test's summary if it completed (a campaign resumed with --resume skips it).
    bool completed(const fs::path &directory, const Json &labels)
    {
      std::error_code error;
      if (!fs::exists(directory / "summary.json", error))
        return false;
      try
      {
        const Json s = read_json_file((directory / "summary.json").string());
        // A test of a clump-driven specimen completed before the Love-Weber stress was that of the
        // specimen between its platens (docs/physics.md §1.5) is run again, not mixed with new ones.
        const Json::json_pointer specimen("/dem/specimen");
        const bool current_stress =
          !s.contains(specimen) || s[specimen].contains("love_weber_volume");
        return s.value("status", "") == "completed" && s.contains("labels") && s["labels"] == labels &&
               current_stress;
      }
      catch (const std::exception &)
      {
        return false;
      }
    }

    // ------------------------------------------------------------------------- campaign.h5
    using hdf5::Handle;

    /// One column of a history.h5 file.
    std::vector<double> read_history_column(const fs::path &file, const std::string &name)
    {
      const Handle f = hdf5::open_file_read_only(file.string());
      return hdf5::read_doubles(f.id, name);
    }

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

    /// A value as summary.json records it: JSON has no infinity or NaN (they are written as null
    /// and read back as NaN), so a test's outcome is the same whether it comes from memory or from
    /// the file of a test that completed earlier.
    double as_recorded(double value) { return std::isfinite(value) ? value : nan; }

    /// A number of a JSON object at `pointer`, NaN when absent.
    double number_at(const Json &j, const std::string &pointer)
    {
      const Json::json_pointer p(pointer);
      return j.contains(p) && j[p].is_number() ? as_recorded(j[p].get<double>()) : nan;
    }

    /// What the campaign keeps of one finished test: its row of /failure_points and what
    /// summary.json reports beside it.
    struct TestOutcome
    {
      FailurePointRow row; ///< status, failure point, its companions and the sample (dem/campaign/campaign_file.h)
      std::string message;
      double steps = nan, wall_s = nan;
      std::string analysis_error;
    };

    /// The outcome of test `t` from its summary (summary.json's content; null: no summary) and
    /// its failure analysis (absent for a run without a clump).
    TestOutcome outcome_of(const CampaignTest &t, const Json &s, const std::optional<TestFailureAnalysis> &analysis)
    {
      TestOutcome o;
      FailurePointRow &row = o.row;
      row.test = t.id;
      row.microstructure = static_cast<double>(t.microstructure);
      row.realization = static_cast<double>(t.realization);
      row.loading_angle_deg = t.angle_deg;
      if (s.is_null())
      {
        row.status = "missing";
        return o;
      }
      row.status = s.value("status", "unknown");
      o.message = s.value("message", "");
      o.steps = number_at(s, "/dem/steps");
      o.wall_s = number_at(s, "/timing/wall_s");
      row.solid_fraction = number_at(s, "/dem/sample/volume_fraction");
      if (std::isnan(row.solid_fraction))
        row.solid_fraction = number_at(s, "/dem/sample/solid_fraction_bulk");
      row.coordination = number_at(s, "/dem/sample/coordination");
      if (std::isnan(row.coordination))
        row.coordination = number_at(s, "/dem/sample/mean_contacts");
      row.bonds = number_at(s, "/dem/bonds");
      row.specimen_height = number_at(s, "/dem/specimen/height_m");
      row.layer_thickness = number_at(s, "/dem/specimen/layer_thickness_m");
      row.particle_diameter = number_at(s, "/dem/specimen/mean_particle_diameter_m");
      row.steady_shear_stress = number_at(s, "/dem/lab_test/results/steady_shear_stress_Pa");
      row.steady_normal_stress = number_at(s, "/dem/lab_test/results/steady_normal_stress_Pa");
      row.steady_stress_ratio = number_at(s, "/dem/lab_test/results/steady_stress_ratio");
      if (!analysis)
        return o;
      const TestFailureAnalysis &a = *analysis;
      if (!a.error.empty())
      {
        o.analysis_error = a.error;
        return o;
      }
      const RecordedFailurePoint &f = a.failure;
      row.sigma = as_recorded(f.sigma.value_or(nan));
      row.tau = as_recorded(f.tau.value_or(nan));
      row.p = as_recorded(f.p);
      row.q = as_recorded(f.q);
      row.failure_time = as_recorded(f.time);
      row.failure_step = as_recorded(f.step);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          row.love_stress[3 * r + c] = as_recorded(f.love_stress(r, c));
      row.flow_angle_deg = as_recorded(a.flow_angle_deg.value_or(nan));
      // The column is the secant modulus of the base normal stress; a shear-controlled test's
      // secant modulus is of the shear stress.
      row.secant_modulus = a.control == ActuatorControl::shear_displacement ? nan : as_recorded(a.secant_modulus.value_or(nan));
      row.softening_ratio = as_recorded(a.softening_ratio.value_or(nan));
      row.peak_q = as_recorded(a.peak_q.q);
      row.max_inertial_number = a.max_inertial_number;
      return o;
    }

    /// The outcome of a test from its files: summary.json and, for the quasi-static measure that
    /// summary.json does not record, history.h5 (a test that completed earlier, or one that another
    /// rank ran).
    TestOutcome read_outcome(const CampaignTest &t, const fs::path &directory)
    {
      std::error_code error;
      if (!fs::exists(directory / "summary.json", error))
        return outcome_of(t, Json(), std::nullopt);
      const Json s = read_json_file((directory / "summary.json").string());
      const Json::json_pointer analysis_pointer("/dem/failure_analysis");
      std::optional<TestFailureAnalysis> analysis;
      if (s.contains(analysis_pointer))
        analysis = failure_analysis_from_json(s[analysis_pointer]);
      if (analysis && analysis->error.empty() && !std::isnan(analysis->failure.step) &&
          fs::exists(directory / "history.h5", error))
      {
        const fs::path history = directory / "history.h5";
        analysis->max_inertial_number = max_inertial_number_before_failure(
          read_history_column(history, history_column::step),
          read_history_column(history, history_column::von_mises_stress),
          read_history_column(history, history_column::inertial_number), analysis->failure.step, analysis->failure.q);
      }
      return outcome_of(t, s, analysis);
    }

    /// |s - s_ref| / |s_ref| for the failure point s = (p, q) of the Love-Weber stress: the
    /// quasi-static check's measure. It is the yield point itself (Ritter et al.'s (2020) criterion maximises q)
    /// and a volume average; the base reactions (sigma, tau) are single-surface readings that ring
    /// with the specimen's slip events near failure (see base_relative_difference).
    double relative_difference(const TestOutcome &a, const TestOutcome &reference)
    {
      return std::hypot(a.row.p - reference.row.p, a.row.q - reference.row.q) /
             std::hypot(reference.row.p, reference.row.q);
    }

    /// The same for the base stresses (sigma, tau), reported beside it.
    double base_relative_difference(const TestOutcome &a, const TestOutcome &reference)
    {
      return std::hypot(a.row.sigma - reference.row.sigma, a.row.tau - reference.row.tau) /
             std::hypot(reference.row.sigma, reference.row.tau);
    }

    std::string format_angle(double a)
    {
      std::ostringstream s;
      s << a;
      return s.str();
    }
  } // namespace

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

    /// campaign.h5: every test's history and status, the microstructures' materials, the
    /// failure-point tables of the loading, compaction and friction tests and the quasi-static check.
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
            std::string label = c.microstructures.empty() ? "scene sample" : "";
            if (!c.microstructures.empty())
              for (const auto &[entry, value] : c.microstructures[m])
                label += (label.empty() ? "" : ", ") + entry + " = " + value;
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

    // summary.json
    Json s;
    s["status"] = any_failed ? "failed" : "completed";
    s["command"] = options.command_line;
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
    Json timing;
    timing["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    timing["sum_of_test_wall_s"] = test_wall;
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
    if (!no_load_path.empty())
    {
      std::cout << "  " << no_load_path.size() << " test(s) without a load path (their realization's bonds do not "
                << "connect the base to the clump), recorded as such:";
      for (const std::string &id : no_load_path)
        std::cout << " " << id;
      std::cout << "\n";
    }
    if (!check.empty())
      std::cout << "  quasi-static check: largest difference of the failure point (p, q) to the "
                << c.quasi_static_slowdown << "x slower runs " << 100 * worst << " % (tolerance "
                << 100 * c.quasi_static_tolerance << " %)\n";
    if (interrupted)
    {
      std::cout << "  interrupted: the tests not completed are recorded as they stopped; --resume runs them\n";
      return exit_interrupted;
    }
    return any_failed ? exit_numerical_failure : exit_success;
  }
} // namespace anticrack::dem
