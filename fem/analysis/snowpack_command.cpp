#include "fem/analysis/snowpack_command.h"

#include "fem/analysis/snowpack_run.h"
#include "fem/model/snowpack_model.h"
#include "fem/scene/snowpack_scene.h"
#include "util/console.h"
#include "util/input_error.h"
#include "util/named_rows.h"
#include "util/phase_timer.h"
#include "util/run_options.h"
#include "util/run_summary.h"
#include "util/sha256.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/multithread_info.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <filesystem>
#include <iostream>

namespace anticrack::fem
{
  namespace fs = std::filesystem;

  namespace
  {
    /// Output files of a snowpack run (an earlier run's are refused without --overwrite).
    const std::vector<std::string> run_files{"summary.json", "series.h5",        "energy_release_rate.h5",
                                             "fields",       "checkpoint.json", "checkpoint",
                                             "saw",          "fixed_cuts"};
  } // namespace

  namespace
  {
    /// The mesh a run would build: its cells and degrees of freedom, and for an analysis that
    /// marches in time the first explicit step (CFL safety x the stable step of the unloaded
    /// snowpack, the lock-up of a collapsed layer shortens it later).
    template <int dim>
    void describe_mesh(const SnowpackScene &scene, MPI_Comm comm)
    {
      SnowpackModel<dim> model(scene, comm);
      ConditionalStream out(&std::cout, dealii::Utilities::MPI::this_mpi_process(comm) == 0);
      out << "  mesh: " << model.n_cells() << " cells, " << model.n_dofs() << " degrees of freedom (Q"
          << scene.mesh.polynomial_degree << ", " << model.n_columns() << " columns of " << scene.mesh.element_length
          << " m)\n";
      if (!scene.analysis.type->time_integration)
        return;
      typename SnowpackModel<dim>::VectorType u, force;
      model.initialize_vector(u);
      model.initialize_vector(force);
      const double stable = model.evaluate(u, force, typename SnowpackModel<dim>::Request());
      out << "  explicit time step: " << scene.analysis.cfl_safety * stable << " s (CFL safety "
          << scene.analysis.cfl_safety << " x the stable step " << stable << " s at rest), "
          << static_cast<unsigned long>(std::ceil(scene.analysis.end_time / (scene.analysis.cfl_safety * stable)))
          << " steps to the end time at least\n";
    }
  } // namespace

  void check_snowpack_scene(const std::string &scene_file)
  {
    const fem::SnowpackScene scene = fem::read_snowpack_scene(scene_file);
    std::cout << "snowpack scene " << scene_file << ": " << scene.analysis.type->title << ", "
              << scene.mesh.dimension << "D, column " << scene.pst.column_length << " m, slab "
              << scene.snowpack.slab_thickness() << " m in " << scene.snowpack.slab_layers.size()
              << " layer(s), weak layer " << scene.snowpack.weak_layer.thickness << " m ("
              << scene.mesh.weak_layer_elements << " elements), slope "
              << scene.snowpack.slope_angle * 180 / 3.14159265358979323846 << " deg\n";
    // Building the mesh needs MPI (p4est).
    std::optional<dealii::Utilities::MPI::MPI_InitFinalize> mpi;
    start_fe_mpi(mpi);
    if (scene.mesh.dimension == 2)
      describe_mesh<2>(scene, MPI_COMM_WORLD);
    else
      describe_mesh<3>(scene, MPI_COMM_WORLD);
  }

  void start_fe_mpi(std::optional<dealii::Utilities::MPI::MPI_InitFinalize> &mpi)
  {
    // One thread per process, also where MPI was started before (under mpirun, by the application,
    // which then skipped the limit of the MPI_InitFinalize below): the FE's parallelism is its ranks
    // and the pipeline's worker processes, and deal.II's task-parallel kernels would otherwise put
    // a thread per core in every rank.
    dealii::MultithreadInfo::set_thread_limit(1);
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (initialised)
      return;
    // deal.II keeps argc and argv (PETSc reads them): they must outlive the session.
    static int argc = 1;
    static char name[] = "anticrack";
    static char *argv_storage[] = {name, nullptr};
    static char **argv = argv_storage;
    mpi.emplace(argc, argv, 1);
  }

  int run_snowpack_scene(const RunOptions &options)
  {
    std::optional<dealii::Utilities::MPI::MPI_InitFinalize> mpi;
    start_fe_mpi(mpi);
    return run_snowpack_scene_in_mpi(options);
  }

