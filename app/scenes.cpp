#include "app/scenes.h"

#include "coupling/calibration_scene.h"
#include "coupling/pipeline.h"
#include "coupling/study.h"
#include "dem/campaign/campaign.h"
#include "dem/scene/parameters.h"
#include "dem/scene/dem_run.h"
#include "fem/analysis/snowpack_command.h"
#include "fem/scene/snowpack_scene.h"
#include "util/input_error.h"
#include "util/mpi_session.h"

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>

namespace anticrack::app
{
  namespace
  {
    /// Declares the DEM entries of `kind`, for `file`'s variants (see SceneKind::declare).
    void declare_dem(dealii::ParameterHandler &prm, const dem::SceneKind kind, const std::string &file,
                     const bool every_variant)
    {
      dem::Declaration declaration;
      if (!file.empty())
        declaration = dem::scene_declaration(file, kind);
      else if (!every_variant)
        declaration.sample_type = declaration.loading_test = 0; // the first of each: the entries' defaults
      declaration.kind = kind;
      dem::declare_dem_scene(prm, declaration);
    }

    /// A DEM scene of `kind`, read and checked, with its runnable component.
    dem::SceneParameters read_dem_scene(const std::string &file, const dem::SceneKind kind)
    {
      dem::SceneParameters scene = dem::read_scene(file, kind);
      dem::require_dem_component(scene);
      return scene;
    }

    struct SceneKind
    {
      const char *name;
      const char *what;
      /// Declares what a scene of this kind can set: that of `file` (its variants), or without a
      /// file the default variants (a valid scene), or with `every_variant` all of them.
      void (*declare)(dealii::ParameterHandler &prm, const std::string &file, bool every_variant);
      void (*check)(const std::string &file, int threads);
      int (*run)(const RunOptions &options);
    };

    coupling::SceneRunner scene_runner();

    // One row per kind; a new kind is a row here and its module's declare / check / run.
    const std::array<SceneKind, 6> scene_kinds{{
      {"dem", "one DEM run: a virtual-laboratory test or a free simulation (subsection DEM)",
       [](dealii::ParameterHandler &prm, const std::string &file, const bool every)
       { declare_dem(prm, dem::SceneKind::dem, file, every); },
       [](const std::string &file, const int threads)
       { dem::check_dem_scene(read_dem_scene(file, dem::SceneKind::dem), threads); },
       [](const RunOptions &options)
       { return dem::run_dem_scene(read_dem_scene(options.scene_file, dem::SceneKind::dem), options); }},
      {"campaign", "the DEM test at every loading angle x realization x microstructure (subsection Campaign)",
       [](dealii::ParameterHandler &prm, const std::string &file, const bool every)
       { declare_dem(prm, dem::SceneKind::campaign, file, every); },
       [](const std::string &file, const int threads)
       {
         const dem::SceneParameters scene = read_dem_scene(file, dem::SceneKind::campaign);
         dem::check_dem_scene(scene, threads);
         dem::describe_campaign(std::cout, scene);
       },
       [](const RunOptions &options)
       { return dem::run_campaign(read_dem_scene(options.scene_file, dem::SceneKind::campaign), options); }},
      {"calibration", "a campaign and the continuum material calibrated from it (subsections Campaign, Calibration)",
       coupling::declare_calibration_scene, coupling::check_calibration_scene, coupling::run_calibration_scene},
      {"snowpack", "a layered snowpack and its saw test with the FE solver (subsection Snowpack)",
       [](dealii::ParameterHandler &prm, const std::string &file, const bool every)
       {
         const fem::AnalysisType *type = !file.empty() ? &fem::analysis_type_in(read_scene_file(file), file)
                                         : every       ? nullptr
                                                       : &fem::default_analysis_type();
         fem::declare_snowpack_scene(prm, type);
       },
       [](const std::string &file, int) { fem::check_snowpack_scene(file); },
       fem::run_snowpack_scene},
      {"pipeline", "a DEM weak layer calibrated and put under the snowpacks of FE scenes, with a report (subsection Pipeline)",
       coupling::declare_pipeline, coupling::check_pipeline_scene, coupling::run_pipeline_scene},
      {"study", "a scene of another kind run again with entries set to other values: errors, orders, run times (subsection Study)",
       coupling::declare_study,
       [](const std::string &file, const int threads) { coupling::check_study_scene(file, threads, scene_runner()); },
       [](const RunOptions &options) { return coupling::run_study_scene(options, scene_runner()); }},
    }};

    const SceneKind &kind_named(const std::string &name, const std::string &where)
    {
      for (const SceneKind &kind : scene_kinds)
        if (name == kind.name)
          return kind;
      throw InputError(where + "unknown scene kind `" + name + "` (allowed: " + scene_kind_names() + ")");
    }

    /// The first pass: the kind a scene file says it is (`set Scene = KIND`), or for a scene
    /// written before that entry, the kind its subsections suggest (a top-level Snowpack: a
    /// snowpack scene; Campaign/Loading angles: a campaign; otherwise one DEM run), with a note
    /// on rank 0. A file that sets nothing is refused: it would run every default.
    const SceneKind &kind_of(const std::string &file)
    {
      const std::vector<ParameterSetting> settings = scan_parameter_settings(read_scene_file(file));
      if (settings.empty())
        throw InputError("The scene file <" + file + "> sets nothing: a scene says what it is (set Scene = " +
                         scene_kind_names() + ") and sets the entries of that kind (`anticrack params --scene "
                         "KIND` lists them).");
      std::string inferred = "dem";
      for (const ParameterSetting &setting : settings)
      {
        if (setting.path.size() == 1 && setting.path.front() == "Scene")
          return kind_named(setting.value, "Scene file <" + file + ">, line " + std::to_string(setting.line) +
                                             ", Scene: ");
        if (setting.path.front() == "Snowpack")
          inferred = "snowpack";
        else if (inferred == "dem" && setting.path == std::vector<std::string>{"Campaign", "Loading angles [deg]"} &&
                 !setting.value.empty())
          inferred = "campaign";
      }
      if (launcher_rank() == 0)
        std::cerr << "anticrack: note: " << file << " does not say what it is; read as a `" << inferred
                  << "` scene (add `set Scene = " << inferred << "` to say so)\n";
      return kind_named(inferred, "");
    }
    /// The study's access to the other kinds: this table's run and check.
    coupling::SceneRunner scene_runner()
    {
      return {[](const RunOptions &options) { return kind_of(options.scene_file).run(options); },
              [](const std::string &file, const int threads) { kind_of(file).check(file, threads); }};
    }
  } // namespace

  int run_scene(const RunOptions &options) { return kind_of(options.scene_file).run(options); }

  int check_scene(const std::string &scene_file, const int threads)
  {
    kind_of(scene_file).check(scene_file, threads);
    std::cout << "\nThe scene is valid.\n";
    return exit_success;
  }

  void print_scene_parameters(std::ostream &out, const ParameterFormat format, const std::string &kind_name,
                              const std::string &scene_file, const bool every_variant)
  {
    const SceneKind &kind = scene_file.empty() ? kind_named(kind_name, "") : kind_of(scene_file);
    dealii::ParameterHandler prm;
    kind.declare(prm, scene_file, every_variant);
    print_parameter_documentation(out, format, prm, kind.name, !every_variant || !scene_file.empty());
  }

  std::string scene_kind_names()
  {
    std::string names;
    for (const SceneKind &kind : scene_kinds)
      names += (names.empty() ? "" : ", ") + std::string(kind.name);
    return names;
  }
} // namespace anticrack::app
