#include "dem/campaign/campaign_tests.h"

#include "dem/scene/history_columns.h"
#include "util/hdf5_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

namespace anticrack::dem::campaign
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();

    using hdf5::Handle;

    /// One column of a history.h5 file.
    std::vector<double> read_history_column(const fs::path &file, const std::string &name)
    {
      const Handle f = hdf5::open_file_read_only(file.string());
      return hdf5::read_doubles(f.id, name);
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
  } // namespace

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

  double relative_difference(const TestOutcome &a, const TestOutcome &reference)
  {
    return std::hypot(a.row.p - reference.row.p, a.row.q - reference.row.q) /
           std::hypot(reference.row.p, reference.row.q);
  }

  double base_relative_difference(const TestOutcome &a, const TestOutcome &reference)
  {
    return std::hypot(a.row.sigma - reference.row.sigma, a.row.tau - reference.row.tau) /
           std::hypot(reference.row.sigma, reference.row.tau);
  }
} // namespace anticrack::dem::campaign