  namespace
  {
    /// Everything that can be wrong with the output directory, found before it is touched: a path
    /// that is not a directory, a resume with nothing to resume from, an earlier run without
    /// --overwrite. Then (rank 0) the directory made and an earlier run's outputs removed.
    void prepare_output_directory(const fem::SnowpackScene &scene, const RunOptions &options, MPI_Comm comm)
    {
      const fs::path dir = options.output_directory;
      std::error_code error;
      if (fs::exists(dir, error) && !fs::is_directory(dir, error))
        throw InputError("The output path <" + dir.string() + "> exists and is not a directory.");
      if (options.resume)
      {
        if (!scene.analysis.type->time_integration)
          throw InputError("--resume: Analysis/Type = `" + std::string(scene.analysis.type->name) +
                           "` writes no checkpoints (only analyses that march in time do: " + quoted_names(analysis_types(), [](const AnalysisType &t) { return t.time_integration; }) + ")");
        // A critical-cut search resumes from its completed runs (fem/analysis/critical_cut_search.h).
        const bool search = scene.pst.saw == fem::SawTest::Saw::bisection || scene.pst.saw == fem::SawTest::Saw::practice;
        if (!fs::exists(dir / "checkpoint.json", error) &&
            !(search && (fs::exists(dir / "saw", error) || fs::exists(dir / "fixed_cuts", error))))
          throw InputError("Cannot resume: <" + dir.string() + "> has no checkpoint.json" +
                           (search ? " and no saw/ or fixed_cuts/ folder" : "") +
                           " (set Output/Checkpoint interval, or run without --resume).");
      }
      else
      {
        for (const std::string &file : run_files)
          if (fs::exists(dir / file, error) && !options.overwrite)
            throw InputError("The output directory <" + dir.string() + "> already holds a run (" + file +
                             "). Use --resume to continue it, --overwrite to replace its outputs, or another "
                             "directory.");
        if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
        {
          fs::create_directories(dir);
          for (const std::string &file : run_files)
            fs::remove_all(dir / file, error);
        }
      }
      MPI_Barrier(comm);
    }

    /// summary.json's record of the scene: its file and hash, the material files', the failed weak
    /// layer's friction and where it comes from (the DEM's friction tests or the scene), the profile.
    Json scene_record(const fem::SnowpackScene &scene, const std::string &scene_file)
    {
      Json scene_json;
      scene_json["file"] = scene_file;
      scene_json["file_sha256"] = util::sha256_of_file(scene_file);
      for (const fem::Layer *layer : {&scene.snowpack.weak_layer, &scene.snowpack.substratum})
        if (!layer->material_file.empty())
          scene_json["material_files"][layer->label] = {{"file", layer->material_file},
                                                        {"sha256", util::sha256_of_file(layer->material_file)}};
      if (const fem::Layer &weak = scene.snowpack.weak_layer; !std::isnan(weak.friction_coefficient))
        scene_json["weak_layer_friction"] = {
          {"friction_coefficient", weak.friction_coefficient},
          {"source", weak.friction_from_material_file ? "material file (DEM friction tests)" : "scene"}};
      if (!scene.profile_record.is_null())
        scene_json["profile"] = scene.profile_record; // each layer's values and their sources, the observed PST
      return scene_json;
    }

    /// Runs the scene's analysis into `summary` (results and status, or the interruption or the
    /// numerical failure with where and when); returns the exit code.
    int run_analysis(const fem::SnowpackScene &scene, const RunOptions &options, PhaseTimer &timer, Json &summary,
                     MPI_Comm comm)
    {
      const bool root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
      fem::SnowpackRunOptions run;
      run.output_directory = options.output_directory;
      run.log = options.quiet ? nullptr : &std::cout;
      run.resume = options.resume;
      run.timer = &timer;
      try
      {
        summary["results"] = fem::run_snowpack(scene, run, comm);
        summary["status"] = "completed";
        return exit_success;
      }
      catch (const fem::RunInterrupted &e)
      {
        summary["status"] = "interrupted";
        summary["message"] = e.what();
        ConditionalStream(&std::cerr, root) << "anticrack: " << e.what() << "\n";
        return exit_interrupted;
      }
      catch (const fem::RunStopped &e)
      {
        summary["status"] = e.status();
        Json failure = e.details();
        failure["message"] = e.what();
        summary["failure"] = failure;
        ConditionalStream(&std::cerr, root) << "anticrack: " << e.heading() << e.what() << "\n";
        return exit_numerical_failure;
      }
    }
  } // namespace

  int run_snowpack_scene_in_mpi(const RunOptions &options)
  {
    const MPI_Comm comm = MPI_COMM_WORLD;
    // Everything that can be wrong with the input is found before the directory is touched.
    const fem::SnowpackScene scene = fem::read_snowpack_scene(options.scene_file);
    prepare_output_directory(scene, options, comm);

    Json summary;
    summary["command"] = options.command_line;
    summary["scene"] = scene_record(scene, options.scene_file);
    summary["versions"] = version_info();
    PhaseTimer timer;
    const auto start = std::chrono::steady_clock::now();
    const int code = run_analysis(scene, options, timer, summary, comm);
    // Where the time went (rank 0's; the ranks work in lock step).
    summary["timing"] = {{"wall_s", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()},
                         {"ranks", dealii::Utilities::MPI::n_mpi_processes(comm)},
                         {"phases", timer.to_json()}};
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      write_json_atomically((fs::path(options.output_directory) / "summary.json").string(), summary);
    return code;
  }
} // namespace anticrack::fem
