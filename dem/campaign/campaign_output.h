// campaign.h5, the file a campaign leaves for the calibration (layout in dem/campaign/campaign.h):
// every test's history and status, the microstructures' materials, the failure-point tables of the
// loading, compaction and friction tests (their columns: dem/campaign/campaign_file.h) and the
// quasi-static check. Internal to dem/campaign.
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
} // namespace anticrack::dem::campaign
