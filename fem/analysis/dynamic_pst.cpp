// The dynamic PST: gravity equilibrium, then the saw, the crack and its arrest in time by explicit
// central differences; series.h5, the fields, and checkpoints from which a run resumes bit for bit.
#include "fem/analysis/outputs.h"
#include "fem/analysis/snowpack_run.h"
#include "fem/model/checkpoint.h"
#include "util/atomic_file.h"
#include "fem/solver/explicit_dynamics.h"
#include "fem/solver/quasi_static.h"
#include "util/input_error.h"
#include "util/problems.h"
#include "util/stop_signals.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

namespace anticrack::fem
{
  using namespace dealii;

  namespace
  {
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
        , log_(root_log(options.log, comm))
        , model_(scene, comm, options.timer)
        , fields_(options.output_directory + "/fields", comm)
        , series_(series_of({{"time", "s", "time since the saw started"},
                             {"cut_length", "m", "saw cut length"},
                             {"crack_tip", "m", "far end of the failed weak layer from the cut end"},
                             {"touchdown_front", "m", "far end of the locked-up (collapsed and closed) weak layer"},
                             {"elastic_energy", "J/m", "stored elastic energy (per m of column width)"},
                             {"kinetic_energy", "J/m", "kinetic energy"},
                             {"dissipated_energy", "J/m", "plastic dissipation"},
                             {"viscous_energy", "J/m", "bulk viscosity and damping"},
                             {"removed_by_saw", "J/m", "elastic energy of the material the saw removed"},
                             {"external_work", "J/m", "work of gravity"},
                             {"time_step", "s", "explicit time step"}}))
      {}

      Json run()
      {
        const auto wall_start = std::chrono::steady_clock::now();
        const StopSignals stop_signals; // before the first line, which tells a caller it may signal
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
      /// Steps between the ranks' agreements on a stop signal (one reduction; ~10 ms of steps).
      static constexpr unsigned long stop_poll_steps = 200;

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
          try
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
            dynamics.step();
          }
          catch (const ReturnMappingError &e)
          {
            throw failure("return mapping", e.what());
          }
          if (!dynamics.step_finite())
            throw failure("non-finite value", "a non-finite force, velocity or time step: " +
                                                  dynamics.non_finite_location());
          if (dynamics.time() >= next_series_)
          {
            fronts_ = model_.crack_fronts(analysis.failure_fraction);
            record();
            next_series_ += scene_.output.series_interval;
            if (!critical_cut_ && fronts_.crack_tip - cut_ >= lead)
            {
              critical_cut_ = cut_;
              critical_time_ = dynamics.time();
              log_.line("[fem] t = ", format_number(dynamics.time(), 4), " s: the crack runs by itself (tip ",
                        format_number(fronts_.crack_tip, 4), " m, cut ", format_number(cut_, 4), " m)");
            }
            if (fronts_.crack_tip >= scene_.pst.column_length - 0.5 * dx)
            {
              end_time_ = dynamics.time();
              log_.line("[fem] t = ", format_number(dynamics.time(), 4), " s: the crack reached the end of the column");
            }
          }
          if (next_field_ > 0 && dynamics.time() >= next_field_)
          {
            fields_.write(model_, dynamics.displacement(), dynamics.time());
            next_field_ += scene_.output.field_interval;
          }
          if (scene_.output.progress_interval > 0 && dynamics.steps() % scene_.output.progress_interval == 0)
            log_.line("[fem] step ", dynamics.steps(), ", t = ", format_number(dynamics.time(), 4), " s, dt = ",
                      format_number(dynamics.time_step(), 3), " s, cut ", format_number(cut_, 4), " m, crack tip ",
                      format_number(fronts_.crack_tip, 4), " m, E_kin = ", format_number(dynamics.energies().kinetic, 3), " J");
          if (scene_.output.checkpoint_interval > 0 && dynamics.steps() % scene_.output.checkpoint_interval == 0)
            write_checkpoint();
          // Ctrl-C / SIGTERM: the ranks agree every stop_poll_steps steps (each may get the signal
          // in another step), write a checkpoint whatever the interval, and stop.
          if (dynamics.steps() % stop_poll_steps == 0 && Utilities::MPI::logical_or(StopSignals::requested(), comm_))
          {
            write_checkpoint();
            throw RunInterrupted("dynamic PST stopped by a signal at step " + std::to_string(dynamics.steps()) +
                                 ", t = " + format_number(dynamics.time(), 6) + " s; checkpoint written, resume "
                                 "with --resume");
          }
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

