// The dynamic PST: gravity equilibrium, then the saw, the crack and its arrest in time by explicit
// central differences; series.h5, the fields, and checkpoints from which a run resumes bit for bit.
#include "fem/analysis/critical_cut_search.h"
#include "fem/analysis/outputs.h"
#include "fem/analysis/snowpack_run.h"
#include "fem/model/checkpoint.h"
#include "fem/scene/layers.h"
#include "util/atomic_file.h"
#include "fem/solver/explicit_dynamics.h"
#include "fem/solver/quasi_static.h"
#include "util/entry_table.h"
#include "util/enum_table.h"
#include "util/input_error.h"
#include "util/problems.h"
#include "util/run_summary.h"
#include "util/stop_signals.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
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
      /// `preloaded_cut`: a bisection trial, whose column is cut by this much before the gravity ramp.
      DynamicPst(const SnowpackScene &scene, const SnowpackRunOptions &options, MPI_Comm comm,
                 std::optional<double> preloaded_cut = {})
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
      {
        preloaded_cut_ = preloaded_cut;
      }

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

      using Outcome = PstOutcome;

      /// Where and when the slab's tension reached its strength.
      struct SlabFracture
      {
        double time = 0, cut = 0;
        typename SnowpackModel<dim>::SlabTension tension;
        bool crack_running = false;
      };

      // The state of the run besides the model and the integrator (saved in checkpoints).
      double cut_ = 0, next_series_ = 0, next_field_ = 0, wall_ = 0;
      std::optional<double> critical_cut_, critical_time_, end_time_;
      CrackFronts fronts_;
      /// When the saw stopped (the full cut made, or the crack running by itself).
      std::optional<double> saw_stopped_;
      /// The far end failing by itself before the crack got there: when, and over what length.
      std::optional<double> free_end_time_;
      double free_end_length_ = 0;
      double largest_tension_ratio_ = 0;
      /// Bisection trial: the cut made before the gravity ramp; the load factor at which the ramp failed.
      std::optional<double> preloaded_cut_, ramp_lost_at_;
      /// Quasi-static saw: the longest cut in equilibrium and the cut the dynamics start from.
      std::optional<std::pair<double, double>> static_bracket_;
      unsigned int static_phases_ = 0; ///< quasi-static saw phases so far
      // Set once the run has ended (never checkpointed: the run stops there).
      Outcome outcome_ = Outcome::running;
      double arrest_position_ = 0, arrest_time_ = 0;
      std::optional<SlabFracture> slab_fracture_;

      void start()
      {
        typename SnowpackModel<dim>::VectorType u;
        model_.initialize_vector(u);
        {
          QuasiStaticSolver<dim> solver(model_);
          if (preloaded_cut_)
          {
            // A bisection trial: the column is cut, then loaded. A ramp that cannot reach the full
            // weight means there is no equilibrium with this cut; the dynamics then start from the
            // last equilibrium under the full weight.
            check_weak_layer_carries_the_snowpack(scene_);
            cut_ = *preloaded_cut_;
            model_.set_cut(cut_);
            try
            {
              solver.apply_gravity(u, scene_.analysis.gravity_steps, [](double, const NewtonResult &) {});
            }
            catch (const GravityRampFailure &e)
            {
              ramp_lost_at_ = e.load_factor;
              log_.line("[fem] no equilibrium with the cut ", format_number(cut_, 4), " m: the gravity ramp fails at ",
                        format_number(100 * e.load_factor, 4), " % of the weight");
            }
          }
          else
            gravity_equilibrium(model_, solver, u, log_);
          if (scene_.pst.saw == SawTest::Saw::quasi_static)
            saw_statically(solver, u);
        }
        // The static phases stored E_el, dissipated D and lost what the saw removed: the external
        // work so far is their sum (a static saw step's vibration energy is not counted).
        const Energies at_rest = model_.energies();
        if (scene_.pst.saw == SawTest::Saw::fixed)
        {
          cut_ = scene_.pst.cut_length;
          model_.set_cut(cut_);
        }
        if (scene_.pst.saw != SawTest::Saw::advancing)
          saw_stopped_ = 0.;
        dynamics_ = std::make_unique<ExplicitDynamics<dim>>(model_, u, at_rest.elastic + at_rest.dissipated +
                                                                         at_rest.removed_by_saw);
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
              if (cut_ >= scene_.pst.cut_length && !saw_stopped_)
                saw_stopped_ = dynamics.time();
            }
            dynamics.step();
          }
          catch (const ReturnMappingError &e)
          {
            throw failure("return mapping", failure_site_of(e));
          }
          if (!dynamics.step_finite())
            throw failure("non-finite value", non_finite_site("a non-finite force, velocity or time step"));
          if (dynamics.time() >= next_series_)
          {
            fronts_ = model_.crack_fronts(analysis.failure_fraction);
            record();
            next_series_ += scene_.output.series_interval;
            detect(dx, lead);
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

      /// The outcome at a series row (the row just recorded). The rows are at most a tenth of the
      /// arrest duration apart (checked), and the slab's tension is the largest since the last row.
      void detect(double dx, double lead)
      {
        const double t = dynamics_->time(), column = scene_.pst.column_length;
        const double remaining = column - cut_;
        // Self-propagation: the tip leads the saw by the lead, or by what is left of the column.
        if (!critical_cut_ && fronts_.crack_tip - cut_ >= std::min(lead, remaining - 0.5 * dx) &&
            fronts_.crack_tip > cut_ + 0.5 * dx)
        {
          critical_cut_ = cut_;
          critical_time_ = t;
          if (!saw_stopped_)
            saw_stopped_ = t; // the saw stops once the crack runs
          log_.line("[fem] t = ", format_number(t, 4), " s: the crack runs by itself (tip ",
                    format_number(fronts_.crack_tip, 4), " m, cut ", format_number(cut_, 4), " m)");
        }
        if (!free_end_time_ && fronts_.far_end_failed > 0 && fronts_.crack_tip + fronts_.far_end_failed < column - 0.5 * dx)
        {
          free_end_time_ = t;
          free_end_length_ = fronts_.far_end_failed;
          log_.line("[fem] t = ", format_number(t, 4), " s: the far end of the column fails by itself over ",
                    format_number(fronts_.far_end_failed, 3), " m (not the crack)");
        }
        const typename SnowpackModel<dim>::SlabTension tension = model_.slab_tension();
        largest_tension_ratio_ = std::max(largest_tension_ratio_, tension.ratio);
        if (tension.ratio >= 1)
        {
          slab_fracture_ = SlabFracture{t, cut_, tension, critical_cut_.has_value()};
          finish(Outcome::slab_fracture, "the slab fractures: its fibre stress " + format_number(tension.stress, 4) +
                                           " Pa reaches the tensile strength " + format_number(tension.strength, 4) +
                                           " Pa in " + layer_label(tension.layer) + " at x = " +
                                           format_number(tension.position[0], 4) + " m");
          return;
        }
        if (fronts_.crack_tip >= column - 0.5 * dx)
        {
          finish(Outcome::end, "the crack reached the end of the column");
          return;
        }
        // Arrest: the tip slower than v_arr over the last t_arr, with the saw stopped for as long.
        const double window = scene_.analysis.arrest_duration;
        if (saw_stopped_ && t - *saw_stopped_ >= window)
        {
          const auto &times = series_.values("time"), &tips = series_.values("crack_tip");
          std::size_t k = times.size() - 1;
          while (k > 0 && times[k] > t - window)
            --k;
          if (fronts_.crack_tip - tips[k] < scene_.analysis.arrest_speed * window)
          {
            arrest_position_ = fronts_.crack_tip;
            arrest_time_ = times[k];
            if (critical_cut_)
              finish(Outcome::arrest, "the crack arrested at " + format_number(arrest_position_, 4) + " m");
            else if (scene_.pst.saw == SawTest::Saw::quasi_static && cut_ < scene_.pst.cut_length - 1e-12)
              saw_on(); // the loss of equilibrium was a local event that settled: the saw goes on
            else
              finish(Outcome::no_propagation, "the cut did not grow into a crack that runs by itself");
          }
        }
      }

      /// The quasi-static saw (PST/Saw = quasi-static): static saw steps from the state u (the
      /// model's committed states) until equilibrium is lost, then the cut with which it was lost
      /// and the explicit dynamics from that state at rest. Called at the start and whenever the
      /// dynamics after a loss of equilibrium settle without a running crack.
      void saw_statically(QuasiStaticSolver<dim> &solver, typename SnowpackModel<dim>::VectorType &u)
      {
        const QuasiStaticSawEnd end = quasi_static_saw(model_, solver, u, log_, [](double, const CrackFronts &, unsigned int) {});
        cut_ = end.lost_at.value_or(end.cut);
        model_.set_cut(cut_);
        static_bracket_ = {end.cut, cut_};
        ++static_phases_;
        log_.line("[fem] quasi-static saw: ", end.reason, "; explicit dynamics from the cut ", format_number(cut_, 4), " m");
      }

      /// After dynamics that settled: equilibrium at the settled state, then the saw again.
      void saw_on()
      {
        log_.line("[fem] t = ", format_number(dynamics_->time(), 4), " s: the event at the cut ", format_number(cut_, 4),
                  " m settled without a running crack; the quasi-static saw goes on");
        typename SnowpackModel<dim>::VectorType u = dynamics_->displacement();
        QuasiStaticSolver<dim> solver(model_);
        const NewtonResult settled = solver.solve(u, 1.0);
        if (!settled.converged)
        {
          // Still no equilibrium: the dynamics go on (the arrest check runs again).
          log_.line("[fem] no equilibrium at the settled state yet (", settled.failure, "); the dynamics continue");
          return;
        }
        saw_statically(solver, u);
        const Energies e = model_.energies();
        const Energies d = dynamics_->energies();
        dynamics_->restart_at_rest(u, e.elastic + e.dissipated + e.removed_by_saw + d.viscous);
        saw_stopped_ = dynamics_->time();
      }

      void finish(Outcome outcome, const std::string &what)
      {
        outcome_ = outcome;
        end_time_ = dynamics_->time();
        log_.line("[fem] t = ", format_number(dynamics_->time(), 4), " s: ", what);
      }

      std::string layer_label(unsigned int layer) const { return layer_of(scene_.snowpack, layer).label; }

      /// The site of `found` (a non-finite value) from the model: the first non-finite node, or only
      /// the description where no displacement, velocity or force is (the time step alone).
      Json non_finite_site(const std::string &found) const
      {
        Json site = dynamics_->non_finite_location();
        if (site.is_null())
          return failure_site(found + " (every displacement, velocity and force is finite)");
        site["description"] = found + ": " + site["description"].get<std::string>();
        return site;
      }

      /// The failure `what` at `where` (a failure site: a cell, a node) now: summary.json's
      /// "failure" gets both and the step, time, time step and cut length; the series written up to
      /// here are kept.
      NumericalFailure failure(const std::string &what, const Json &where) const
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
                                  std::to_string(dynamics.steps()) + ", cut " + format_number(cut_, 4) +
                                  " m): " + where.value("description", std::string()),
                                details);
      }

      void record()
      {
        const ExplicitDynamics<dim> &dynamics = *dynamics_;
        if (!dynamics.finite())
          throw failure("non-finite value", non_finite_site("a non-finite displacement or velocity"));
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
                                   critical_cut_.value_or(-1.), critical_time_.value_or(-1.), saw_stopped_.value_or(-1.),
                                   free_end_time_.value_or(-1.), free_end_length_, largest_tension_ratio_,
                                   static_bracket_ ? static_bracket_->first : -1., static_bracket_ ? static_bracket_->second : -1.,
                                   double(static_phases_)})
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
        json_in.close();
        // A torn or foreign index is refused naming it (never a JSON library's text).
        const std::string restart = "Run again without --resume and with --overwrite to start the run afresh.";
        const Json info = interpret_json_file(json_file, "an FE checkpoint's index", [](const Json &j) {
          j.at("resume_key_sha256").get<std::string>();
          j.at("ranks").get<unsigned int>();
          j.at("step").get<unsigned long>();
          return j;
        }, restart);
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
          double critical_cut = 0, critical_time = 0, saw_stopped = 0, free_end_time = 0, static_low = 0, static_high = 0,
                 static_phases = 0;
          for (double *value : {&cut_, &next_series_, &next_field_, &wall_, &fronts_.crack_tip, &fronts_.touchdown,
                                &critical_cut, &critical_time, &saw_stopped, &free_end_time, &free_end_length_,
                                &largest_tension_ratio_, &static_low, &static_high, &static_phases})
            checkpoint::read(in, *value);
          static_phases_ = static_cast<unsigned int>(static_phases);
          if (static_low >= 0)
            static_bracket_ = std::make_pair(static_low, static_high);
          if (critical_cut >= 0)
            critical_cut_ = critical_cut, critical_time_ = critical_time;
          if (saw_stopped >= 0)
            saw_stopped_ = saw_stopped;
          if (free_end_time >= 0)
            free_end_time_ = free_end_time;
          series_.replace_values([&](const TimeSeries::Column &column) {
            std::vector<double> values;
            checkpoint::read_vector(in, values, -1, "time series " + column.name);
            return values;
          });
          fields_.load(in);
        }
        catch (const checkpoint::Mismatch &e)
        {
          // The index matched this scene, so a file that does not read back is torn or foreign.
          throw UnusableOutputFile(rank_file(step, Utilities::MPI::this_mpi_process(comm_)),
                                   "cannot be read back as this scene's checkpoint (" + std::string(e.what()) + ")",
                                   restart);
        }
        log_.line("[fem] resumed at step ", step, ", t = ", format_number(dynamics_->time(), 4), " s");
      }

      Json results()
      {
        const ExplicitDynamics<dim> &dynamics = *dynamics_;
        const double dx = scene_.pst.column_length / model_.n_columns();
        const double lead = self_propagation_lead(scene_);
        const bool reached_end = outcome_ == Outcome::end;
        // The saw's critical cut is bracketed by the rows: the crack ran by itself from a cut
        // between the last row before the detection at which its tip was still at the saw and
        // the cut at the detection (which waits for a lead of one slab thickness, so that a tip
        // that only jumps ahead of the saw by a few elements is not taken for a running crack).
        // "At the saw" is within the weak layer's thickness (at least one element, the tip's
        // resolution): a length of the snowpack, not of the mesh. Two element lengths, as
        // before, made the answer the mesh's: the lead of the tip over the saw grows smoothly
        // with the cut, and the same curve read at 4, 2 and 1 cm gave 0.245, 0.215 and 0.197 m
        // on 2, 1 and 0.5 cm elements; read at the layer's 2 cm, 0.225, 0.215 and 0.212 m
        // (docs/work_precision.md). The lower end is reported; the critical cut as practice
        // defines it (independent of the saw speed and of this length) is the quasi-static PST's
        // and the bisection's (docs/fem.md "The critical cut").
        const auto &t = series_.values("time"), &tip = series_.values("crack_tip"),
                   &td = series_.values("touchdown_front"), &cuts = series_.values("cut_length");
        std::optional<double> critical_cut = critical_cut_, critical_time = critical_time_;
        const double at_the_saw = std::max(scene_.snowpack.weak_layer.thickness, dx);
        if (critical_time_)
          for (std::size_t k = 0; k < t.size() && t[k] <= *critical_time_; ++k)
            if (tip[k] - cuts[k] <= at_the_saw)
            {
              critical_cut = cuts[k];
              critical_time = t[k];
            }
        // Steady propagation speed: least-squares slope of the tip position over the rows where
        // the crack runs by itself (from its detection on: the saw no longer drives it) with the
        // tip in the middle half of the distance it ran by itself (from its position at the
        // detection to the column end, less a far end that failed by itself, or to where it
        // stopped). Touchdown distance: median of tip − touchdown front there.
        std::optional<double> speed, touchdown;
        if (critical_time_)
        {
          std::size_t detected = 0;
          while (detected + 1 < t.size() && t[detected] < *critical_time_)
            ++detected;
          const double from = tip[detected],
                       to = reached_end ? scene_.pst.column_length - free_end_length_ : fronts_.crack_tip;
          const double low = from + 0.25 * (to - from), high = from + 0.75 * (to - from);
          double st = 0, sx = 0, stt = 0, stx = 0, n = 0;
          std::vector<double> behind;
          for (std::size_t k = 0; k < t.size(); ++k)
            if (t[k] >= *critical_time_ && tip[k] >= low && tip[k] <= high)
            {
              st += t[k], sx += tip[k], stt += t[k] * t[k], stx += t[k] * tip[k], n += 1;
              if (td[k] > 0)
                behind.push_back(tip[k] - td[k]);
            }
          // The tip is read per element: its middle half must span two elements for a slope (a
          // crack that stopped within four elements of where it began to run by itself has no speed).
          if (n >= 3 && n * stt - st * st > 0 && high - low >= 2 * dx * (1 - 1e-9))
            speed = (n * stx - st * sx) / (n * stt - st * st);
          if (!behind.empty())
          {
            std::nth_element(behind.begin(), behind.begin() + behind.size() / 2, behind.end());
            touchdown = behind[behind.size() / 2];
          }
        }
        auto optional = [](const std::optional<double> &v) { return v ? Json(*v) : Json(nullptr); };
        Json warnings = Json::array();
        Json r;
        r["analysis"] = scene_.analysis.type->name;
        r["mesh"] = mesh_json(model_, comm_);
        r["critical_cut_length_m"] = optional(critical_cut);
        r["critical_cut_bracket_m"] = critical_cut ? Json::array({*critical_cut, *critical_cut_}) : Json(nullptr);
        switch (scene_.pst.saw)
        {
          case SawTest::Saw::quasi_static:
            // The longest cut in equilibrium and the one without: the crack runs from a cut in between.
            r["critical_cut_method"] = "quasi-static saw, handed over to explicit dynamics when equilibrium is lost";
            r["quasi_static_saw_phases"] = static_phases_;
            if (critical_cut && static_bracket_)
              r["critical_cut_bracket_m"] = Json::array({static_bracket_->first, static_bracket_->second});
            break;
          case SawTest::Saw::advancing:
            r["critical_cut_method"] = "advancing saw: its position when the crack ran by itself (depends on the saw speed)";
            break;
          default:
            r["critical_cut_method"] = "fixed cut";
            break;
        }
        if (preloaded_cut_)
          r["trial"] = {{"cut_length_m", *preloaded_cut_},
                        {"gravity_ramp_failed_at_load_factor", ramp_lost_at_ ? Json(*ramp_lost_at_) : Json(nullptr)}};
        r["self_propagation_lead_m"] = lead;
        r["gaume2017"] = gaume2017_reference(scene_.snowpack);
        r["collapsed_layer_under_the_slab"] = collapse_under_the_slab(scene_);
        if (const Json &c = r["collapsed_layer_under_the_slab"]; c.is_object() && !c["slab_crushes_the_collapsed_layer"].get<bool>())
          warnings.push_back("the slab cannot crush the collapsed weak layer: at its residual strength R p0 = " +
                             format_number(c["residual_strength_Pa"].get<double>(), 4) + " Pa it carries " +
                             format_number(c["residual_confined_flow_stress_Pa"].get<double>(), 4) +
                             " Pa in confined compaction, more than the slab's normal traction " +
                             format_number(c["normal_traction_Pa"].get<double>(), 4) +
                             " Pa, so a crack can run only as the layer's softening front, without collapse or touchdown");
        r["flexural_wave"] = flexural_wave_reference(scene_.snowpack);
        r["saw_speed_m_per_s"] = scene_.pst.saw == SawTest::Saw::advancing ? Json(scene_.pst.saw_speed) : Json(nullptr);
        r["outcome"] = pst_outcome_names().name(outcome_);
        switch (outcome_)
        {
          case Outcome::running:
          {
            const double moved = tip.empty() ? 0. : tip.back() - tip[std::max<std::ptrdiff_t>(
                                                                 0, std::ptrdiff_t(tip.size()) - 1 -
                                                                      std::ptrdiff_t(scene_.analysis.arrest_duration /
                                                                                     scene_.output.series_interval))];
            std::string warning = "the PST has no outcome at the end time " + format_number(dynamics.time(), 4) + " s: ";
            if (critical_cut_)
              warning += "the crack runs by itself, its tip at " + format_number(fronts_.crack_tip, 4) + " m of " +
                         format_number(scene_.pst.column_length, 4) + " m";
            else if (scene_.pst.saw == SawTest::Saw::quasi_static)
              warning += "the quasi-static saw is at " + format_number(cut_, 4) + " m after " +
                         std::to_string(static_phases_) + " losses of equilibrium, each followed for at least "
                         "Arrest duration";
            else if (!saw_stopped_)
              warning += "the saw is still cutting (at " + format_number(cut_, 4) + " m)";
            else
              warning += "the tip still moves (" + format_number(moved, 3) + " m over the last Arrest duration)";
            warning += "; increase Analysis/Explicit/End time [s]";
            if (speed && *speed > 0 && critical_cut_)
              warning += " to at least " +
                         format_number(dynamics.time() + (scene_.pst.column_length - fronts_.crack_tip) / *speed +
                                         scene_.analysis.arrest_duration, 3) +
                         " s (the rest of the column at " + format_number(*speed, 3) + " m/s, then the arrest check)";
            warnings.push_back(warning);
            log_.line("[fem] warning: ", warning);
            break;
          }
          default:
            break;
        }
        r["arrest_detection"] = {{"speed_m_per_s", scene_.analysis.arrest_speed},
                                 {"duration_s", scene_.analysis.arrest_duration}};
        r["arrest_position_m"] = outcome_ == Outcome::arrest ? Json(arrest_position_) : Json(nullptr);
        r["arrest_time_s"] = outcome_ == Outcome::arrest ? Json(arrest_time_) : Json(nullptr);
        if (slab_fracture_)
        {
          const SlabFracture &f = *slab_fracture_;
          Json position = Json::array();
          for (unsigned int d = 0; d < dim; ++d)
            position.push_back(f.tension.position[d]);
          r["slab_fracture"] = {{"time_s", f.time},
                                {"time_resolution_s", scene_.output.series_interval},
                                {"cut_length_m", f.cut},
                                {"layer", layer_label(f.tension.layer)},
                                {"position_m", position},
                                {"fibre_stress_Pa", f.tension.stress},
                                {"tensile_strength_Pa", f.tension.strength},
                                {"crack_running", f.crack_running}};
        }
        else
          r["slab_fracture"] = nullptr;
        r["largest_slab_tension_over_strength"] = largest_tension_ratio_;
        r["slab_tensile_strength"] = slab_strengths_json();
        r["free_end_failure"] = free_end_time_ ? Json{{"time_s", *free_end_time_}, {"length_m", free_end_length_}}
                                               : Json(nullptr);
        r["warnings"] = warnings;
        r["time_crack_runs_s"] = optional(critical_time);
        r["time_reached_end_s"] = reached_end ? optional(end_time_) : Json(nullptr);
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

      /// σ_t of every slab layer and where it comes from.
      Json slab_strengths_json() const
      {
        Json layers = Json::array();
        for (const Layer &layer : scene_.snowpack.slab_layers)
          layers.push_back({{"layer", layer.label},
                            {"tensile_strength_Pa", layer.tensile_strength},
                            {"source", layer.tensile_strength_from_density ? "Sigrist 2006 density law" : "scene"}});
        return layers;
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
    if (scene.pst.saw == SawTest::Saw::bisection || scene.pst.saw == SawTest::Saw::practice)
      return run_critical_cut_search(scene, options, comm, [comm](const SnowpackScene &s, const SnowpackRunOptions &o,
                                                                  std::optional<double> preloaded_cut) {
        return DynamicPst<dim>(s, o, comm, preloaded_cut).run();
      });
    return DynamicPst<dim>(scene, options, comm).run();
  }

  namespace
  {
    /// subsection Analysis/Explicit: each entry declared and read from this one table.
    const std::vector<BoundEntry<Analysis>> &explicit_entries()
    {
      static const std::vector<BoundEntry<Analysis>> table = {
        {"End time [s]", "1", &Analysis::end_time, 0, no_upper_bound,
         "t_end: simulated time after the saw starts. Units: s."},
        {"CFL safety factor", "0.5", &Analysis::cfl_safety, 0.01, 1,
         "C: safety factor of the explicit time step dt = C min(h / c_p). Dimensionless."},
        {"Linear bulk viscosity", "0.06", &Analysis::linear_bulk_viscosity, 0, 10,
         "c_1: linear coefficient of the bulk viscosity pressure p_v = rho h (c_2^2 h e_v'^2 - c_1 "
         "c e_v'). Dimensionless."},
        {"Quadratic bulk viscosity", "1.2", &Analysis::quadratic_bulk_viscosity, 0, 10,
         "c_2: quadratic coefficient of the bulk viscosity pressure (acts in compression only). "
         "Dimensionless."},
        {"Mass damping [1/s]", "0", &Analysis::mass_damping, 0, no_upper_bound,
         "alpha_M: mass-proportional damping, force -alpha_M M v. Units: 1/s."},
        {"Arrest speed [m/s]", "0.5", &Analysis::arrest_speed, 0, no_upper_bound,
         "v_arr: once the saw has stopped, the crack has arrested (Arr), or never started (no "
         "propagation), when its tip has advanced less than v_arr t_arr over the last t_arr; the "
         "run then ends. Units: m/s."},
        {"Arrest duration [s]", "0.1", &Analysis::arrest_duration, 0, no_upper_bound,
         "t_arr: the time over which the tip must stay slower than v_arr (see Arrest speed); "
         "Output/Series interval must be at most t_arr / 10. Units: s."}};
      return table;
    }
  } // namespace

  AnalysisType dynamic_pst_analysis()
  {
    return {
      "explicit dynamics", "dynamic PST (explicit central differences)",
      "gravity equilibrium, then the saw and crack propagation in time (explicit central differences).",
      /* yielding_weak_layer = */ true, /* time_integration = */ true,
      [](ParameterHandler &prm) {
        prm.enter_subsection("Explicit");
        declare_entries(prm, explicit_entries());
        prm.leave_subsection();
      },
      [](ParameterHandler &prm, SnowpackScene &scene) {
        Analysis &analysis = scene.analysis;
        prm.enter_subsection("Explicit");
        parse_entries(prm, explicit_entries(), analysis);
        prm.leave_subsection();
      },
      [](const SnowpackScene &scene, Problems &problems) {
        if (!(scene.analysis.end_time > 0))
          problems.add("Analysis/Explicit/End time [s]", "must be > 0");
        if (!(scene.analysis.arrest_speed > 0))
          problems.add("Analysis/Explicit/Arrest speed [m/s]", "must be > 0");
        if (!(scene.analysis.arrest_duration > 0))
          problems.add("Analysis/Explicit/Arrest duration [s]", "must be > 0");
        else if (!(scene.output.series_interval <= scene.analysis.arrest_duration / 10 * (1 + 1e-12)))
          problems.add("Output/Series interval [s]",
                       "must be <= Analysis/Explicit/Arrest duration [s] / 10 = " +
                         format_number(scene.analysis.arrest_duration / 10) + " (is " +
                         format_number(scene.output.series_interval) +
                         "): the arrest is read from the crack tip's rows over that duration");
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
