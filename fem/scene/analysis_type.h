// An FE analysis as a snowpack scene knows it (the value of Analysis/Type): its name and paragraph of
// documentation, which of the entries several analyses share it reads, its own entries, what it
// needs of the rest of the scene, and the functions that run it in 2D and 3D.
//
// Each analysis describes itself in its own file of fem/analysis/ (NAME.cpp: the run and its
// `AnalysisType NAME_analysis()`), and the table of them, analysis_types(), is in
// fem/analysis/snowpack_run.cpp. The scene reader (fem/scene/snowpack_scene.cpp) sees only this
// description: it declares, parses and checks a scene from the table without including an analysis.
#pragma once

#include <mpi.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack
{
  class Problems;
}

namespace anticrack::fem
{
  using Json = nlohmann::ordered_json;

  struct SnowpackScene;       // fem/scene/snowpack_scene.h
  struct SnowpackRunOptions;  // fem/analysis/snowpack_run.h

  struct AnalysisType
  {
    const char *name;          ///< the value of Analysis/Type (and "analysis" in summary.json)
    const char *title;         ///< what `anticrack check` says the scene computes
    const char *documentation; ///< its paragraph of the Analysis/Type documentation (after "`name`: ")

    /// A yielding weak layer under gravity (the saw tests, the load to failure): it reads
    /// Analysis/Crack band regularisation, Analysis/Newton/Gravity steps and subsection
    /// Analysis/Crack detection, and needs a cohesive Cam-Clay weak layer; the pipeline reruns it
    /// for the calibration's uncertainty.
    bool yielding_weak_layer;
    /// Marches in time behind a saw that may advance: it reads PST/Saw and PST/Saw speed [m/s], and
    /// its checkpoints are what `anticrack run --resume` continues.
    bool time_integration;

    /// Declares its own entries; called inside subsection Analysis, after the shared ones.
    void (*declare_parameters)(dealii::ParameterHandler &prm);
    /// Reads them (inside subsection Analysis) into scene.analysis: into its fields that the solvers
    /// read, or into Analysis::settings for values of the analysis alone.
    void (*parse_parameters)(dealii::ParameterHandler &prm, SnowpackScene &scene);
    /// What it needs of the scene beyond its entries' patterns; adds one problem per violation.
    void (*check)(const SnowpackScene &scene, Problems &problems);

    /// Runs it; returns the "results" of summary.json (every number with its unit in its name).
    /// Collective over the communicator.
    Json (*run_2d)(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm communicator);
    Json (*run_3d)(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm communicator);
  };

  /// Every analysis, in the order the documentation lists them (fem/analysis/snowpack_run.cpp).
  const std::vector<AnalysisType> &analysis_types();
  /// The analysis of a scene that sets no Analysis/Type.
  const AnalysisType &default_analysis_type();
  /// The analysis called `name`; throws std::invalid_argument naming the allowed ones.
  const AnalysisType &analysis_type_named(const std::string &name);
  /// "a|b|c": the names, for Patterns::Selection and messages.
  std::string analysis_type_pattern();
} // namespace anticrack::fem
