// run_snowpack(): the analysis of the scene's Analysis/Type in the scene's dimension, from one table.
#include "fem/analysis/snowpack_run.h"

#include "fem/analysis/dynamic_pst.h"
#include "fem/analysis/energy_release_rate.h"
#include "fem/analysis/quasi_static_pst.h"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <stdexcept>

namespace anticrack::fem
{
  namespace
  {
    using AnalysisFunction = Json (*)(const SnowpackScene &, const SnowpackRunOptions &, MPI_Comm);

    struct AnalysisEntry
    {
      Analysis::Type type;
      AnalysisFunction in_2d, in_3d;
    };

    const AnalysisEntry analyses[] = {
      {Analysis::Type::energy_release_rate, &run_energy_release_rate<2>, &run_energy_release_rate<3>},
      {Analysis::Type::quasi_static, &run_quasi_static_pst<2>, &run_quasi_static_pst<3>},
      {Analysis::Type::explicit_dynamics, &run_dynamic_pst<2>, &run_dynamic_pst<3>},
    };
  } // namespace

  Json run_snowpack(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm communicator)
  {
    const auto entry = std::find_if(std::begin(analyses), std::end(analyses),
                                    [&](const AnalysisEntry &e) { return e.type == scene.analysis.type; });
    if (entry == std::end(analyses))
      throw std::logic_error("run_snowpack: no analysis for this Analysis/Type");
    const auto start = std::chrono::steady_clock::now();
    Json results = (scene.mesh.dimension == 2 ? entry->in_2d : entry->in_3d)(scene, options, communicator);
    results["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return results;
  }
} // namespace anticrack::fem
