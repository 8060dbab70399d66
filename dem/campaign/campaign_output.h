// campaign.h5, the file a campaign leaves for the calibration (layout in dem/campaign/campaign.h):
// every test's history and status, the microstructures' materials, the failure-point tables of the
// loading, compaction and friction tests (their columns: dem/campaign/campaign_file.h) and the
// quasi-static check; and the campaign's summary.json. Internal to dem/campaign.
#pragma once

#include "dem/campaign/campaign_tests.h"

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace anticrack::dem::campaign
{
  /// Writes `campaign_file` whole (atomically) from the tests' outcomes and histories
  /// (DIRECTORY/tests/<id>/history.h5 next to it).
  void write_campaign_file(const std::filesystem::path &campaign_file, const SceneParameters &scene,
                           const std::vector<SceneParameters> &microstructure_scenes,
                           const std::vector<CampaignTest> &tests, std::map<std::string, TestOutcome> &outcomes);

  /// The campaign's summary.json up to its outputs (the driver adds its timing and versions), and
  /// what the console repeats of it.
  struct CampaignSummary
  {
    Json json;
    double test_wall_s = 0;                ///< the tests' own wall times, summed
    std::vector<std::string> no_load_path; ///< tests whose realization's bonds do not connect base and clump
    bool quasi_static_checked = false;
    double largest_difference = 0;         ///< of the quasi-static check's pairs (infinite: one without a value)
  };
  CampaignSummary campaign_summary(const SceneParameters &scene, const std::vector<CampaignTest> &tests,
                                   std::map<std::string, TestOutcome> &outcomes, bool any_failed,
                                   const std::string &command);
} // namespace anticrack::dem::campaign
