// The load to failure: the body force of every layer, turned to the load angle ψ from the inward
// layer normal, is ramped by a load factor λ from 0 in adaptive Newton steps until equilibrium is lost.
// Two uses, one mechanism:
//  - the FE model of a DEM specimen (docs/fem.md "The DEM specimen repeated"): the weak layer is the
//    specimen between the fixed base and a stiff top layer, the platen, whose weight is the clump force;
//    ψ = 0 compresses, 90° shears and 180° pulls, as the DEM's loading angle; the column ends are free
//    (an open-sided specimen);
//  - a snowpack's safety factor under its own weight (ψ = the slope angle): how many times heavier the
//    column (cut by PST/Cut length, 0: intact) would have to be before it fails.
// Under load control the ramp cannot pass the peak: the failure load is the last converged λ, and the
// first refused step brackets it to `Load factor resolution`.
#include "fem/analysis/outputs.h"
#include "fem/analysis/snowpack_run.h"
#include "fem/solver/quasi_static.h"
#include "util/stop_signals.h"
#include "util/problems.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <any>
#include <cmath>
#include <sstream>
#include <string>

namespace anticrack::fem
{
  using namespace dealii;

  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// The analysis's own entries (Analysis::settings).
    struct LoadToFailureSettings
    {
      double load_angle = 0;          ///< ψ [rad] from the inward layer normal, in [0, π]
      double resolution = 1e-3;       ///< relative width of the failure load's bracket
      double maximum_load_factor = 1e3; ///< the ramp stops here if nothing has failed
    };

    const LoadToFailureSettings &settings_of(const SnowpackScene &scene)
    {
      return std::any_cast<const LoadToFailureSettings &>(scene.analysis.settings);
    }

    /// The weak layer's mean state over all ranks (every weak-layer cell has the same volume on the
    /// structured mesh): layer-plane tractions (normal compression positive, shear along +x) and the
    /// strains that go with them (compaction positive, engineering shear strain).
    struct WeakLayerMeans
    {
      double normal_stress = 0, shear_stress = 0, normal_strain = 0, shear_strain = 0;
    };

