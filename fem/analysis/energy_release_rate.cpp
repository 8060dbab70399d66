// The energy release rate analysis: G(a) of a saw cut in an elastic snowpack, the cut length at
// which G reaches G_c, energy_release_rate.h5 and the fields of the longest cut.
#include "fem/analysis/outputs.h"
#include "fem/analysis/snowpack_run.h"
#include "fem/solver/quasi_static.h"
#include "util/stop_signals.h"
#include "util/format.h"
#include "util/problems.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <cmath>
#include <limits>
#include <optional>

namespace anticrack::fem
{
  using namespace dealii;

  namespace
  {
    /// G(a) of a saw cut: the cut lengths, Π per unit width at each, and G = −ΔΠ/Δa at the
    /// midpoints of consecutive cuts with the beam on an elastic foundation's G beside it.
    struct ReleaseRateCurve
    {
      std::vector<double> cuts, potentials;
      std::vector<double> midpoints, release_rates, beam_rates;

      /// The cut length at which G reaches `fracture_energy` (linear between midpoints), if any.
      [[nodiscard]] std::optional<double> cut_length_at(double fracture_energy) const
      {
        for (unsigned int k = 0; k + 1 < midpoints.size(); ++k)
          if (release_rates[k] < fracture_energy && release_rates[k + 1] >= fracture_energy)
            return midpoints[k] + (fracture_energy - release_rates[k]) / (release_rates[k + 1] - release_rates[k]) *
                                    (midpoints[k + 1] - midpoints[k]);
        return std::nullopt;
      }
    };

    /// Π(a) = ½ u·K u − f·u = −½ f·u at equilibrium (linear) for the cuts 0, dx, ..., n dx, and G
    /// from it; `u` is left at the longest cut's solution.
    template <int dim>
    ReleaseRateCurve release_rate_curve(const SnowpackScene &scene, SnowpackModel<dim> &model,
                                        QuasiStaticSolver<dim> &solver, typename SnowpackModel<dim>::VectorType &u,
                                        MPI_Comm comm)
    {
      const double dx = scene.pst.column_length / model.n_columns();
      const unsigned int n_cuts = (unsigned int)std::floor(scene.pst.cut_length / dx + 1e-9);
      const double width = result_width<dim>(scene);
      ReleaseRateCurve curve;
      for (unsigned int k = 0; k <= n_cuts; ++k)
      {
        if (k > 0)
          stop_if_signalled("energy release rate", "cut " + format_number((k - 1) * dx, 4) + " m", comm);
        model.set_cut(k * dx);
        u = 0;
        const NewtonResult result = solver.solve(u, 1.0);
        if (!result.converged)
          throw NumericalFailure("energy release rate: the elastic solve at cut length " + format_number(k * dx, 4) +
                                   " m failed: " + result.failure,
                                 {{"what", "elastic solve"},
                                  {"where", result.failure_site},
                                  {"when", {{"phase", "energy release rate"}, {"cut_length_m", k * dx}}}});
        curve.cuts.push_back(k * dx);
        curve.potentials.push_back(-0.5 * (model.gravity_force() * u) / width);
      }
      const auto beam = beam_model(scene.snowpack);
      for (unsigned int k = 0; k + 1 < curve.cuts.size(); ++k)
      {
        curve.midpoints.push_back(0.5 * (curve.cuts[k] + curve.cuts[k + 1]));
        curve.release_rates.push_back(-(curve.potentials[k + 1] - curve.potentials[k]) / dx);
        curve.beam_rates.push_back(beam ? closed_forms::energy_release_rate(*beam, curve.midpoints.back())
                                        : std::numeric_limits<double>::quiet_NaN());
      }
      return curve;
    }

    /// The critical cut's interval from G_c's (the material file's): G(a) of the elastic snowpack
    /// does not depend on G_c, so G_c's interval maps exactly, through this run's G(a)
    /// (increasing), onto an interval of the critical cut: no further runs. Only G_c's uncertainty
    /// is carried here; the weak layer's E, which moves G(a), needs another run (the pipeline's
    /// uncertainty stage does it and combines the two, coupling/pipeline_uncertainty.h).
    Json critical_cut_interval(const SnowpackScene &scene, const ReleaseRateCurve &curve)
    {
      const MaterialInterval &G_c_interval = scene.analysis.fracture_energy_interval;
      const std::optional<double> lower = curve.cut_length_at(G_c_interval.lower),
                                  upper = curve.cut_length_at(G_c_interval.upper);
      Json interval;
      interval["fracture_energy_J_per_m2"] = {G_c_interval.lower, G_c_interval.upper};
      interval["confidence"] = scene.snowpack.weak_layer.confidence;
      interval["critical_cut_length_m"] = {lower ? Json(*lower) : Json(nullptr), upper ? Json(*upper) : Json(nullptr)};
      interval["carries"] = "the interval of the material file's fracture energy density (over the DEM realizations) "
                            "through this run's G(a), at this run's E (E moves G(a): another run, which the "
                            "pipeline's uncertainty stage makes)";
      if (!lower)
        interval["lower_note"] = G_c_interval.lower > 0 ? "below the first midpoint (shorter than one element)"
                                                        : "G_c's lower bound is not positive: no lower bound of the cut";
      if (!upper)
        interval["upper_note"] = "beyond the longest cut " + format_number(curve.cuts.back(), 4) + " m";
      return interval;
    }

