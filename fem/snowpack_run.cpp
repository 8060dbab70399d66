// The three analyses of a snowpack scene (see the header) and what they write.
#include "fem/snowpack_run.h"

#include "fem/closed_forms.h"
#include "fem/explicit_dynamics.h"
#include "fem/quasi_static.h"
#include "fem/snowpack_model.h"
#include "util/hdf5_file.h"

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/mpi.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>

namespace anticrack::fem
{
  using namespace dealii;

  namespace
  {
    /// Columns of a time series, written by rank 0 as one HDF5 dataset per column with its unit.
    class TimeSeries
    {
    public:
      struct Column
      {
        std::string name, unit, description;
        std::vector<double> values;
      };

      explicit TimeSeries(std::vector<Column> columns) : columns_(std::move(columns)) {}

      void add_row(const std::vector<double> &row)
      {
        for (unsigned int k = 0; k < columns_.size(); ++k)
          columns_[k].values.push_back(row[k]);
      }

      const std::vector<double> &column(const std::string &name) const
      {
        for (const Column &c : columns_)
          if (c.name == name)
            return c.values;
        throw std::logic_error("no time-series column " + name);
      }

      /// Writes file (via file.tmp and a rename, so a reader never sees half a file) on rank 0.
      void write(const std::string &file, const std::string &description, MPI_Comm communicator) const
      {
        if (Utilities::MPI::this_mpi_process(communicator) != 0)
          return;
        const std::string temporary = file + ".tmp";
        {
          hdf5::Handle h5 = hdf5::create_file(temporary);
          hdf5::write_string_attribute(h5.id, "description", description);
          for (const Column &c : columns_)
            hdf5::write_doubles(h5.id, c.name, c.values, c.unit, c.description);
        }
        std::filesystem::rename(temporary, file);
      }

    private:
      std::vector<Column> columns_;
    };

    /// The .pvd record of the field outputs, rewritten after every output by rank 0.
    class FieldRecord
    {
    public:
      FieldRecord(std::string directory, MPI_Comm communicator)
        : directory_(std::move(directory)), communicator_(communicator)
      {
        if (Utilities::MPI::this_mpi_process(communicator) == 0)
          std::filesystem::create_directories(directory_);
        MPI_Barrier(communicator);
      }

      template <int dim>
      void write(const SnowpackModel<dim> &model, const typename SnowpackModel<dim>::VectorType &u, double time)
      {
        const std::string pvtu = model.write_fields(u, directory_, "fields", entries_.size());
        entries_.emplace_back(time, pvtu);
        if (Utilities::MPI::this_mpi_process(communicator_) == 0)
        {
          std::ofstream out(directory_ + "/fields.pvd");
          DataOutBase::write_pvd_record(out, entries_);
        }
      }

    private:
      std::string directory_;
      MPI_Comm communicator_;
      std::vector<std::pair<double, std::string>> entries_;
    };

    class Log
    {
    public:
      Log(std::ostream *out, MPI_Comm communicator)
        : out_(Utilities::MPI::this_mpi_process(communicator) == 0 ? out : nullptr)
      {}
      template <typename... T>
      void line(const T &...parts)
      {
        if (!out_)
          return;
        (*out_ << ... << parts) << std::endl;
      }

    private:
      std::ostream *out_;
    };

    std::string format(double value, int precision = 4)
    {
      std::ostringstream out;
      out << std::setprecision(precision) << value;
      return out.str();
    }

    /// Width the 2D results are per (1 m, plane strain) or the 3D column width.
    template <int dim>
    double result_width(const SnowpackScene &scene)
    {
      return dim == 2 ? 1. : scene.pst.column_width;
    }

    Json energies_json(const Energies &e)
    {
      Json j;
      j["elastic_J"] = e.elastic;
      j["kinetic_J"] = e.kinetic;
      j["dissipated_plastic_J"] = e.dissipated;
      j["dissipated_viscous_J"] = e.viscous;
      j["removed_by_saw_J"] = e.removed_by_saw;
      j["external_work_J"] = e.external_work;
      const double stored = e.elastic + e.kinetic + e.dissipated + e.viscous + e.removed_by_saw;
      j["balance_error_relative"] =
        std::abs(e.external_work - stored) / std::max({std::abs(e.external_work), std::abs(e.elastic), 1e-300});
      return j;
    }

