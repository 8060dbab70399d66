#include "app/scenes.h"

#include "dem/campaign/campaign.h"
#include "dem/scene/parameters.h"
#include "dem/scene/run.h"
#include "fem/analysis/run.h"
#include "fem/scene/snowpack_scene.h"
#include "util/input_error.h"

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <iostream>

namespace anticrack::app
{
  namespace
  {
    /// A DEM scene read and checked, with its runnable component.
    dem::SceneParameters read_dem_scene(const std::string &file)
    {
      dem::SceneParameters scene = dem::read_scene(file);
      dem::require_dem_component(scene);
      return scene;
    }

    struct SceneKind
    {
      const char *name;
      const char *what;
      void (*declare)(dealii::ParameterHandler &prm);
      void (*check)(const std::string &file, int threads);
      int (*run)(const RunOptions &options);
    };

    // One row per kind; a new kind is a row here and its module's declare / check / run.
    const std::array<SceneKind, 3> scene_kinds{{
      {"dem", "one DEM run: a virtual-laboratory test or a free simulation (subsection DEM)",
       dem::declare_dem_scene,
       [](const std::string &file, const int threads) { dem::check_dem_scene(read_dem_scene(file), threads); },
       [](const RunOptions &options) { return dem::run_dem_scene(read_dem_scene(options.scene_file), options); }},
      {"campaign", "the DEM test at every loading angle x realization x microstructure (subsection Campaign)",
       dem::declare_dem_scene,
       [](const std::string &file, const int threads)
       {
         const dem::SceneParameters scene = read_dem_scene(file);
         dem::check_dem_scene(scene, threads);
         dem::describe_campaign(std::cout, scene);
       },
       [](const RunOptions &options) { return dem::run_campaign(read_dem_scene(options.scene_file), options); }},
      {"snowpack", "a layered snowpack and its saw test with the FE solver (subsection Snowpack)",
       fem::declare_snowpack_scene,
       [](const std::string &file, int) { fem::check_snowpack_scene(file); }, fem::run_snowpack_scene},
    }};

    const SceneKind &kind_named(const std::string &name)
    {
      for (const SceneKind &kind : scene_kinds)
        if (name == kind.name)
          return kind;
      throw InputError("unknown scene kind `" + name + "` (allowed: " + scene_kind_names() + ")");
    }

    /// The kind of a scene file: a top-level `subsection Snowpack` makes a snowpack scene, a
    /// DEM scene with loading angles a campaign.
    const SceneKind &kind_of(const std::string &file)
    {
      if (fem::is_snowpack_scene(file))
        return kind_named("snowpack");
      return kind_named(read_dem_scene(file).campaign.enabled() ? "campaign" : "dem");
    }
  } // namespace

  int run_scene(const RunOptions &options) { return kind_of(options.scene_file).run(options); }

  int check_scene(const std::string &scene_file, const int threads)
  {
    kind_of(scene_file).check(scene_file, threads);
    std::cout << "\nThe scene is valid.\n";
    return exit_success;
  }

  void print_scene_parameters(std::ostream &out, const ParameterFormat format, const std::string &kind_name)
  {
    const SceneKind &kind = kind_named(kind_name);
    dealii::ParameterHandler prm;
    kind.declare(prm);
    print_parameter_documentation(out, format, prm, kind.name);
  }

  std::string scene_kind_names()
  {
    std::string names;
    for (const SceneKind &kind : scene_kinds)
      names += (names.empty() ? "" : ", ") + std::string(kind.name);
    return names;
  }
} // namespace anticrack::app
