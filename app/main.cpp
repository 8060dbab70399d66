// anticrack: the command-line front end.
//
//   anticrack run SCENE.prm -o DIR [--resume] [--overwrite] [--threads T] [--material-cache DIR]
//   anticrack check SCENE.prm [--threads T]
//   anticrack calibrate CAMPAIGN.h5|SCENE.prm -o DIR [--poisson-ratio NU]
//                       [--bootstrap N] [--seed S] [--confidence C] [--no-plots] [--overwrite]
//                       [--threads T] [--snow-bond-strength PA --snow-bond-modulus PA
//                        --snow-grain-diameter M --snow-particle-density KG_M3]
//   anticrack params [--snowpack] [--format prm|description|json]
//   anticrack bench dem --lattice n --steps S --threads T
//
// Exit codes: 0 success, 1 numerical failure of a run that has started, 2 bad input (scene,
// command line, checkpoint that does not match), 130 interrupted. Bad input is always found before
// anything is written.
#include "app/bench.h"
#include "app/scenes.h"
#include "coupling/calibrate.h"
#include "dem/common/types.h"
#include "util/input_error.h"
#include "util/mpi_session.h"
#include "util/output_lock.h"
#include "util/source_version.h"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iterator>
#include <iostream>
#include <optional>
#include <string>

namespace
{
  using namespace anticrack;
  using namespace anticrack::app;
  using anticrack::coupling::CalibrateOptions;

  void print_framed_error(const std::string &title, const std::string &message)
  {
    // Under mpirun every rank finds the same bad input: rank 0 reports it (ANTICRACK_DEBUG_RANKS set:
    // every rank does, for an error that only another rank meets).
    if (launcher_rank() != 0 && !std::getenv("ANTICRACK_DEBUG_RANKS"))
      return;
    const std::string rule(78, '-');
    std::cerr << "\n" << rule << "\n" << title << "\n\n" << message << "\n" << rule << "\n";
  }

  /// The one table from the modules' error types to the exit code and the title of the message;
  /// the first row whose type the error has wins.
  struct ErrorKind
  {
    bool (*matches)(const std::exception &);
    const char *title;
    int exit_code;
  };

  template <class Error>
  bool is(const std::exception &e)
  {
    return dynamic_cast<const Error *>(&e) != nullptr;
  }

  const ErrorKind error_kinds[] = {
    {is<InputError>, "anticrack: invalid input (nothing was written)", exit_bad_input},
    {is<UnusableOutputFile>, "anticrack: a file of an earlier run cannot be used (nothing was written)", exit_bad_input},
    {is<dem::SetupError>, "anticrack: invalid set-up", exit_bad_input},
    {is<dem::NumericalError>, "anticrack: numerical failure", exit_numerical_failure},
    {is<std::exception>, "anticrack: error", exit_numerical_failure},
  };

  const ErrorKind &kind_of_error(const std::exception &e)
  {
    for (const ErrorKind &kind : error_kinds)
      if (kind.matches(e))
        return kind;
    return error_kinds[std::size(error_kinds) - 1];
  }

  std::string join_arguments(int argc, char **argv)
  {
    std::string line;
    for (int k = 0; k < argc; ++k)
      line += (k ? " " : "") + std::string(argv[k]);
    return line;
  }
  /// The subcommands' options as CLI11 fills them, and the subcommands themselves (null until
  /// declared), one declaration function per subcommand below; `run_command` runs the one given.
  struct CommandLine
  {
    RunOptions run_options;
    CLI::App *run = nullptr;

    CalibrateOptions calibrate_options;
    coupling::SnowUnits snow;
    CLI::Option *snow_strength = nullptr;
    bool no_plots = false;
    CLI::App *calibrate = nullptr;

    std::string check_file;
    int check_threads = -1;
    CLI::App *check = nullptr;

    std::string format = "prm", params_kind = "dem", params_scene;
    bool snowpack_parameters = false, every_variant = false;
    CLI::App *params = nullptr;

    BenchOptions bench_options;
    CLI::App *bench_dem = nullptr;
  };