    template <int dim>
    Json mesh_json(const SnowpackModel<dim> &model, MPI_Comm communicator)
    {
      Json j;
      j["dimension"] = dim;
      j["cells"] = model.n_cells();
      j["dofs"] = model.n_dofs();
      j["columns"] = model.n_columns();
      j["element_length_m"] = model.scene().pst.column_length / model.n_columns();
      j["weak_layer_elements"] = model.scene().mesh.weak_layer_elements;
      j["ranks"] = Utilities::MPI::n_mpi_processes(communicator);
      return j;
    }

    /// The beam on an elastic foundation of fem/closed_forms.h for a snowpack with one slab layer
    /// (several layers have no single E; none is returned then).
    std::optional<closed_forms::SlabOnFoundation> beam_model(const Snowpack &s)
    {
      if (s.slab_layers.size() != 1)
        return std::nullopt;
      closed_forms::SlabOnFoundation beam;
      const ContinuumMaterial &slab = s.slab_layers[0].material;
      beam.slab_thickness = s.slab_layers[0].thickness;
      beam.slab_youngs_modulus = slab.youngs_modulus;
      beam.slab_poisson_ratio = slab.poisson_ratio;
      beam.slab_density = slab.density;
      beam.weak_layer_thickness = s.weak_layer.thickness;
      beam.weak_layer_youngs_modulus = s.weak_layer.material.youngs_modulus;
      beam.weak_layer_poisson_ratio = s.weak_layer.material.poisson_ratio;
      beam.gravity = s.gravity;
      beam.slope_angle = s.slope_angle;
      return beam;
    }