    template <int dim>
    WeakLayerMeans weak_layer_means(const SnowpackModel<dim> &model, MPI_Comm comm)
    {
      double sums[5] = {0, 0, 0, 0, 0};
      for (const CellSummary<dim> &cell : model.cell_summaries())
        if (cell.layer == layer_weak)
        {
          sums[0] -= cell.stress[dim - 1][dim - 1];
          sums[1] += cell.stress[0][dim - 1];
          sums[2] -= cell.strain[dim - 1][dim - 1];
          sums[3] += 2 * cell.strain[0][dim - 1];
          sums[4] += 1;
        }
      double total[5];
      Utilities::MPI::sum(ArrayView<const double>(sums, 5), comm, ArrayView<double>(total, 5));
      const double n = std::max(total[4], 1.);
      return {total[0] / n, total[1] / n, total[2] / n, total[3] / n};
    }
  } // namespace

  namespace
  {
    /// Where the ramp stopped: the load factor reached, the last step tried, and why it stopped.
    struct RampEnd
    {
      double load = 0, step = 0;
      bool failed = false;
      std::string failure;
    };

    /// Ramps the load factor from 0 in Newton steps until equilibrium is lost (or the maximum load
    /// factor is reached), one series row per converged step. Steps that soften the weak layer are
    /// held to the resolution: a large step past the peak could otherwise land on the collapsed
    /// layer's lock-up branch, which carries more load again. Such a step is undone (the model's
    /// history from a snapshot) and halved. The layer has failed when the ramp cannot go on by the
    /// resolution, or when its failed elements span the column.
    template <int dim>
    RampEnd ramp_to_failure(const SnowpackScene &scene, const LoadToFailureSettings &settings, SnowpackModel<dim> &model,
                            QuasiStaticSolver<dim> &solver, typename SnowpackModel<dim>::VectorType &u,
                            TimeSeries &series, double normal_per_load, double shear_per_load, MPI_Comm comm)
    {
      RampEnd end;
      double &load = end.load, &step = end.step;
      step = 1. / scene.analysis.gravity_steps;
      double softening = model.weak_layer_softening();
      // Resolved: the step is the resolution's fraction of the load reached (at no load yet, 1e-12 of
      // the first step: the layer carries nothing).
      const double resolution = settings.resolution, first_step = step;
      const auto resolved = [&load, &step, resolution, first_step] {
        return load > 0 ? step <= resolution * load : step <= 1e-12 * first_step;
      };
      typename SnowpackModel<dim>::VectorType before = u;
      while (load < settings.maximum_load_factor)
      {
        stop_if_signalled("load to failure", "load factor " + format_number(load, 6), comm);
        step = std::min(step, settings.maximum_load_factor - load);
        std::stringstream history;
        model.save(history);
        before = u;
        const NewtonResult result = solver.solve(u, load + step);
        const double softened = result.converged ? model.weak_layer_softening() : softening;
        const bool failed_through = result.converged && model.crack_fronts(scene.analysis.failure_fraction).crack_tip >=
                                                          scene.pst.column_length * (1 - 1e-9);
        if (!result.converged || failed_through || (softened > softening + 1e-9 && !resolved()))
        {
          if (result.converged)
          {
            model.load(history);
            u = before;
            u.update_ghost_values();
          }
          if (resolved())
          {
            end.failed = true;
            end.failure = result.converged ? "the weak layer fails through the column at the next step" : result.failure;
            break;
          }
          step /= 2;
          continue;
        }
        load += step;
        softening = softened;
        const WeakLayerMeans m = weak_layer_means(model, comm);
        series.append({load, load * normal_per_load, load * shear_per_load, m.normal_stress, m.shear_stress,
                       m.normal_strain, m.shear_strain, softening, double(result.iterations)});
        if (result.iterations <= 4)
          step *= 2;
      }
      return end;
    }
  } // namespace

  template <int dim>
  Json run_load_to_failure(const SnowpackScene &given, const SnowpackRunOptions &options, MPI_Comm comm)
  {
    const LoadToFailureSettings &settings = settings_of(given);
    // The body force's direction is the model's slope angle (fem/model/snowpack_model.cpp): turned
    // to ψ, g = g (sin ψ, −cos ψ) in the layer's frame.
    SnowpackScene scene = given;
    scene.snowpack.slope_angle = settings.load_angle;
    const StopSignals stop_signals;
    ConditionalStream log = root_log(options.log, comm);
    SnowpackModel<dim> model(scene, comm, options.timer);
    QuasiStaticSolver<dim> solver(model);
    log.line("[fem] load to failure at ", format_number(settings.load_angle * 180 / pi, 4), " deg: ", model.n_cells(),
             " cells, ", model.n_dofs(), " dofs");
    typename SnowpackModel<dim>::VectorType u;
    model.initialize_vector(u);
    model.set_cut(scene.pst.cut_length);
    FieldRecord fields(options.output_directory + "/fields", comm);

    const double weight = scene.snowpack.slab_weight_per_area();
    const double normal_per_load = weight * std::cos(settings.load_angle),
                 shear_per_load = weight * std::sin(settings.load_angle);
    TimeSeries series = series_of({{"load_factor", "1", "lambda: the body forces' multiple of gravity"},
                                   {"slab_normal_traction", "Pa", "lambda x the slab's weight per area along the inward normal"},
                                   {"slab_shear_traction", "Pa", "lambda x the slab's weight per area along +x"},
                                   {"weak_layer_normal_stress", "Pa", "mean layer-normal stress of the weak layer, compression positive"},
                                   {"weak_layer_shear_stress", "Pa", "mean layer-plane shear stress of the weak layer"},
                                   {"weak_layer_normal_strain", "1", "mean layer-normal strain of the weak layer, compaction positive"},
                                   {"weak_layer_shear_strain", "1", "mean engineering shear strain of the weak layer"},
                                   {"weak_layer_softening", "1", "mean (p0_initial - p0) / (p0_initial - p0_floor) of the weak layer"},
                                   {"newton_iterations", "1", "Newton iterations of the step"}});
    const RampEnd end = ramp_to_failure(scene, settings, model, solver, u, series, normal_per_load, shear_per_load, comm);
    const double load = end.load;
    u.update_ghost_values();
    fields.write(model, u, load);
    write_on_root(series, options.output_directory + "/series.h5", "load to failure, one row per converged load step",
                  comm);
    const WeakLayerMeans means = weak_layer_means(model, comm);
    const double sigma = means.normal_stress, tau = means.shear_stress;
    log.line("[fem] ", end.failed ? "failed" : "held", " at load factor ", format_number(load, 6), ": slab traction (",
             format_number(load * normal_per_load, 5), ", ", format_number(load * shear_per_load, 5),
             ") Pa, weak layer mean stress (", format_number(sigma, 5), ", ", format_number(tau, 5), ") Pa");

    Json results;
    results["analysis"] = scene.analysis.type->name;
    results["mesh"] = mesh_json(model, comm);
    results["load_angle_deg"] = settings.load_angle * 180 / pi;
    results["failed"] = end.failed;
    results["failure_load_factor"] = end.failed ? Json(load) : Json(nullptr);
    results["failure_load_factor_bracket"] = end.failed ? Json::array({load, load + end.step}) : Json(nullptr);
    results["failure_reason"] = end.failed ? end.failure
                                           : "equilibrium holds up to Analysis/Load to failure/Maximum load factor = " +
                                               format_number(settings.maximum_load_factor);
    results["largest_load_factor"] = load;
    // The DEM's base stresses, the clump force over the area: the slab's weight per area at the
    // failure load, along and across the layer normal.
    results["slab_traction_at_largest_load_Pa"] = {{"normal", load * normal_per_load}, {"shear", load * shear_per_load}};
    results["weak_layer_mean_stress_at_largest_load_Pa"] = {{"normal", sigma}, {"shear", tau}};
    results["newton_iterations"] = solver.total_iterations();
    return results;
  }

  AnalysisType load_to_failure_analysis()
  {
    return {"load to failure", "load to failure (Newton)",
            "the body forces of every layer, turned to `Load to failure/Load angle` from the inward layer normal, "
            "ramped by a load factor until equilibrium is lost: the FE model of a DEM specimen (the weak layer "
            "between the fixed base and a stiff slab layer, the platen) or a snowpack's safety factor under its own "
            "weight (the load angle the slope angle). The column is first cut by `PST/Cut length`, whose default "
            "(0.3 m) is the saw tests': set 0 for an intact column.",
            /* yielding_weak_layer = */ true, /* time_integration = */ false,
            [](ParameterHandler &prm) {
              prm.enter_subsection("Load to failure");
              prm.declare_entry("Load angle [deg]", "0", Patterns::Double(0, 180),
                                "psi: direction of the body forces from the inward normal of the layers, as the DEM's "
                                "loading angle: 0 compresses the weak layer, 90 shears it along +x, 180 pulls it. "
                                "Snowpack/Slope angle must be 0 or equal to it. Units: deg.");
              prm.declare_entry("Load factor resolution", "1e-3", Patterns::Double(1e-8, 0.1),
                                "The ramp stops when a step of this fraction of the load factor fails: the failure "
                                "load's bracket. Dimensionless.");
              prm.declare_entry("Maximum load factor", "1000", Patterns::Double(0),
                                "The ramp stops here if equilibrium still holds (the result then says so). "
                                "Dimensionless.");
              prm.leave_subsection();
            },
            [](ParameterHandler &prm, SnowpackScene &scene) {
              prm.enter_subsection("Load to failure");
              LoadToFailureSettings settings;
              settings.load_angle = prm.get_double("Load angle [deg]") * pi / 180;
              settings.resolution = prm.get_double("Load factor resolution");
              settings.maximum_load_factor = prm.get_double("Maximum load factor");
              scene.analysis.settings = settings;
              prm.leave_subsection();
            },
            [](const SnowpackScene &scene, Problems &problems) {
              const LoadToFailureSettings &settings = settings_of(scene);
              const double slope = scene.snowpack.slope_angle;
              if (slope != 0 && std::abs(slope - settings.load_angle) > 1e-12)
                problems.add("Snowpack/Slope angle [deg]",
                             "must be 0 or equal to Analysis/Load to failure/Load angle [deg] (" +
                               format_number(settings.load_angle * 180 / pi) + "), which gives the direction of the load "
                               "(is " + format_number(slope * 180 / pi) + ")");
              if (!(settings.maximum_load_factor > 0))
                problems.add("Analysis/Load to failure/Maximum load factor", "must be > 0");
            },
            &run_load_to_failure<2>, &run_load_to_failure<3>};
  }
} // namespace anticrack::fem
