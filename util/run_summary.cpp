#include "util/run_summary.h"

#include "util/atomic_file.h"
#include "util/source_version.h"

#include <Eigen/Core>
#include <hdf5.h>
#include <omp.h>

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
    try
    {
      return Json::parse(text);
    }
    catch (const std::exception &e)
    {
      throw std::runtime_error(file + " is not valid JSON: " + e.what());
    }
  }

  void write_json_atomically(const std::string &file, const Json &json)
  {
    write_text_atomically(file, [&](std::ostream &out) {
      // Non-finite numbers (a failed run) become null rather than invalid JSON.
      out << json.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
    });
  }
} // namespace anticrack
