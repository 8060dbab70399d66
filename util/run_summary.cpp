#include "util/run_summary.h"

#include "util/atomic_file.h"
#include "util/sha256.h"
#include "util/source_version.h"

#include <Eigen/Core>
#include <hdf5.h>
#include <omp.h>

#include <filesystem>
#include <stdexcept>

// From CMake (util/CMakeLists.txt): util links no deal.II.
#ifndef ANTICRACK_DEAL_II_VERSION
#  define ANTICRACK_DEAL_II_VERSION "unknown"
#endif

namespace anticrack
{
  Json version_info()
  {
    unsigned major = 0, minor = 0, release = 0;
    H5get_libversion(&major, &minor, &release);
    Json v;
    v["anticrack"] = source_version();
    v["deal.II"] = ANTICRACK_DEAL_II_VERSION;
    v["eigen"] = std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                 std::to_string(EIGEN_MINOR_VERSION);
    v["hdf5"] = std::to_string(major) + "." + std::to_string(minor) + "." + std::to_string(release);
#if defined(__clang__)
    v["compiler"] = std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
    v["compiler"] = std::string("gcc ") + __VERSION__;
#else
    v["compiler"] = "unknown";
#endif
    v["openmp_threads"] = omp_get_max_threads();
    return v;
  }

  Json read_json_file(const std::string &file)
  {
    const std::string text = read_text_file(file);
    Json json;
    try
    {
      json = Json::parse(text);
    }
    catch (const std::exception &e)
    {
      throw UnusableOutputFile(file, text.empty() ? "is empty" : "is not valid JSON (torn, cut short, or not written by anticrack)");
    }
    if (!json.is_object())
      throw UnusableOutputFile(file, "holds JSON but not an object (" + std::string(json.type_name()) +
                                       "): it is not a file anticrack writes");
    return json;
  }

  bool completed_from_scene(const std::string &summary_file, const std::string &scene_sha256)
  {
    std::error_code error;
    if (!std::filesystem::exists(summary_file, error))
      return false;
    return interpret_json_file(summary_file, "a run's summary", [&](const Json &summary) {
      if (summary.value("status", "") != "completed" || !summary.contains("scene") ||
          summary["scene"].value("file_sha256", "") != scene_sha256)
        return false;
      const Json materials = summary["scene"].value("material_files", Json::object()); // named: items() refers to it
      for (const auto &[layer, material] : materials.items())
      {
        const std::string file = material.at("file").get<std::string>();
        if (!std::filesystem::exists(file, error) || util::sha256_of_file(file) != material.at("sha256").get<std::string>())
          return false;
      }
      return true;
    });
  }

  void write_json_atomically(const std::string &file, const Json &json)
  {
    write_text_atomically(file, [&](std::ostream &out) {
      // Non-finite numbers (a failed run) become null rather than invalid JSON.
      out << json.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    });
  }
} // namespace anticrack