      /// The failure `what` at `where` (a cell, a node) now: summary.json's "failure" gets both and
      /// the step, time, time step and cut length; the series written up to here are kept.
      NumericalFailure failure(const std::string &what, const std::string &where) const
      {
        const ExplicitDynamics<dim> &dynamics = *dynamics_;
        Json details = {{"what", what},
                        {"where", where},
                        {"when", {{"phase", "explicit dynamics"},
                                  {"step", dynamics.steps()},
                                  {"time_s", dynamics.time()},
                                  {"time_step_s", dynamics.time_step()},
                                  {"cut_length_m", cut_}}}};
        return NumericalFailure("dynamic PST: " + what + " at t = " + format_number(dynamics.time(), 6) + " s (step " +
                                  std::to_string(dynamics.steps()) + ", cut " + format_number(cut_, 4) + " m): " + where,
                                details);
      }

      void record()
      {
        const ExplicitDynamics<dim> &dynamics = *dynamics_;
        if (!dynamics.finite())
          throw failure("non-finite value", "a non-finite displacement or velocity: " + dynamics.non_finite_location());
        const Energies e = per_width<dim>(dynamics.energies(), scene_);
        series_.append({dynamics.time(), cut_, fronts_.crack_tip, fronts_.touchdown, e.elastic, e.kinetic,
                        e.dissipated, e.viscous, e.removed_by_saw, e.external_work, dynamics.time_step()});
      }

      void write_series() const
      {
        write_on_root(series_, options_.output_directory + "/series.h5",
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
        const auto phase = model_.timer().scope("output");
        const std::string file = rank_file(step, rank);
        write_atomically(file, [&](const std::string &temporary) {
          std::ofstream out(temporary, std::ios::binary);
          model_.save(out);
          dynamics_->save(out);
          save_run_state(out);
          if (!out.flush())
            throw std::runtime_error("cannot write the checkpoint " + temporary);
        }, /*durable=*/true);
        MPI_Barrier(comm_);
        if (rank == 0)
        {
          Json info;
          info["step"] = step;
          info["time_s"] = dynamics_->time();
          info["ranks"] = Utilities::MPI::n_mpi_processes(comm_);
          info["dofs"] = model_.n_dofs();
          info["resume_key_sha256"] = scene_.resume_key_sha256;
          write_text_atomically(options_.output_directory + "/checkpoint.json",
                                [&](std::ostream &out) { out << info.dump(2) << '\n'; }, /*durable=*/true);
          // Older steps are no longer needed.
          for (const auto &entry : std::filesystem::directory_iterator(options_.output_directory + "/checkpoint"))
            if (entry.path().filename().string().rfind("step_" + std::to_string(step) + "_", 0) != 0)
              std::filesystem::remove(entry.path());
        }
        write_series();
        log_.line("[fem] checkpoint at step ", step, ", t = ", format_number(dynamics_->time(), 4), " s");
      }

      void save_run_state(std::ostream &out) const
      {
        for (const double value : {cut_, next_series_, next_field_, wall_, fronts_.crack_tip, fronts_.touchdown,
                                   critical_cut_.value_or(-1.), critical_time_.value_or(-1.)})
          checkpoint::write(out, value);
        for (const TimeSeries::Column &column : series_.columns())
          checkpoint::write_vector(out, column.values);
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
        // Every rank must refuse together: a rank that stopped alone would leave the others
        // waiting in the next collective call.
        const std::vector<int> missing = Utilities::MPI::all_gather(comm_, int(!in));
        for (unsigned int rank = 0; rank < missing.size(); ++rank)
          if (missing[rank])
            throw InputError("cannot resume: the checkpoint file " + rank_file(step, rank) + " is missing");
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
          series_.replace_values([&](const TimeSeries::Column &column) {
            std::vector<double> values;
            checkpoint::read_vector(in, values, -1, "time series " + column.name);
            return values;
          });
          fields_.load(in);
        }
        catch (const checkpoint::Mismatch &e)
        {
          throw InputError("cannot resume from " + json_file + ": " + e.what());
        }
        log_.line("[fem] resumed at step ", step, ", t = ", format_number(dynamics_->time(), 4), " s");
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
        const auto &t = series_.values("time"), &tip = series_.values("crack_tip"),
                   &td = series_.values("touchdown_front"), &cuts = series_.values("cut_length");
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
        r["analysis"] = scene_.analysis.type->name;
        r["mesh"] = mesh_json(model_, comm_);
        r["critical_cut_length_m"] = optional(critical_cut);
        r["self_propagation_lead_m"] = lead;
        r["gaume2017"] = gaume2017_reference(scene_.snowpack);
        r["saw_speed_m_per_s"] = scene_.pst.saw == SawTest::Saw::advancing ? Json(scene_.pst.saw_speed) : Json(nullptr);
        r["crack"] = reached_end ? "reached the column end" : (critical_cut ? "arrested" : "did not start");
        r["arrest_position_m"] = reached_end ? Json(nullptr) : Json(fronts_.crack_tip);
        r["time_crack_runs_s"] = optional(critical_time);
        r["time_reached_end_s"] = optional(end_time_);
        r["propagation_speed_m_per_s"] = optional(speed);
        r["touchdown_distance_m"] = optional(touchdown);
        r["final_crack_tip_m"] = fronts_.crack_tip;
        r["final_touchdown_front_m"] = fronts_.touchdown;
        {
          // The closure of the collapsed layer, which the collapse height bounds (the lock-up
          // spring adds H p / K_d, a few per cent of it under a slab's weight).
          const CrackFronts final_state = model_.crack_fronts(scene_.analysis.failure_fraction);
          r["weak_layer_closure"] = {{"collapse_height_m", scene_.snowpack.weak_layer.collapse_height},
                                     {"mean_over_locked_columns_m", final_state.locked_closure},
                                     {"largest_m", final_state.largest_closure}};
        }
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
      ConditionalStream log_;
      SnowpackModel<dim> model_;
      std::unique_ptr<ExplicitDynamics<dim>> dynamics_;
      FieldRecord fields_;
      TimeSeries series_;
    };
  } // namespace

