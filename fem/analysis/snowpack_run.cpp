// run_snowpack(): the analysis of the scene's Analysis/Type in the scene's dimension, and the table
// of analyses (fem/scene/analysis_type.h) that the scene reader declares, parses and checks from.
#include "fem/analysis/snowpack_run.h"

#include <chrono>
#include <stdexcept>

namespace anticrack::fem
{
  // Each in its own file of fem/analysis/.
  AnalysisType energy_release_rate_analysis();
  AnalysisType quasi_static_pst_analysis();
  AnalysisType dynamic_pst_analysis();
  AnalysisType load_to_failure_analysis();

  const std::vector<AnalysisType> &analysis_types()
  {
    static const std::vector<AnalysisType> types{
      energy_release_rate_analysis(),
      quasi_static_pst_analysis(),
      dynamic_pst_analysis(),
      load_to_failure_analysis(),
    };
    return types;
  }

  const AnalysisType &default_analysis_type() { return analysis_type_named("explicit dynamics"); }

  Json run_snowpack(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm communicator)
  {
    const AnalysisType *type = scene.analysis.type;
    if (!type)
      throw std::logic_error("run_snowpack: the scene has no Analysis/Type (it was not read by read_snowpack_scene)");
    const auto start = std::chrono::steady_clock::now();
    Json results = (scene.mesh.dimension == 2 ? type->run_2d : type->run_3d)(scene, options, communicator);
    results["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return results;
  }
} // namespace anticrack::fem