  void declare_run(CLI::App &app, CommandLine &c)
  {
    RunOptions &run_options = c.run_options;
    auto *run = c.run = app.add_subcommand("run", "Run a scene and write its results into a directory");
    run->add_option("scene", run_options.scene_file, "Scene file (.prm)")->required()->check(CLI::ExistingFile);
    run->add_option("-o,--output", run_options.output_directory,
                    "Output directory (DEM: summary.json, history.h5, snapshots/, paraview/, checkpoint.h5; "
                    "snowpack: summary.json, series.h5 or energy_release_rate.h5, fields/)")
      ->required();
    auto *resume_flag = run->add_flag("--resume", run_options.resume,
                  "Continue from DIR/checkpoint.h5 up to DEM/Steps (the scene must match the checkpoint)");
    run->add_flag("--overwrite", run_options.overwrite,
                  "Replace the outputs of an earlier run in DIR (otherwise such a directory is refused)")
      ->excludes(resume_flag);
    run->add_option("--threads", run_options.threads,
                    "OpenMP threads of a DEM scene (0: all available); overrides DEM/Threads (snowpack scenes use MPI "
                    "ranks only)")
      ->check(CLI::NonNegativeNumber);
    run->add_option("--material-cache", run_options.material_cache,
                    "Pipelines: a folder of calibrated weak layers shared between runs; a weak layer calibrated "
                    "before with the same inputs by the same calibrating code is copied from it, a new one stored in it "
                    "(coupling/material_cache.h)")
      ->envname("ANTICRACK_MATERIAL_CACHE");
  }

  void declare_calibrate(CLI::App &app, CommandLine &c)
  {
    CalibrateOptions &calibrate_options = c.calibrate_options;
    auto *calibrate = c.calibrate = app.add_subcommand(
      "calibrate", "Fit the continuum material (cohesive Cam-Clay, elasticity, softening) to a DEM campaign");
    calibrate->add_option("input", calibrate_options.input,
                          "campaign.h5 of a campaign run, or a scene (.prm) whose campaign is run first into DIR/campaign")
      ->required()
      ->check(CLI::ExistingFile);
    calibrate->add_option("-o,--output", calibrate_options.output_directory,
                          "Output directory (material file(s), calibration.h5, summary.json, plots)")
      ->required();
    calibrate->add_option("--bootstrap", calibrate_options.bootstrap_samples,
                          "Bootstrap resamples of the realizations (0: covariance intervals only)")
      ->check(CLI::Range(0, 100000))
      ->capture_default_str();
    calibrate->add_option("--seed", calibrate_options.seed, "Seed of the bootstrap")->capture_default_str();
    calibrate->add_option("--confidence", calibrate_options.confidence, "Level of every interval")
      ->check(CLI::Range(0.5, 0.999))
      ->capture_default_str();
    calibrate->add_option("--poisson-ratio", calibrate_options.poisson_ratio,
                          "Poisson's ratio to use instead of the one from the 0 and 90 degree tests (E then comes from "
                          "the axial modulus alone); for specimens that are not isotropic")
      ->check(CLI::Range(-0.999, 0.499));
    c.snow_strength =
      calibrate->add_option("--snow-bond-strength", c.snow.bond_tensile_strength,
                            "Also write the material in snow units (material_snow.prm): the snow's bond tensile strength "
                            "[Pa]; every modulus and strength scales by it over the DEM's (docs/calibration.md)")
        ->check(CLI::PositiveNumber);
    // The snow's other units: all four or none (coupling/snow_units.h).
    const std::vector<CLI::Option *> snow_options = {
      c.snow_strength,
      calibrate->add_option("--snow-bond-modulus", c.snow.bond_modulus,
                            "The snow's bond modulus for material_snow.prm [Pa]; the campaign must have been run at "
                            "its ratio to the bond strength")
        ->check(CLI::PositiveNumber),
      calibrate->add_option("--snow-grain-diameter", c.snow.grain_diameter,
                            "The snow's grain diameter for material_snow.prm [m]; lengths scale by it over the "
                            "DEM's mean sphere diameter")
        ->check(CLI::PositiveNumber),
      calibrate->add_option("--snow-particle-density", c.snow.particle_density,
                            "The snow's grain density for material_snow.prm [kg/m^3] (ice: 917)")
        ->check(CLI::PositiveNumber)};
    for (CLI::Option *option : snow_options)
      for (CLI::Option *other : snow_options)
        if (other != option)
          option->needs(other);
    calibrate->add_flag("--no-plots", c.no_plots, "Do not run scripts/plot_calibration.py");
    calibrate->add_flag("--overwrite", calibrate_options.overwrite, "Replace an earlier calibration in DIR");
    calibrate->add_option("--threads", calibrate_options.threads, "OpenMP threads of a scene's campaign")
      ->check(CLI::NonNegativeNumber);
  }