  template <int dim>
  Json run_dynamic_pst(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm)
  {
    DynamicPst<dim> pst(scene, options, comm);
    return pst.run();
  }

  AnalysisType dynamic_pst_analysis()
  {
    return {
      "explicit dynamics", "dynamic PST (explicit central differences)",
      "gravity equilibrium, then the saw and crack propagation in time (explicit central differences).",
      /* yielding_weak_layer = */ true, /* time_integration = */ true,
      [](ParameterHandler &prm) {
        prm.enter_subsection("Explicit");
        prm.declare_entry("End time [s]", "1", Patterns::Double(0),
                          "t_end: simulated time after the saw starts. Units: s.");
        prm.declare_entry("CFL safety factor", "0.5", Patterns::Double(0.01, 1),
                          "C: safety factor of the explicit time step dt = C min(h / c_p). Dimensionless.");
        prm.declare_entry("Linear bulk viscosity", "0.06", Patterns::Double(0, 10),
                          "c_1: linear coefficient of the bulk viscosity pressure p_v = rho h (c_2^2 h e_v'^2 - c_1 "
                          "c e_v'). Dimensionless.");
        prm.declare_entry("Quadratic bulk viscosity", "1.2", Patterns::Double(0, 10),
                          "c_2: quadratic coefficient of the bulk viscosity pressure (acts in compression only). "
                          "Dimensionless.");
        prm.declare_entry("Mass damping [1/s]", "0", Patterns::Double(0),
                          "alpha_M: mass-proportional damping, force -alpha_M M v. Units: 1/s.");
        prm.leave_subsection();
      },
      [](ParameterHandler &prm, SnowpackScene &scene) {
        Analysis &analysis = scene.analysis;
        prm.enter_subsection("Explicit");
        analysis.end_time = prm.get_double("End time [s]");
        analysis.cfl_safety = prm.get_double("CFL safety factor");
        analysis.linear_bulk_viscosity = prm.get_double("Linear bulk viscosity");
        analysis.quadratic_bulk_viscosity = prm.get_double("Quadratic bulk viscosity");
        analysis.mass_damping = prm.get_double("Mass damping [1/s]");
        prm.leave_subsection();
      },
      [](const SnowpackScene &scene, Problems &problems) {
        if (!(scene.analysis.end_time > 0))
          problems.add("Analysis/Explicit/End time [s]", "must be > 0");
        // The stable step is estimated as 1/(c sqrt(Σ (p/h_i)²)) (SnowpackModel::evaluate), exact
        // for Q1 with the lumped mass. Q2's lumped Gauss–Lobatto (Simpson) mass gives its 1D
        // element chain the highest frequency √24 c/h, so central differences need
        // Δt ≤ 2h/(√24 c) = √(2/3) h/(2c): the safety factor must stay below √(2/3) (tensor-product
        // elements: the same ratio in every direction).
        const double q2_limit = std::sqrt(2.0 / 3.0);
        if (scene.mesh.polynomial_degree == 2 && scene.analysis.cfl_safety > q2_limit)
          problems.add("Analysis/Explicit/CFL safety factor",
                       "must be <= " + format_number(q2_limit, 4) + " with Mesh/Polynomial degree = 2 (is " +
                         format_number(scene.analysis.cfl_safety) + "): the Q2 elements' lumped Gauss-Lobatto mass "
                         "makes their highest frequency sqrt(24) c/h, and the step estimate is Q1's");
      },
      &run_dynamic_pst<2>, &run_dynamic_pst<3>};
  }
} // namespace anticrack::fem