    /// What the analysis answers: G(a), the critical cut at G_c with its interval or why there is
    /// none, and the beam's characteristic length.
    template <int dim>
    Json release_rate_results(const SnowpackScene &scene, const SnowpackModel<dim> &model,
                              const ReleaseRateCurve &curve, MPI_Comm comm)
    {
      const double G_c = scene.analysis.fracture_energy;
      const std::optional<double> critical = curve.cut_length_at(G_c);
      Json results;
      results["analysis"] = scene.analysis.type->name;
      results["mesh"] = mesh_json(model, comm);
      results["fracture_energy_J_per_m2"] = G_c;
      results["fracture_energy_source"] =
        scene.analysis.fracture_energy_from_material_file ?
          "the weak layer's material file: fracture energy density x thickness" :
          "Analysis/Fracture energy [J/m^2]";
      results["critical_cut_length_m"] = critical ? Json(*critical) : Json(nullptr);
      if (!critical && !curve.release_rates.empty() && curve.release_rates.front() >= G_c)
        results["critical_cut_length_note"] = "G = " + format_number(curve.release_rates.front(), 4) +
                                               " J/m^2 exceeds G_c already at the first midpoint, a = " +
                                               format_number(curve.midpoints.front(), 4) +
                                               " m: the critical cut is shorter than one element (refine the mesh)";
      else if (!critical)
        results["critical_cut_length_note"] =
          "G stays below G_c up to the longest cut " + format_number(curve.cuts.back(), 4) + " m";
      const MaterialInterval &G_c_interval = scene.analysis.fracture_energy_interval;
      if (critical && std::isfinite(G_c_interval.lower) && std::isfinite(G_c_interval.upper))
        results["critical_cut_length_interval"] = critical_cut_interval(scene, curve);
      Json g;
      g["cut_length_m"] = curve.midpoints;
      g["fe_J_per_m2"] = curve.release_rates;
      if (const auto beam = beam_model(scene.snowpack))
      {
        g["beam_on_elastic_foundation_J_per_m2"] = curve.beam_rates;
        results["beam_characteristic_length_m"] = closed_forms::characteristic_length(*beam);
      }
      results["energy_release_rate"] = g;
      return results;
    }
  } // namespace

