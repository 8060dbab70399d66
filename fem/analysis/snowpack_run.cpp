// The three analyses of a snowpack scene (see the header) and what they write.
#include "fem/analysis/snowpack_run.h"

#include "fem/model/checkpoint.h"
#include "fem/closed_forms.h"
#include "fem/solver/explicit_dynamics.h"
#include "fem/solver/quasi_static.h"
#include "fem/model/snowpack_model.h"
#include "util/hdf5_file.h"
#include "util/input_error.h"

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

      void save(std::ostream &out) const
      {
        for (const Column &c : columns_)
          checkpoint::write_vector(out, c.values);
      }

      void load(std::istream &in)
      {
        for (Column &c : columns_)
          checkpoint::read_vector(in, c.values, -1, "time series " + c.name);
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

      /// Writes the fields at `time`, unless that time was written last already.
      template <int dim>
      void write(const SnowpackModel<dim> &model, const typename SnowpackModel<dim>::VectorType &u, double time)
      {
        if (!entries_.empty() && entries_.back().first == time)
          return;
        const std::string pvtu = model.write_fields(u, directory_, "fields", entries_.size());
        entries_.emplace_back(time, pvtu);
        if (Utilities::MPI::this_mpi_process(communicator_) == 0)
        {
          std::ofstream out(directory_ + "/fields.pvd");
          DataOutBase::write_pvd_record(out, entries_);
        }
      }

      void save(std::ostream &out) const
      {
        checkpoint::write(out, std::uint64_t(entries_.size()));
        for (const auto &[time, name] : entries_)
        {
          checkpoint::write(out, time);
          checkpoint::write_vector(out, std::vector<char>(name.begin(), name.end()));
        }
      }

      void load(std::istream &in)
      {
        std::uint64_t n = 0;
        checkpoint::read(in, n);
        entries_.clear();
        for (std::uint64_t k = 0; k < n; ++k)
        {
          double time = 0;
          std::vector<char> name;
          checkpoint::read(in, time);
          checkpoint::read_vector(in, name, -1, "field record");
          entries_.emplace_back(time, std::string(name.begin(), name.end()));
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

    /// Energies per metre of column width in 3D (2D already counts them per metre).
    template <int dim>
    Energies per_width(Energies e, const SnowpackScene &scene)
    {
      const double width = result_width<dim>(scene);
      for (double *value : {&e.elastic, &e.kinetic, &e.dissipated, &e.viscous, &e.external_work, &e.removed_by_saw})
        *value /= width;
      return e;
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
                         {"elastic_energy", "J/m", "stored elastic energy", {}},
                         {"dissipated_energy", "J/m", "plastic dissipation", {}},
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
        const Energies e = per_width<dim>(model.energies(), scene);
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
      energies = per_width<dim>(energies, scene);
      Json energy = energies_json(energies);
      // Each saw step is a sudden change solved statically: gravity's work f_g·Δu goes half into
      // elastic energy (linear response) and half into what would have been the step's vibration,
      // which a static solve drops. So the balance does not close here; what it misses is reported.
      energy.erase("balance_error_relative");
      energy["not_stored_in_static_steps_J"] =
        energies.external_work - (energies.elastic + energies.dissipated + energies.removed_by_saw);
      results["energies_per_width"] = energy;
      results["newton_iterations"] = solver.total_iterations();
      return results;
    }

    // ---------------------------------------------------------------------------------------
    // Dynamic PST: gravity equilibrium, then the saw, the crack and its arrest in time; checkpoints
    // every `Checkpoint interval` steps, from which a run resumes bit for bit.
    template <int dim>
    class DynamicPst
    {
    public:
      DynamicPst(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
        : scene_(scene)
        , options_(options)
        , comm_(comm)
        , log_(options.log, comm)
        , model_(scene, comm)
        , fields_(options.output_directory + "/fields", comm)
        , series_({{"time", "s", "time since the saw started", {}},
                   {"cut_length", "m", "saw cut length", {}},
                   {"crack_tip", "m", "far end of the failed weak layer from the cut end", {}},
                   {"touchdown_front", "m", "far end of the locked-up (collapsed and closed) weak layer", {}},
                   {"elastic_energy", "J/m", "stored elastic energy (per m of column width)", {}},
                   {"kinetic_energy", "J/m", "kinetic energy", {}},
                   {"dissipated_energy", "J/m", "plastic dissipation", {}},
                   {"viscous_energy", "J/m", "bulk viscosity and damping", {}},
                   {"removed_by_saw", "J/m", "elastic energy of the material the saw removed", {}},
                   {"external_work", "J/m", "work of gravity", {}},
                   {"time_step", "s", "explicit time step", {}}})
      {}

      Json run()
      {
        const auto wall_start = std::chrono::steady_clock::now();
        log_.line("[fem] dynamic PST: ", model_.n_cells(), " cells, ", model_.n_dofs(), " dofs, ",
                  Utilities::MPI::n_mpi_processes(comm_), " rank(s)");
        if (options_.resume)
          resume();
        else
          start();
        try
        {
          integrate();
        }
        catch (const NumericalFailure &)
        {
          write_series(); // what was computed up to the failure
          throw;
        }
        wall_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
        write_series();
        return results();
      }

    private:
      // The state of the run besides the model and the integrator (saved in checkpoints).
      double cut_ = 0, next_series_ = 0, next_field_ = 0, wall_ = 0;
      std::optional<double> critical_cut_, critical_time_, end_time_;
      CrackFronts fronts_;

      void start()
      {
        typename SnowpackModel<dim>::VectorType u;
        model_.initialize_vector(u);
        {
          QuasiStaticSolver<dim> solver(model_);
          gravity_equilibrium(model_, solver, u, log_);
        }
        // The quasi-static ramp stored E_el and dissipated D; its external work is their sum.
        const Energies at_rest = model_.energies();
        if (scene_.pst.saw == SawTest::Saw::fixed)
          model_.set_cut(scene_.pst.cut_length);
        cut_ = scene_.pst.saw == SawTest::Saw::fixed ? scene_.pst.cut_length : 0;
        dynamics_ = std::make_unique<ExplicitDynamics<dim>>(model_, u, at_rest.elastic + at_rest.dissipated);
        fields_.write(model_, dynamics_->displacement(), 0);
        fronts_ = model_.crack_fronts(scene_.analysis.failure_fraction);
        record();
        next_series_ = scene_.output.series_interval;
        next_field_ = scene_.output.field_interval;
      }

      void integrate()
      {
        const Analysis &analysis = scene_.analysis;
        const double dx = scene_.pst.column_length / model_.n_columns();
        const double lead = self_propagation_lead(scene_);
        ExplicitDynamics<dim> &dynamics = *dynamics_;
        while (dynamics.time() < analysis.end_time && !end_time_)
        {
          if (scene_.pst.saw == SawTest::Saw::advancing && !critical_cut_)
          {
            const double saw = std::min(scene_.pst.saw_speed * dynamics.time(), scene_.pst.cut_length);
            if (saw > cut_)
            {
              cut_ = saw;
              if (model_.set_cut(cut_))
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
          if (dynamics.time() >= next_series_)
          {
            fronts_ = model_.crack_fronts(analysis.failure_fraction);
            record();
            next_series_ += scene_.output.series_interval;
            if (!critical_cut_ && fronts_.crack_tip - cut_ >= lead)
            {
              critical_cut_ = cut_;
              critical_time_ = dynamics.time();
              log_.line("[fem] t = ", format(dynamics.time()), " s: the crack runs by itself (tip ",
                        format(fronts_.crack_tip), " m, cut ", format(cut_), " m)");
            }
            if (fronts_.crack_tip >= scene_.pst.column_length - 0.5 * dx)
            {
              end_time_ = dynamics.time();
              log_.line("[fem] t = ", format(dynamics.time()), " s: the crack reached the end of the column");
            }
          }
          if (next_field_ > 0 && dynamics.time() >= next_field_)
          {
            fields_.write(model_, dynamics.displacement(), dynamics.time());
            next_field_ += scene_.output.field_interval;
          }
          if (scene_.output.progress_interval > 0 && dynamics.steps() % scene_.output.progress_interval == 0)
            log_.line("[fem] step ", dynamics.steps(), ", t = ", format(dynamics.time()), " s, dt = ",
                      format(dynamics.time_step(), 3), " s, cut ", format(cut_), " m, crack tip ",
                      format(fronts_.crack_tip), " m, E_kin = ", format(dynamics.energies().kinetic, 3), " J");
          if (scene_.output.checkpoint_interval > 0 && dynamics.steps() % scene_.output.checkpoint_interval == 0)
            write_checkpoint();
        }
        // A run that stopped at its end time can be extended (--resume with a later end time): its
        // checkpoint comes before the final row and fields, which a longer run would not have.
        if (scene_.output.checkpoint_interval > 0 && !end_time_)
          write_checkpoint();
        if (!end_time_) // otherwise the row of the step that reached the end is the last one
        {
          fronts_ = model_.crack_fronts(analysis.failure_fraction);
          record();
        }
        fields_.write(model_, dynamics.displacement(), dynamics.time());
      }

      void record()
      {
        const ExplicitDynamics<dim> &dynamics = *dynamics_;
        if (!dynamics.finite())
          throw NumericalFailure("dynamic PST: non-finite displacement or velocity at t = " +
                                 format(dynamics.time(), 6) + " s (step " + std::to_string(dynamics.steps()) +
                                 ", dt = " + format(dynamics.time_step(), 3) + " s)");
        const Energies e = per_width<dim>(dynamics.energies(), scene_);
        series_.add_row({dynamics.time(), cut_, fronts_.crack_tip, fronts_.touchdown, e.elastic, e.kinetic,
                         e.dissipated, e.viscous, e.removed_by_saw, e.external_work, dynamics.time_step()});
      }

      void write_series() const
      {
        series_.write(options_.output_directory + "/series.h5",
                      "dynamic PST time series (energies per m of column width)", comm_);
      }

      // --- checkpoints: DIR/checkpoint/step_S_rank_R.bin per rank, then DIR/checkpoint.json (rank 0)
      // names the step; a run killed while writing resumes from the previous complete one.
      std::string rank_file(unsigned long step, unsigned int rank) const
      {
        return options_.output_directory + "/checkpoint/step_" + std::to_string(step) + "_rank_" +
               std::to_string(rank) + ".bin";
      }

      void write_checkpoint()
      {
        const unsigned int rank = Utilities::MPI::this_mpi_process(comm_);
        const unsigned long step = dynamics_->steps();
        if (rank == 0)
          std::filesystem::create_directories(options_.output_directory + "/checkpoint");
        MPI_Barrier(comm_);
        const std::string file = rank_file(step, rank);
        {
          std::ofstream out(file + ".tmp", std::ios::binary);
          model_.save(out);
          dynamics_->save(out);
          save_run_state(out);
          if (!out)
            throw std::runtime_error("cannot write the checkpoint " + file);
        }
        std::filesystem::rename(file + ".tmp", file);
        MPI_Barrier(comm_);
        if (rank == 0)
        {
          Json info;
          info["step"] = step;
          info["time_s"] = dynamics_->time();
          info["ranks"] = Utilities::MPI::n_mpi_processes(comm_);
          info["dofs"] = model_.n_dofs();
          info["resume_key_sha256"] = scene_.resume_key_sha256;
          const std::string json = options_.output_directory + "/checkpoint.json";
          {
            std::ofstream out(json + ".tmp");
            out << info.dump(2) << '\n';
          }
          std::filesystem::rename(json + ".tmp", json);
          // Older steps are no longer needed.
          for (const auto &entry : std::filesystem::directory_iterator(options_.output_directory + "/checkpoint"))
            if (entry.path().filename().string().rfind("step_" + std::to_string(step) + "_", 0) != 0)
              std::filesystem::remove(entry.path());
        }
        write_series();
        log_.line("[fem] checkpoint at step ", step, ", t = ", format(dynamics_->time()), " s");
      }

      void save_run_state(std::ostream &out) const
      {
        for (const double value : {cut_, next_series_, next_field_, wall_, fronts_.crack_tip, fronts_.touchdown,
                                   critical_cut_.value_or(-1.), critical_time_.value_or(-1.)})
          checkpoint::write(out, value);
        series_.save(out);
        fields_.save(out);
      }

      void resume()
      {
        const std::string json_file = options_.output_directory + "/checkpoint.json";
        std::ifstream json_in(json_file);
        if (!json_in)
          throw InputError("cannot resume: " + json_file + " does not exist (set Output/Checkpoint interval)");
        const Json info = Json::parse(json_in);
        if (info.value("resume_key_sha256", "") != scene_.resume_key_sha256)
          throw InputError("cannot resume from " + json_file +
                           ": it was written by another scene (only Analysis/Explicit/End time and Output may "
                           "change)");
        if (info.value("ranks", 0u) != Utilities::MPI::n_mpi_processes(comm_))
          throw InputError("cannot resume from " + json_file + ": it was written on " +
                           std::to_string(info.value("ranks", 0u)) + " rank(s); run on as many");
        const unsigned long step = info["step"];
        std::ifstream in(rank_file(step, Utilities::MPI::this_mpi_process(comm_)), std::ios::binary);
        if (!in)
          throw InputError("cannot resume: the checkpoint file " +
                           rank_file(step, Utilities::MPI::this_mpi_process(comm_)) + " is missing");
        typename SnowpackModel<dim>::VectorType u;
        model_.initialize_vector(u);
        try
        {
          model_.load(in);
          dynamics_ = std::make_unique<ExplicitDynamics<dim>>(model_, u, 0., true);
          dynamics_->load(in);
          double critical_cut = 0, critical_time = 0;
          for (double *value : {&cut_, &next_series_, &next_field_, &wall_, &fronts_.crack_tip, &fronts_.touchdown,
                                &critical_cut, &critical_time})
            checkpoint::read(in, *value);
          if (critical_cut >= 0)
            critical_cut_ = critical_cut, critical_time_ = critical_time;
          series_.load(in);
          fields_.load(in);
        }
        catch (const checkpoint::Mismatch &e)
        {
          throw InputError("cannot resume from " + json_file + ": " + e.what());
        }
        log_.line("[fem] resumed at step ", step, ", t = ", format(dynamics_->time()), " s");
      }

      Json results()
      {
        const ExplicitDynamics<dim> &dynamics = *dynamics_;
        const double dx = scene_.pst.column_length / model_.n_columns();
        const double lead = self_propagation_lead(scene_);
        const bool reached_end = end_time_.has_value();
        // The crack ran by itself from the last row before the detection at which its tip was
        // still within two element lengths of the saw: that cut is the critical cut length (the
        // detection itself waits for a lead of one slab thickness, so that a tip that only jumps
        // ahead of the saw by a few elements is not taken for a running crack).
        const auto &t = series_.column("time"), &tip = series_.column("crack_tip"),
                   &td = series_.column("touchdown_front"), &cuts = series_.column("cut_length");
        std::optional<double> critical_cut = critical_cut_, critical_time = critical_time_;
        if (critical_time_)
          for (std::size_t k = 0; k < t.size() && t[k] <= *critical_time_; ++k)
            if (tip[k] - cuts[k] <= 2 * dx)
            {
              critical_cut = cuts[k];
              critical_time = t[k];
            }
        // Steady propagation speed: least-squares slope of the tip position over the rows where
        // the tip lies in the middle half of the distance it ran (from the critical cut to the end,
        // or to where it arrested). Touchdown distance: median of tip − touchdown front there.
        std::optional<double> speed, touchdown;
        if (critical_cut)
        {
          const double from = *critical_cut, to = reached_end ? scene_.pst.column_length : fronts_.crack_tip;
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
        auto optional = [](const std::optional<double> &v) { return v ? Json(*v) : Json(nullptr); };
        Json r;
        r["analysis"] = "explicit dynamics";
        r["mesh"] = mesh_json(model_, comm_);
        r["critical_cut_length_m"] = optional(critical_cut);
        r["self_propagation_lead_m"] = lead;
        r["saw_speed_m_per_s"] = scene_.pst.saw == SawTest::Saw::advancing ? Json(scene_.pst.saw_speed) : Json(nullptr);
        r["crack"] = reached_end ? "reached the column end" : (critical_cut ? "arrested" : "did not start");
        r["arrest_position_m"] = reached_end ? Json(nullptr) : Json(fronts_.crack_tip);
        r["time_crack_runs_s"] = optional(critical_time);
        r["time_reached_end_s"] = optional(end_time_);
        r["propagation_speed_m_per_s"] = optional(speed);
        r["touchdown_distance_m"] = optional(touchdown);
        r["final_crack_tip_m"] = fronts_.crack_tip;
        r["final_touchdown_front_m"] = fronts_.touchdown;
        r["simulated_time_s"] = dynamics.time();
        r["time_steps"] = dynamics.steps();
        r["last_time_step_s"] = dynamics.time_step();
        r["energies_per_width"] = energies_json(per_width<dim>(dynamics.energies(), scene_));
        r["width_m"] = result_width<dim>(scene_);
        r["explicit_wall_time_s"] = wall_;
        r["quadrature_point_updates_per_s_per_rank"] =
          wall_ > 0 ? double(dynamics.steps()) * model_.n_cells() * std::pow(scene_.mesh.polynomial_degree + 1, dim) /
                        wall_ / Utilities::MPI::n_mpi_processes(comm_)
                    : 0.;
        return r;
      }

      const SnowpackScene &scene_;
      const SnowpackRunOptions &options_;
      MPI_Comm comm_;
      Log log_;
      SnowpackModel<dim> model_;
      std::unique_ptr<ExplicitDynamics<dim>> dynamics_;
      FieldRecord fields_;
      TimeSeries series_;
    };

    template <int dim>
    Json run_explicit_pst(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
    {
      DynamicPst<dim> pst(scene, options, comm);
      return pst.run();
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