  void declare_check(CLI::App &app, CommandLine &c)
  {
    auto *check = c.check = app.add_subcommand("check", "Validate a scene and build its model; print what would run");
    check->add_option("scene", c.check_file, "Scene file (.prm)")->required()->check(CLI::ExistingFile);
    check->add_option("--threads", c.check_threads, "OpenMP threads (0: all available)")
      ->check(CLI::NonNegativeNumber);
  }

  void declare_params(CLI::App &app, CommandLine &c)
  {
    auto *params = c.params = app.add_subcommand(
      "params", "Print the entries a scene can set, each with its default, pattern and documentation");
    params->add_option("scene", c.params_scene, "A scene file: list what this scene (its kind and variants) can set")
      ->check(CLI::ExistingFile);
    params->add_option("--scene", c.params_kind, "The kind of scene: " + scene_kind_names())->capture_default_str();
    params->add_flag("--snowpack", c.snowpack_parameters, "Same as --scene snowpack");
    params->add_flag("--every-variant", c.every_variant,
                     "The entries of every variant (DEM/Sample/Type, DEM/Loading/Test), not only the default one; "
                     "the listing is then documentation, not a valid scene");
    params->add_option("--format", c.format, "prm (a complete scene with comments), description, or json")
      ->check(CLI::IsMember({"prm", "description", "json"}))
      ->capture_default_str();
  }

  void declare_bench(CLI::App &app, CommandLine &c)
  {
    auto *bench = app.add_subcommand("bench", "Benchmarks");
    bench->require_subcommand(1);
    auto *bench_dem_command = c.bench_dem = bench->add_subcommand(
      "dem", "Time the DEM engine on a bonded periodic simple-cubic lattice; prints one JSON line");
    bench_dem_command->add_option("--lattice", c.bench_options.lattice, "Spheres per edge n (n^3 spheres)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
    bench_dem_command->add_option("--steps", c.bench_options.steps, "Time steps to time")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
    bench_dem_command->add_option("--threads", c.bench_options.threads, "OpenMP threads (0: all available)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  }

  /// Runs the subcommand the command line gave; exceptions reach main().
  int run_command(const CommandLine &c, int argc, char **argv)
  {
    // One process writes into an output directory at a time (util/output_lock.h); under mpirun the
    // first rank holds the lock for all of them.
    std::optional<OutputDirectoryLock> output_lock;
    if (launcher_rank() == 0 && (*c.run || *c.calibrate))
      output_lock.emplace(*c.run ? c.run_options.output_directory : c.calibrate_options.output_directory);
    if (*c.run)
    {
      RunOptions options = c.run_options;
      options.command_line = join_arguments(argc, argv);
      return run_scene(options);
    }
    if (*c.calibrate)
    {
      CalibrateOptions options = c.calibrate_options;
      options.plots = !c.no_plots;
      if (*c.snow_strength)
        options.snow = c.snow;
      options.command_line = join_arguments(argc, argv);
      return coupling::run_calibration(options);
    }
    if (*c.check)
      return check_scene(c.check_file, c.check_threads);
    if (*c.params)
    {
      print_scene_parameters(std::cout, c.format == "json"        ? ParameterFormat::json :
                                        c.format == "description" ? ParameterFormat::description :
                                                                    ParameterFormat::prm,
                             c.snowpack_parameters ? "snowpack" : c.params_kind, c.params_scene, c.every_variant);
      return exit_success;
    }
    if (*c.bench_dem)
      return bench_dem(c.bench_options);
    return exit_success;
  }
} // namespace

int main(int argc, char **argv)
{
  CLI::App app{"anticrack: bonded-particle DEM of snow and rock, calibration and finite elements.\n"
               "Scenes are deal.II parameter files; `anticrack params` lists every entry."};
  app.set_version_flag("--version", source_version());
  app.require_subcommand(1);
  CommandLine command_line;
  for (const auto declare : {declare_run, declare_calibrate, declare_check, declare_params, declare_bench})
    declare(app, command_line);

  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::ParseError &e)
  {
    const int code = app.exit(e);
    return code == 0 ? exit_success : exit_bad_input;
  }

  try
  {
    return run_command(command_line, argc, argv);
  }
  catch (const std::exception &e)
  {
    const ErrorKind &kind = kind_of_error(e);
    print_framed_error(kind.title, e.what());
    return kind.exit_code;
  }
}
