// The tests of a campaign (dem/campaign/campaign.h) and what the campaign keeps of each: their ids
// and order, the ranks' shares, whether a resumed test completed earlier, and its outcome (its row
// of /failure_points and what summary.json reports beside it) from memory or from its files.
// Internal to dem/campaign.
#pragma once

#include "dem/campaign/campaign_file.h"
#include "dem/common/types.h"
#include "dem/scene/failure_analysis.h"
#include "dem/scene/parameters.h"
#include "util/run_summary.h"

#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anticrack::dem::campaign
{
  /// One test of a campaign.
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

  /// Test ids: m<M>_r<R>_psi<angle> (e.g. m0_r2_psi067.5), m<M>_r<R>_compaction, m<M>_r<R>_friction.
  std::string test_id(Index m, Index r, double angle);
  std::string compaction_test_id(Index m, Index r);
  std::string friction_test_id(Index m, Index r);

  /// Every test of the campaign, grouped by sample (microstructure, realization): first the
  /// angles, then the compaction test, then the friction test, then the sample's quasi-static
  /// references (of the angles and the compaction test; the friction test's rate is checked by
  /// hand, docs/calibration.md).
  std::vector<CampaignTest> enumerate_tests(const parameters::Campaign &c, Index microstructures);

  /// Contiguous block [begin, end) of `tests` for `rank`, balanced by the expected cost
  /// (CampaignTest::cost).
  std::pair<std::size_t, std::size_t> block_of(const std::vector<CampaignTest> &tests, const parameters::Campaign &c,
                                               int rank, int size);

  /// The status of the tests of a realization whose bonds do not connect base and clump
  /// (SpecimenWithoutLoadPath): not run, recorded, left out of the calibration.
  inline constexpr const char *status_no_load_path = "no load path";

  /// Whether the test in `directory` completed with these labels (a campaign resumed with
  /// --resume skips it).
  bool completed(const std::filesystem::path &directory, const Json &labels);

  /// What the campaign keeps of one finished test: its row of /failure_points and what
  /// summary.json reports beside it.
  struct TestOutcome
  {
    FailurePointRow row; ///< status, failure point, its companions and the sample (dem/campaign/campaign_file.h)
    std::string message;
    double steps = std::numeric_limits<double>::quiet_NaN(), wall_s = std::numeric_limits<double>::quiet_NaN();
    std::string analysis_error;
  };

  /// The outcome of test `t` from its summary (summary.json's content; null: no summary) and
  /// its failure analysis (absent for a run without a clump).
  TestOutcome outcome_of(const CampaignTest &t, const Json &s, const std::optional<TestFailureAnalysis> &analysis);

  /// The outcome of a test from its files: summary.json and, for the quasi-static measure that
  /// summary.json does not record, history.h5 (a test that completed earlier, or one that another
  /// rank ran).
  TestOutcome read_outcome(const CampaignTest &t, const std::filesystem::path &directory);

  /// |s - s_ref| / |s_ref| for the failure point s = (p, q) of the Love-Weber stress: the
  /// quasi-static check's measure. It is the yield point itself (Ritter et al.'s (2020) criterion maximises q)
  /// and a volume average; the base reactions (sigma, tau) are single-surface readings that ring
  /// with the specimen's slip events near failure (see base_relative_difference).
  double relative_difference(const TestOutcome &a, const TestOutcome &reference);

  /// The same for the base stresses (sigma, tau), reported beside it.
  double base_relative_difference(const TestOutcome &a, const TestOutcome &reference);
} // namespace anticrack::dem::campaign
