#include "coupling/material_cache.h"

#include "util/run_summary.h"
#include "util/sha256.h"
#include "util/source_version.h"

#include <unistd.h>

#include <algorithm>
#include <ctime>
#include <fstream>

namespace anticrack::coupling
{
  namespace fs = std::filesystem;

  namespace
  {
    /// Now, UTC, ISO 8601.
    std::string utc_now()
    {
      const std::time_t now = std::time(nullptr);
      char text[32];
      std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
      return text;
    }

    /// The stage folder's files but the campaign's raw data (MaterialCache::raw_campaign_data).
    void copy_without_raw_campaign(const fs::path &stage_directory, const fs::path &entry)
    {
      fs::create_directories(entry);
      for (auto it = fs::recursive_directory_iterator(stage_directory); it != fs::recursive_directory_iterator(); ++it)
      {
        const fs::path relative = fs::relative(it->path(), stage_directory);
        const auto &left_out = MaterialCache::raw_campaign_data;
        if (std::find(std::begin(left_out), std::end(left_out), relative.generic_string()) != std::end(left_out))
        {
          if (it->is_directory())
            it.disable_recursion_pending();
          continue;
        }
        if (it->is_directory())
          fs::create_directories(entry / relative);
        else
          fs::copy_file(it->path(), entry / relative);
      }
    }
  } // namespace

  MaterialCache::MaterialCache(fs::path directory)
    : directory_(directory.empty() ? directory : fs::absolute(directory))
  {}

  std::string MaterialCache::key(const std::string &stage_inputs_sha256)
  {
    return util::sha256_hex("weak-layer stage inputs " + stage_inputs_sha256 + "\ncalibrating code " +
                            calibration_code_sha256());
  }

  std::optional<fs::path> MaterialCache::find(const std::string &key) const
  {
    if (!enabled())
      return std::nullopt;
    const fs::path entry = directory_ / key;
    std::error_code error;
    if (fs::is_directory(entry, error) && fs::is_regular_file(entry / record_file, error))
      return entry;
    return std::nullopt;
  }

  nlohmann::ordered_json MaterialCache::restore(const std::string &key, const fs::path &stage_directory) const
  {
    const fs::path entry = directory_ / key;
    fs::remove_all(stage_directory);
    fs::create_directories(stage_directory.parent_path());
    fs::copy(entry, stage_directory, fs::copy_options::recursive);
    fs::remove(stage_directory / record_file);
    std::ifstream in(entry / record_file);
    return nlohmann::ordered_json::parse(in);
  }

  void MaterialCache::store(const std::string &key, const std::string &stage_inputs_sha256,
                            const fs::path &stage_directory, nlohmann::ordered_json record) const
  {
    fs::create_directories(directory_);
    const fs::path entry = directory_ / key;
    const fs::path staging = directory_ / (".incoming-" + key + "-" + std::to_string(::getpid()));
    fs::remove_all(staging);
    copy_without_raw_campaign(stage_directory, staging);
    record["calibrated_at"] = utc_now(); // stored right after the calibration completed
    record["key"] = key;
    record["stage_inputs_sha256"] = stage_inputs_sha256;
    record["calibration_code_sha256"] = calibration_code_sha256();
    record["versions"] = version_info();
    record["left_out"] = std::vector<std::string>(std::begin(raw_campaign_data), std::end(raw_campaign_data));
    record["calibrated_in"] = fs::absolute(stage_directory).string();
    write_json_atomically((staging / record_file).string(), record);
    std::error_code error;
    fs::rename(staging, entry, error); // fails if another run stored the same key first
    if (error)
      fs::remove_all(staging);
  }
} // namespace anticrack::coupling