  // Energy release rate of a saw cut in an elastic snowpack: Π(a) = ½ u·K u − f·u = −½ f·u at
  // equilibrium (linear), G at the midpoints of consecutive cuts = −ΔΠ/Δa per unit width.
  template <int dim>
  Json run_energy_release_rate(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
  {
    const StopSignals stop_signals;
    ConditionalStream log = root_log(options.log, comm);
    SnowpackModel<dim> model(scene, comm, options.timer);
    QuasiStaticSolver<dim> solver(model);
    log.line("[fem] energy release rate: ", model.n_cells(), " cells, ", model.n_dofs(), " dofs, ",
             Utilities::MPI::n_mpi_processes(comm), " rank(s)");
    typename SnowpackModel<dim>::VectorType u;
    model.initialize_vector(u);
    const ReleaseRateCurve curve = release_rate_curve(scene, model, solver, u, comm);

    // Columns of different lengths: Π at the cuts, G at their midpoints.
    TimeSeries table({{"cut_length", "m", "cut length a", false, curve.cuts},
                      {"potential_energy", "J/m", "total potential energy per unit width at each cut", false, curve.potentials},
                      {"midpoint_cut_length", "m", "midpoints of consecutive cuts, where G is given", false, curve.midpoints},
                      {"energy_release_rate", "J/m^2", "G = -dPi/da of the FE model", false, curve.release_rates},
                      {"energy_release_rate_beam", "J/m^2",
                       "beam on an elastic foundation, fem/closed_forms.h (NaN: several slab layers)", false, curve.beam_rates}});
    write_on_root(table, options.output_directory + "/energy_release_rate.h5", "energy release rate of a saw cut",
                  comm);
    FieldRecord fields(options.output_directory + "/fields", comm);
    u.update_ghost_values();
    fields.write(model, u, curve.cuts.back());

    Json results = release_rate_results(scene, model, curve, comm);
    results["newton_iterations"] = solver.total_iterations();
    const std::optional<double> critical = curve.cut_length_at(scene.analysis.fracture_energy);
    log.line("[fem] G(", format_number(curve.midpoints.front(), 4), " m) = ", format_number(curve.release_rates.front(), 4),
             " J/m^2 ... G(", format_number(curve.midpoints.back(), 4), " m) = ",
             format_number(curve.release_rates.back(), 4), " J/m^2; a(G_c = ", scene.analysis.fracture_energy, ") = ",
             critical ? format_number(*critical, 4) + " m" : std::string("beyond the longest cut"));
    return results;
  }

  AnalysisType energy_release_rate_analysis()
  {
    return {
      "energy release rate", "energy release rate (elastic)",
      "elastic snowpack, G(a) = -dPi/da over every cut length up to `PST/Cut length`, and the cut length at "
      "which G reaches the weak layer's fracture energy.",
      /* yielding_weak_layer = */ false, /* time_integration = */ false,
      [](ParameterHandler &prm) {
        prm.declare_entry("Fracture energy [J/m^2]", "0", Patterns::Double(0),
                          "G_c: fracture energy of the weak layer; the analysis reports the cut length at which G "
                          "reaches it (energy release rate analysis). 0: from the weak layer's material file, "
                          "its Material/Collapse/Fracture energy density [J/m^3] (the DEM compaction tests') "
                          "times Snowpack/Weak layer/Thickness [m]; one of the two must give it. Units: J/m^2.");
      },
      [](ParameterHandler &prm, SnowpackScene &scene) {
        const Layer &weak = scene.snowpack.weak_layer; // read before the analysis
        const double given = prm.get_double("Fracture energy [J/m^2]");
        scene.analysis.fracture_energy_from_material_file = !(given > 0) && weak.fracture_energy_density > 0;
        scene.analysis.fracture_energy_entry = given;
        scene.analysis.fracture_energy =
          scene.analysis.fracture_energy_from_material_file ? weak.fracture_energy_density * weak.thickness : given;
        if (scene.analysis.fracture_energy_from_material_file)
          scene.analysis.fracture_energy_interval = {weak.fracture_energy_density_interval.lower * weak.thickness,
                                                     weak.fracture_energy_density_interval.upper * weak.thickness};
      },
      [](const SnowpackScene &scene, Problems &problems) {
        // Π(a) = −½ f·u holds for a linear snowpack only, and G needs two cuts for a difference.
        const Snowpack &s = scene.snowpack;
        auto elastic = [&](const Layer &layer, const std::string &section) {
          if (layer.model != Layer::Model::elastic)
            problems.add(section + "/Model", "must be `elastic` for the energy release rate analysis");
        };
        for (unsigned int k = 0; k < s.slab_layers.size(); ++k)
          elastic(s.slab_layers[k], "Snowpack/" + slab_layer_section(k));
        elastic(s.weak_layer, "Snowpack/Weak layer");
        elastic(s.substratum, "Snowpack/Substratum");
        if (scene.analysis.fracture_energy_entry > 0 && s.weak_layer.fracture_energy_density > 0)
          problems.add("Analysis/Fracture energy [J/m^2]",
                       "is given (" + format_number(scene.analysis.fracture_energy_entry) + ") and so is the weak layer's material file's fracture "
                       "energy density (" + format_number(s.weak_layer.fracture_energy_density) +
                       " J/m^3, Material/Collapse): give it once (0 here takes the file's)");
        else if (!(scene.analysis.fracture_energy > 0))
          problems.add("Analysis/Fracture energy [J/m^2]",
                       "must be > 0, or 0 with a weak-layer material file whose Material/Collapse gives the fracture "
                       "energy density (the DEM compaction tests'; allowed: > 0 J/m^2)");
        const double dx = scene.mesh.element_length, a = scene.pst.cut_length;
        if (!(a >= 2 * dx))
          problems.add("PST/Cut length [m]", "must cover at least two element lengths, " + format_number(2 * dx) +
                                               " m, for G(a) (is " + format_number(a) + ")");
      },
      &run_energy_release_rate<2>, &run_energy_release_rate<3>};
  }
} // namespace anticrack::fem