    // ---------------------------------------------------------------------------------------
    // Energy release rate of a saw cut in an elastic snowpack: Π(a) = ½ u·K u − f·u = −½ f·u at
    // equilibrium (linear), G at the midpoints of consecutive cuts = −ΔΠ/Δa per unit width.
    template <int dim>
    Json run_energy_release_rate(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
    {
      Log log(options.log, comm);
      SnowpackModel<dim> model(scene, comm);
      QuasiStaticSolver<dim> solver(model);
      log.line("[fem] energy release rate: ", model.n_cells(), " cells, ", model.n_dofs(), " dofs, ",
               Utilities::MPI::n_mpi_processes(comm), " rank(s)");
      const double dx = scene.pst.column_length / model.n_columns();
      const unsigned int n_cuts = (unsigned int)std::floor(scene.pst.cut_length / dx + 1e-9);
      const double width = result_width<dim>(scene);
      typename SnowpackModel<dim>::VectorType u;
      model.initialize_vector(u);
      std::vector<double> cuts, potentials;
      for (unsigned int k = 0; k <= n_cuts; ++k)
      {
        model.set_cut(k * dx);
        u = 0;
        const NewtonResult result = solver.solve(u, 1.0);
        if (!result.converged)
          throw NumericalFailure("energy release rate: the elastic solve at cut length " + format(k * dx) +
                                 " m failed: " + result.failure);
        cuts.push_back(k * dx);
        potentials.push_back(-0.5 * (model.gravity_force() * u) / width);
      }
      std::vector<double> midpoints, release_rates, beam_rates;
      const auto beam = beam_model(scene.snowpack);
      for (unsigned int k = 0; k + 1 < cuts.size(); ++k)
      {
        midpoints.push_back(0.5 * (cuts[k] + cuts[k + 1]));
        release_rates.push_back(-(potentials[k + 1] - potentials[k]) / dx);
        beam_rates.push_back(beam ? closed_forms::energy_release_rate(*beam, midpoints.back())
                                  : std::numeric_limits<double>::quiet_NaN());
      }

      // The cut length at which G reaches G_c (linear interpolation between midpoints).
      const double G_c = scene.analysis.fracture_energy;
      std::optional<double> critical;
      for (unsigned int k = 0; k + 1 < midpoints.size() && !critical; ++k)
        if (release_rates[k] < G_c && release_rates[k + 1] >= G_c)
          critical = midpoints[k] + (G_c - release_rates[k]) / (release_rates[k + 1] - release_rates[k]) *
                                      (midpoints[k + 1] - midpoints[k]);

      // Columns of different lengths: Π at the cuts, G at their midpoints.
      TimeSeries table({{"cut_length", "m", "cut length a", cuts},
                        {"potential_energy", "J/m", "total potential energy per unit width at each cut", potentials},
                        {"midpoint_cut_length", "m", "midpoints of consecutive cuts, where G is given", midpoints},
                        {"energy_release_rate", "J/m^2", "G = -dPi/da of the FE model", release_rates},
                        {"energy_release_rate_beam", "J/m^2",
                         "beam on an elastic foundation, fem/closed_forms.h (NaN: several slab layers)", beam_rates}});
      table.write(options.output_directory + "/energy_release_rate.h5", "energy release rate of a saw cut", comm);
      FieldRecord fields(options.output_directory + "/fields", comm);
      u.update_ghost_values();
      fields.write(model, u, cuts.back());

      Json results;
      results["analysis"] = "energy release rate";
      results["mesh"] = mesh_json(model, comm);
      results["fracture_energy_J_per_m2"] = G_c;
      results["critical_cut_length_m"] = critical ? Json(*critical) : Json(nullptr);
      if (!critical)
        results["critical_cut_length_note"] = "G stays below G_c up to the longest cut " + format(cuts.back()) + " m";
      Json g;
      g["cut_length_m"] = midpoints;
      g["fe_J_per_m2"] = release_rates;
      if (beam)
      {
        g["beam_on_elastic_foundation_J_per_m2"] = beam_rates;
        results["beam_characteristic_length_m"] = closed_forms::characteristic_length(*beam);
      }
      results["energy_release_rate"] = g;
      results["newton_iterations"] = solver.total_iterations();
      log.line("[fem] G(", format(midpoints.front()), " m) = ", format(release_rates.front()), " J/m^2 ... G(",
               format(midpoints.back()), " m) = ", format(release_rates.back()), " J/m^2; a(G_c = ", G_c,
               ") = ", critical ? format(*critical) + " m" : std::string("beyond the longest cut"));
      return results;
    }

    /// Gravity equilibrium of the uncut column (shared by the quasi-static and dynamic PST).
    template <int dim>
    void gravity_equilibrium(SnowpackModel<dim> &model, QuasiStaticSolver<dim> &solver,
                             typename SnowpackModel<dim>::VectorType &u, Log &log)
    {
      const auto start = std::chrono::steady_clock::now();
      solver.apply_gravity(u, model.scene().analysis.gravity_steps, [&](double load, const NewtonResult &r) {
        log.line("[fem] gravity ", format(100 * load, 3), " %: ", r.iterations, " Newton iterations, |r|/|f| = ",
                 format(r.relative_residual, 2));
      });
      log.line("[fem] gravity equilibrium in ",
               format(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 3), " s");
    }

    double self_propagation_lead(const SnowpackScene &scene)
    {
      return scene.analysis.self_propagation_lead > 0 ? scene.analysis.self_propagation_lead
                                                      : scene.snowpack.slab_thickness();
    }

    // ---------------------------------------------------------------------------------------
    // Quasi-static PST: saw steps with Newton until equilibrium is lost or the crack leads the saw.
    template <int dim>
    Json run_quasi_static_pst(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
    {
      Log log(options.log, comm);
      SnowpackModel<dim> model(scene, comm);
      QuasiStaticSolver<dim> solver(model);
      log.line("[fem] quasi-static PST: ", model.n_cells(), " cells, ", model.n_dofs(), " dofs");
      typename SnowpackModel<dim>::VectorType u;
      model.initialize_vector(u);
      gravity_equilibrium(model, solver, u, log);
      FieldRecord fields(options.output_directory + "/fields", comm);
      fields.write(model, u, 0);

      const double dx = scene.pst.column_length / model.n_columns();
      const double nominal_step = scene.analysis.saw_step > 0 ? scene.analysis.saw_step : dx;
      const double lead = self_propagation_lead(scene);
      TimeSeries series({{"cut_length", "m", "saw cut length a", {}},
                         {"crack_tip", "m", "far end of the failed weak layer from the cut end", {}},
                         {"touchdown_front", "m", "far end of the locked-up weak layer from the cut end", {}},
                         {"elastic_energy", "J", "stored elastic energy", {}},
                         {"dissipated_energy", "J", "plastic dissipation", {}},
                         {"newton_iterations", "1", "Newton iterations of the step", {}}});
      double cut = 0, step = nominal_step;
      std::optional<double> critical;
      std::string reason;
      // External work: the ramp's is what it stored and dissipated (quasi-static), then the
      // constant weight's f_g · Δu over the saw steps.
      const Energies after_gravity = model.energies();
      double external_work = after_gravity.elastic + after_gravity.dissipated;
      typename SnowpackModel<dim>::VectorType previous = u;
      while (cut < scene.pst.cut_length - 1e-12)
      {
        const double next = std::min(cut + step, scene.pst.cut_length);
        model.set_cut(next);
        const NewtonResult result = solver.solve(u, 1.0);
        if (!result.converged)
        {
          model.set_cut(cut);
          if (step < nominal_step / 64)
          {
            critical = next;
            reason = "no equilibrium with the next cut increment: " + result.failure;
            break;
          }
          step /= 2;
          continue;
        }
        cut = next;
        previous.sadd(-1., 1., u);
        external_work += model.gravity_force() * previous;
        previous = u;
        const CrackFronts fronts = model.crack_fronts(scene.analysis.failure_fraction);
        const Energies e = model.energies();
        series.add_row({cut, fronts.crack_tip, fronts.touchdown, e.elastic, e.dissipated, (double)result.iterations});
        log.line("[fem] cut ", format(cut), " m: crack tip ", format(fronts.crack_tip), " m, ", result.iterations,
                 " Newton iterations");
        if (fronts.crack_tip - cut >= lead)
        {
          critical = cut;
          reason = "the crack tip leads the saw by " + format(fronts.crack_tip - cut) + " m";
          break;
        }
        step = std::min(2 * step, nominal_step);
      }
      u.update_ghost_values();
      fields.write(model, u, 1);
      series.write(options.output_directory + "/series.h5", "quasi-static PST, one row per converged saw step", comm);

      Json results;
      results["analysis"] = "quasi-static";
      results["mesh"] = mesh_json(model, comm);
      results["critical_cut_length_m"] = critical ? Json(*critical) : Json(nullptr);
      results["critical_cut_length_reason"] =
        critical ? reason : "equilibrium holds up to the longest cut " + format(scene.pst.cut_length) + " m";
      Energies energies = model.energies();
      energies.external_work = external_work;
      results["energies_per_width"] = energies_json(energies);
      results["newton_iterations"] = solver.total_iterations();
      return results;
    }

    // ---------------------------------------------------------------------------------------
    // Dynamic PST: gravity equilibrium, then the saw, the crack and its arrest in time.
    template <int dim>
    Json run_explicit_pst(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
    {
      Log log(options.log, comm);
      const Analysis &analysis = scene.analysis;
      SnowpackModel<dim> model(scene, comm);
      typename SnowpackModel<dim>::VectorType u;
      model.initialize_vector(u);
      {
        QuasiStaticSolver<dim> solver(model);
        log.line("[fem] dynamic PST: ", model.n_cells(), " cells, ", model.n_dofs(), " dofs, ",
                 Utilities::MPI::n_mpi_processes(comm), " rank(s)");
        gravity_equilibrium(model, solver, u, log);
      }
      // The quasi-static ramp stored E_el and dissipated D; its external work is their sum.
      const Energies at_rest = model.energies();
      const double dx = scene.pst.column_length / model.n_columns();
      const double lead = self_propagation_lead(scene);
      const double width = result_width<dim>(scene);

      if (scene.pst.saw == SawTest::Saw::fixed)
        model.set_cut(scene.pst.cut_length);
      ExplicitDynamics<dim> dynamics(model, u, at_rest.elastic + at_rest.dissipated);
      FieldRecord fields(options.output_directory + "/fields", comm);
      fields.write(model, dynamics.displacement(), 0);

      TimeSeries series({{"time", "s", "time since the saw started", {}},
                         {"cut_length", "m", "saw cut length", {}},
                         {"crack_tip", "m", "far end of the failed weak layer from the cut end", {}},
                         {"touchdown_front", "m", "far end of the locked-up (collapsed and closed) weak layer", {}},
                         {"elastic_energy", "J", "stored elastic energy (per m of width in 2D)", {}},
                         {"kinetic_energy", "J", "kinetic energy", {}},
                         {"dissipated_energy", "J", "plastic dissipation", {}},
                         {"viscous_energy", "J", "bulk viscosity and damping", {}},
                         {"removed_by_saw", "J", "elastic energy of the material the saw removed", {}},
                         {"external_work", "J", "work of gravity", {}},
                         {"time_step", "s", "explicit time step", {}}});

      const auto wall_start = std::chrono::steady_clock::now();
      std::optional<double> critical_cut, critical_time, end_time;
      double cut = scene.pst.saw == SawTest::Saw::fixed ? scene.pst.cut_length : 0;
      double next_series = scene.output.series_interval, next_field = scene.output.field_interval;
      CrackFronts fronts;
      bool reached_end = false;
      auto record = [&]() {
        if (!dynamics.finite())
          throw NumericalFailure("dynamic PST: non-finite displacement or velocity at t = " +
                                 format(dynamics.time(), 6) + " s (step " + std::to_string(dynamics.steps()) +
                                 ", dt = " + format(dynamics.time_step(), 3) + " s)");
        const Energies e = dynamics.energies();
        series.add_row({dynamics.time(), cut, fronts.crack_tip, fronts.touchdown, e.elastic, e.kinetic, e.dissipated,
                        e.viscous, e.removed_by_saw, e.external_work, dynamics.time_step()});
      };
      fronts = model.crack_fronts(analysis.failure_fraction);
      record();
      while (dynamics.time() < analysis.end_time)
      {
        if (scene.pst.saw == SawTest::Saw::advancing && !critical_cut)
        {
          const double saw = std::min(scene.pst.saw_speed * dynamics.time(), scene.pst.cut_length);
          if (saw > cut)
          {
            cut = saw;
            if (model.set_cut(cut))
              dynamics.refresh_internal_force();
          }
        }
        try
        {
          dynamics.step();
        }
        catch (const ReturnMappingError &e)
        {
          throw NumericalFailure("dynamic PST at t = " + format(dynamics.time(), 6) + " s (step " +
                                 std::to_string(dynamics.steps()) + "): " + e.what());
        }
        if (dynamics.time() >= next_series)
        {
          fronts = model.crack_fronts(analysis.failure_fraction);
          record();
          next_series += scene.output.series_interval;
          if (!critical_cut && fronts.crack_tip - cut >= lead)
          {
            critical_cut = cut;
            critical_time = dynamics.time();
            log.line("[fem] t = ", format(dynamics.time()), " s: the crack runs by itself (tip ",
                     format(fronts.crack_tip), " m, cut ", format(cut), " m)");
          }
          if (fronts.crack_tip >= scene.pst.column_length - 0.5 * dx && !reached_end)
          {
            reached_end = true;
            end_time = dynamics.time();
            log.line("[fem] t = ", format(dynamics.time()), " s: the crack reached the end of the column");
            break;
          }
        }
        if (next_field > 0 && dynamics.time() >= next_field)
        {
          fields.write(model, dynamics.displacement(), dynamics.time());
          next_field += scene.output.field_interval;
        }
        if (scene.output.progress_interval > 0 && dynamics.steps() % scene.output.progress_interval == 0)
          log.line("[fem] step ", dynamics.steps(), ", t = ", format(dynamics.time()), " s, dt = ",
                   format(dynamics.time_step(), 3), " s, cut ", format(cut), " m, crack tip ", format(fronts.crack_tip),
                   " m, E_kin = ", format(dynamics.energies().kinetic, 3), " J");
      }
      if (!reached_end) // otherwise the row of the step that reached the end is the last one
      {
        fronts = model.crack_fronts(analysis.failure_fraction);
        record();
      }
      fields.write(model, dynamics.displacement(), dynamics.time());
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      series.write(options.output_directory + "/series.h5",
                   "dynamic PST time series (energies per m of column width in 2D)", comm);

      // The crack ran by itself from the last row before the detection at which its tip was still
      // within two element lengths of the saw: that cut is the critical cut length (the detection
      // itself waits for a lead of one slab thickness, so that a tip that only jumps ahead of the
      // saw by a few elements is not taken for a running crack).
      const auto &t = series.column("time"), &tip = series.column("crack_tip"), &td = series.column("touchdown_front"),
                 &cuts = series.column("cut_length");
      const double detected_at = critical_time ? *critical_time : 0;
      if (critical_time)
        for (std::size_t k = 0; k < t.size() && t[k] <= detected_at; ++k)
          if (tip[k] - cuts[k] <= 2 * dx)
          {
            critical_cut = cuts[k];
            critical_time = t[k];
          }
      // Steady propagation speed: least-squares slope of the tip position over the rows where the
      // tip lies in the middle half of the distance it ran (from the critical cut to the end, or to
      // where it arrested). Touchdown distance: median of tip − touchdown front over those rows.
      std::optional<double> speed, touchdown;
      if (critical_cut)
      {
        const double from = *critical_cut, to = reached_end ? scene.pst.column_length : fronts.crack_tip;
        const double low = from + 0.25 * (to - from), high = from + 0.75 * (to - from);
        double st = 0, sx = 0, stt = 0, stx = 0, n = 0;
        std::vector<double> behind;
        for (std::size_t k = 0; k < t.size(); ++k)
          if (t[k] >= *critical_time && tip[k] >= low && tip[k] <= high)
          {
            st += t[k], sx += tip[k], stt += t[k] * t[k], stx += t[k] * tip[k], n += 1;
            if (td[k] > 0)
              behind.push_back(tip[k] - td[k]);
          }
        if (n >= 3 && n * stt - st * st > 0)
          speed = (n * stx - st * sx) / (n * stt - st * st);
        if (!behind.empty())
        {
          std::nth_element(behind.begin(), behind.begin() + behind.size() / 2, behind.end());
          touchdown = behind[behind.size() / 2];
        }
      }

      Json results;
      results["analysis"] = "explicit dynamics";
      results["mesh"] = mesh_json(model, comm);
      results["critical_cut_length_m"] = critical_cut ? Json(*critical_cut) : Json(nullptr);
      results["self_propagation_lead_m"] = lead;
      results["saw_speed_m_per_s"] = scene.pst.saw == SawTest::Saw::advancing ? Json(scene.pst.saw_speed) : Json(nullptr);
      results["crack"] = reached_end ? "reached the column end" : (critical_cut ? "arrested" : "did not start");
      results["arrest_position_m"] = reached_end ? Json(nullptr) : Json(fronts.crack_tip);
      results["time_crack_runs_s"] = critical_time ? Json(*critical_time) : Json(nullptr);
      results["time_reached_end_s"] = end_time ? Json(*end_time) : Json(nullptr);
      results["propagation_speed_m_per_s"] = speed ? Json(*speed) : Json(nullptr);
      results["touchdown_distance_m"] = touchdown ? Json(*touchdown) : Json(nullptr);
      results["final_crack_tip_m"] = fronts.crack_tip;
      results["final_touchdown_front_m"] = fronts.touchdown;
      results["simulated_time_s"] = dynamics.time();
      results["time_steps"] = dynamics.steps();
      results["last_time_step_s"] = dynamics.time_step();
      results["energies_per_width"] = energies_json(dynamics.energies());
      results["width_m"] = width;
      results["explicit_wall_time_s"] = wall;
      results["quadrature_point_updates_per_s_per_rank"] =
        wall > 0 ? double(dynamics.steps()) * model.n_cells() * std::pow(scene.mesh.polynomial_degree + 1, dim) /
                     wall / Utilities::MPI::n_mpi_processes(comm)
                 : 0.;
      return results;
    }

    template <int dim>
    Json run_in_dimension(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
    {
      switch (scene.analysis.type)
      {
        case Analysis::Type::energy_release_rate:
          return run_energy_release_rate<dim>(scene, options, comm);
        case Analysis::Type::quasi_static:
          return run_quasi_static_pst<dim>(scene, options, comm);
        case Analysis::Type::explicit_dynamics:
          return run_explicit_pst<dim>(scene, options, comm);
      }
      return {};
    }
  } // namespace

  Json run_snowpack(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm communicator)
  {
    const auto start = std::chrono::steady_clock::now();
    Json results = scene.mesh.dimension == 2 ? run_in_dimension<2>(scene, options, communicator)
                                             : run_in_dimension<3>(scene, options, communicator);
    results["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return results;
  }
} // namespace anticrack::fem
