// A cache of calibrated weak layers, shared between pipeline runs (`anticrack run --material-cache
// DIR`, or the environment's ANTICRACK_MATERIAL_CACHE). A field study puts one DEM weak layer under
// tens of pits, and a study of a season runs several pipelines with the same weak layer: its
// campaign and calibration (minutes) then run once, and every later pipeline copies the stage's
// folder (DIR/weak_layer/: the campaign, calibration.h5, the material files, the plots) from the
// cache.
//
// The key is what decides the stage's results, and nothing else: the SHA-256 of the stage's inputs
// (the weak-layer scene's text with the pipeline's changes, and the snow units: the stage's own
// inputs_sha256, coupling/pipeline.h) and of the code that calibrates (every file coupling/calibrate.cpp
// reaches through its includes: the DEM, the calibration, the material models and the hand-off,
// with the compiler and flags that built them: anticrack::calibration_code_sha256(),
// util/source_version.h). A change to that code may calibrate differently, so it never reuses
// another code's material; a rebuild, or a change to the FE solver's models and analyses, the
// pipeline, the studies or the app, keeps the entries, so that a field study's weak layers (hours of
// DEM) outlive the FE work done on top of them. Where the pipeline scene lives, its output folder and its snowpack scenes are not in the key.
//
// An entry keeps what the pipeline, its report and its uncertainty read (the material files,
// calibration.h5, the calibration's and the campaign's summary.json, the plots), not the campaign's
// raw data (campaign.h5 with the samples and histories, and each test's folder: 25 MB for a class of
// 2 500 spheres against well under 1 MB), which stays in the run that calibrated it (the record's
// calibrated_in). So a season's classes fit in a folder one can keep beside the scenes.
//
// An entry is written whole or not at all: the folder is copied next to the cache's entries under
// a temporary name, its record (cache_entry.json: the key, what went into it, where and when it was
// calibrated) written last, and then renamed to the key; an entry without its record is not used.
// Two pipelines that calibrate the same layer at once both store it; the second rename loses and
// its copy is removed.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace anticrack::coupling
{
  class MaterialCache
  {
  public:
    /// A cache in `directory` (created when first stored into); an empty directory: no cache.
    explicit MaterialCache(std::filesystem::path directory);

    [[nodiscard]] bool enabled() const { return !directory_.empty(); }
    [[nodiscard]] const std::filesystem::path &directory() const { return directory_; }

    /// The key of a weak-layer stage with these inputs, calibrated by this build's calibrating code.
    [[nodiscard]] static std::string key(const std::string &stage_inputs_sha256);

    /// The cached entry of `key` (its folder), if one was stored whole.
    [[nodiscard]] std::optional<std::filesystem::path> find(const std::string &key) const;

    /// Replaces `stage_directory` by a copy of the entry `key` (which find() returned); returns
    /// the entry's record.
    nlohmann::ordered_json restore(const std::string &key, const std::filesystem::path &stage_directory) const;

    /// Stores the completed stage folder under `key`; `record` says where it came from (it gets the
    /// key, the inputs, the calibrating code's hash and the time, calibrated_at, added). Throws std::filesystem::filesystem_error
    /// when the cache cannot be written.
    void store(const std::string &key, const std::string &stage_inputs_sha256,
               const std::filesystem::path &stage_directory, nlohmann::ordered_json record) const;

    static constexpr const char *record_file = "cache_entry.json";
    /// The stage folder's paths an entry leaves out: the campaign's raw data.
    static constexpr const char *raw_campaign_data[] = {"campaign/campaign.h5", "campaign/tests"};

  private:
    std::filesystem::path directory_;
  };
} // namespace anticrack::coupling
