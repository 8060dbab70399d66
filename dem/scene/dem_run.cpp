#include "dem/scene/dem_run.h"

#include "dem/io/state_hdf5.h"
#include "dem/io/state_vtp.h"
#include "dem/lab/lab_protocol.h"
#include "dem/lab/measurements.h"
#include "dem/scene/failure_analysis.h"
#include "dem/scene/history_columns.h"
#include "dem/scene/model.h"
#include "util/input_error.h"
#include "util/stop_signals.h"
#include "util/phase_timer.h"
#include "util/progress.h"
#include "util/run_summary.h"
#include "util/time_series.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <numeric>
#include <optional>
#include <sstream>

namespace anticrack::dem
{
  namespace fs = std::filesystem;

  namespace
  {
    /// Files of a run inside its output directory.
    struct OutputFiles
    {
      fs::path directory;
      [[nodiscard]] fs::path summary() const { return directory / "summary.json"; }
      [[nodiscard]] fs::path history() const { return directory / "history.h5"; }
      [[nodiscard]] fs::path checkpoint() const { return directory / "checkpoint.h5"; }
      [[nodiscard]] fs::path checkpoint_info() const { return directory / "checkpoint.json"; }
      [[nodiscard]] fs::path snapshots() const { return directory / "snapshots"; }
      [[nodiscard]] fs::path paraview() const { return directory / "paraview"; }
      /// Everything a run may leave behind, for --overwrite and the "already used" check.
      [[nodiscard]] std::vector<fs::path> all() const
      {
        return {summary(), history(), checkpoint(), checkpoint_info(), snapshots(), paraview()};
      }
    };

    std::string numbered(const std::string &stem, Index step, const std::string &extension)
    {
      char digits[32];
      std::snprintf(digits, sizeof digits, "%06lld", static_cast<long long>(step));
      return stem + "_" + digits + extension;
    }

    bool multiple_of(Index step, Index interval) { return interval > 0 && step % interval == 0; }

    struct BondCounts
    {
      Index intact = 0, tension = 0, shear = 0;
    };

    BondCounts count_bonds(const dem::BondList &bonds)
    {
      BondCounts c;
      for (const auto s : bonds.state)
        (s == dem::BondState::intact ? c.intact : s == dem::BondState::broken_tension ? c.tension : c.shear)++;
      return c;
    }

    void print_framed(std::ostream &out, const std::string &title, const std::string &body)
    {
      const std::string rule(78, '-');
      out << "\n" << rule << "\n" << title << "\n\n" << body << "\n" << rule << "\n";
    }
  } // namespace

  // ---------------------------------------------------------------------------------------------
  // The run of one scene: the public face is the constructor, prepare() and run(); the private
  // functions follow the pipeline (history, outputs, checkpoints, summary).
  class DemRun
  {
  public:
    DemRun(const SceneParameters &scene, std::unique_ptr<DemModel> model, const RunOptions &options);

    /// Checks the output directory and, with --resume, loads the checkpoint. Writes nothing;
    /// throws InputError.
    void prepare();

    /// Creates the output directory, runs to DEM/Steps and writes every output. Returns the exit code.
    int run();

    /// The summary and the failure analysis that run() wrote, with its exit code.
    [[nodiscard]] DemRunRecord record(int exit_code) const { return {exit_code, summary_, failure_analysis_}; }

  private:
    void declare_history_columns();
    void record_history();
    [[nodiscard]] double inertial_number(const dem::Mat3 &stress) const;
    /// The largest inertial number before the peak of q (0: the actuators did not move); above
    /// quasi_static_inertial_number the run is flagged as not quasi-static.
    [[nodiscard]] double largest_inertial_number_before_peak() const;
    double initial_sample_height_ = 0; ///< z extent of the spheres at the start [m] (loading strain)
    /// Thickness of the deformable layer between the fixed base and the clump, at the start [m].
    [[nodiscard]] double layer_thickness() const;
    double initial_layer_thickness_ = 0;
    double mean_particle_diameter_ = 0; ///< 2 x the mean radius of every sphere at the start [m]
    /// The fixed base and the clump when the scene has both: rigid platens, not part of the specimen
    /// whose Love-Weber stress the history records (dem/lab/measurements.h); empty otherwise.
    dem::PlatenSpheres platens_;
    /// The volume of that stress: the base area times the platens' current separation
    /// (dem::platen_separation), or without platens the volume the spheres occupy.
    [[nodiscard]] double stress_volume() const;
    void write_history();
    void write_snapshot();
    void write_checkpoint();
    void write_outputs(bool first, bool last);
    void report_progress();
    void report_quiet_progress();
    std::chrono::steady_clock::time_point last_quiet_report_ = std::chrono::steady_clock::now();

    [[nodiscard]] Json summary(const std::string &status, const std::string &message) const;
    Json summary_; ///< as written to summary.json
    std::optional<dem::TestFailureAnalysis> failure_analysis_; ///< of a clump-driven test, once the run ended
    void print_start() const;
    void print_end(double wall) const;

    // --- scene and model
    const SceneParameters &scene_;
    std::unique_ptr<DemModel> model_;
    std::unique_ptr<dem::LabProtocol> protocol_; ///< the test's loading programme, if any
    dem::DemSystem &system_;
    RunOptions options_;
    OutputFiles files_;
    Index total_steps_;

    // --- run state of this invocation
    std::optional<Index> resumed_from_step_;
    Index first_step_ = 0;
    double wall_seconds_ = 0;
    Index last_history_step_ = -1, last_snapshot_step_ = -1, last_checkpoint_step_ = -1;
    Index snapshots_written_ = 0, checkpoints_written_ = 0;
    bool protocol_finished_ = false;
    /// The protocol asked for a history row at this step's control call.
    bool history_row_due_ = false;
    /// The protocol, not Output/History interval [steps], says when the history takes a row.
    [[nodiscard]] bool sampled_by_protocol() const { return protocol_ && protocol_->samples_history(); }

    // --- time series
    TimeSeries history_;

    // --- where the time goes (summary.json timing.phases)
    PhaseTimer timer_;

    // --- console and ParaView
    std::optional<ProgressReporter> progress_;
    std::optional<dem::io::PvdCollection> pvd_particles_, pvd_bonds_;
  };

  DemRun::DemRun(const SceneParameters &scene, std::unique_ptr<DemModel> model, const RunOptions &options)
    : scene_(scene), model_(std::move(model)), system_(model_->system), options_(options),
      files_{fs::path(options.output_directory)}, total_steps_(scene.dem.steps)
  {
    timer_.add("sample and model", model_->build_seconds);
    declare_history_columns();
    const auto [low, high] = dem::sphere_extent(system_.particles, 2);
    initial_sample_height_ = high - low;
    initial_layer_thickness_ = layer_thickness();
    // The grains' size: the length the snow units scale the layer by (coupling/snow_units.h).
    double radius_sum = 0;
    for (const double r : system_.particles.radius)
      radius_sum += r;
    mean_particle_diameter_ = system_.particles.radius.empty() ? 0 : 2 * radius_sum / system_.particles.radius.size();
    if (!model_->fixed_particles.empty() && model_->clump >= 0)
    {
      platens_.assign(system_.particles.size(), dem::Platen::none);
      for (const Index p : model_->fixed_particles)
        platens_[p] = dem::Platen::base;
      for (const Index p : system_.clumps[model_->clump].members)
        platens_[p] = dem::Platen::top;
    }
    protocol_ = make_lab_protocol(scene_, *model_);
  }

  double DemRun::stress_volume() const
  {
    return platens_.empty() ? dem::sample_volume(system_) : model_->base_area * dem::platen_separation(system_, platens_);
  }

  double DemRun::layer_thickness() const
  {
    // The deformable layer between the two rigid parts: from the highest centre of the fixed base
    // to the lowest centre of the clump (bonds and contacts act between centres). Without a base
    // or a clump, the whole sample.
    if (model_->fixed_particles.empty() || model_->clump < 0)
      return initial_sample_height_;
    double base_top = -std::numeric_limits<double>::infinity(), clump_bottom = std::numeric_limits<double>::infinity();
    for (const Index p : model_->fixed_particles)
      base_top = std::max(base_top, system_.particles.position[p].z());
    for (const Index p : system_.clumps[model_->clump].members)
      clump_bottom = std::min(clump_bottom, system_.particles.position[p].z());
    return clump_bottom - base_top;
  }

  void DemRun::declare_history_columns()
  {
    TimeSeries &h = history_;
    h.add_column(history_column::time, "s", "simulated time t");
    h.add_column(history_column::step, "-", "time step number", true);
    h.add_column("dt", "s", "time step dt in use");
    h.add_column("kinetic_energy", "J", "E_kin = sum 1/2 m v(n-1/2).v(n+1/2) + rotation, spheres and clumps");
    h.add_column("elastic_energy_contacts", "J", "elastic energy stored in contacts (with walls)");
    h.add_column("elastic_energy_bonds", "J", "elastic energy stored in intact parallel bonds");
    h.add_column("gravity_potential_energy", "J", "-sum m g.x");
    h.add_column("dissipated_friction", "J", "dissipated by Coulomb sliding (accumulated)");
    h.add_column("dissipated_viscous", "J", "dissipated by contact dashpots (accumulated)");
    h.add_column("dissipated_local_damping", "J", "dissipated by Cundall local damping (accumulated)");
    h.add_column("dissipated_bond_breakage", "J", "elastic energy released by broken bonds (accumulated)");
    h.add_column("dissipated_energy", "J", "sum of the four dissipated energies");
    h.add_column("external_work", "J", "work of walls, clump forces and fixed spheres (accumulated)");
    h.add_column("energy_balance_error", "J",
                 "stored + dissipated - external work, minus its initial value (0 for exact bookkeeping)");
    h.add_column("intact_bonds", "-", "number of intact bonds", true);
    h.add_column("broken_bonds_tension", "-", "bonds broken by sigma_bar >= sigma_bar_c", true);
    h.add_column("broken_bonds_shear", "-", "bonds broken by tau_bar >= c_bar - sigma_bar tan phi_bar", true);
    for (const auto &wall : system_.walls)
    {
      Eigen::Index axis = 0;
      wall.normal.cwiseAbs().maxCoeff(&axis);
      h.add_column("wall_" + wall.name + "_position", "m",
                   std::string("coordinate ") + "xyz"[axis] + " of wall " + wall.name);
      h.add_column("wall_" + wall.name + "_normal_stress", "Pa",
                   "compressive normal stress on wall " + wall.name + ", -F.n / A");
    }
    if (!model_->fixed_particles.empty())
    {
      h.add_column(history_column::base_normal_stress, "Pa",
                   "compressive stress on the fixed base, -sum f_z / A with A the x-y area of the domain");
      h.add_column(history_column::base_shear_stress, "Pa", "shear stress on the fixed base, sum f_x / A");
    }
    if (model_->clump >= 0)
    {
      for (const char a : {'x', 'y', 'z'})
        h.add_column(history_column::clump_displacement(a), "m",
                     "displacement of the clump's centre of mass since the start (not wrapped)");
      for (const char a : {'x', 'y', 'z'})
        h.add_column(history_column::clump_velocity(a), "m/s", "clump velocity (half step)");
      for (const char *a : {"x", "y", "z"})
        h.add_column(std::string("clump_applied_force_") + a, "N", "applied force F(t) on the clump");
      h.add_column("clump_normal_stress", "Pa", "-F_z(t) / A with A the x-y area of the domain");
      h.add_column("clump_shear_stress", "Pa", "F_x(t) / A with A the x-y area of the domain");
      h.add_column("clump_kinetic_energy", "J", "1/2 m |v|^2 + 1/2 w.I w of the clump (Ritter et al.'s (2020) failure window)");
      h.add_column(history_column::normal_strain, "-", "-u_z / H0: clump displacement over the initial sample height, compression positive");
      h.add_column(history_column::shear_strain, "-", "u_x / H0: clump displacement along x over the initial sample height");
    }
    // Micro-to-macro measures (docs/physics.md §1.5) of the specimen: between the fixed base and the
    // clump when the scene has both, else of every sphere (dem/lab/measurements.h).
    const bool platens = !model_->fixed_particles.empty() && model_->clump >= 0;
    for (const char *c : {"xx", "yy", "zz", "xy", "xz", "yz"})
      h.add_column(history_column::love_stress(c), "Pa",
                   "Love-Weber stress sigma_" + std::string(c) + " (tension positive) over sample_volume" +
                     (platens ? ", of the spheres between the base and the clump (pairs within a platen left out)" : ""));
    h.add_column("mean_pressure", "Pa", "p = -tr(sigma)/3 of the Love-Weber stress (compression positive)");
    h.add_column(history_column::von_mises_stress, "Pa", "q = sqrt(3/2 s:s) of the Love-Weber stress");
    h.add_column("sample_volume", "m^3",
                 platens ? "base area times the separation of the platens' lines of action (the heights of the base's "
                           "and the clump's sphere centres weighted by the z-forces they get from the specimen)"
                         : "box length along periodic axes times the spheres' extent along open ones");
    h.add_column("coordination_number", "-", "2 N_c / N over touching contacts and intact bonds (a pair once)");
    for (const char *c : {"xx", "yy", "zz"})
      h.add_column(std::string("fabric_") + c, "-", "fabric tensor C_" + std::string(c) + " = <n n> over contacts and bonds");
    h.add_column("broken_bond_fraction", "-", "broken bonds / all bonds");
    h.add_column(history_column::inertial_number, "-",
                 "I = strain rate x mean diameter x sqrt(rho / s), strain rate = actuator speed / sample height, "
                 "s = sqrt(sigma:sigma / 3) the Love-Weber stress magnitude (= |p| under isotropic stress)");
  }

  double DemRun::inertial_number(const dem::Mat3 &stress) const
  {
    // I = gamma_dot d sqrt(rho / P) (Ritter et al. 2020), with the strain rate taken as the actuator's speed
    // (clump or fastest wall) over the sample height. The confining stress P of shear flows is
    // generalised to any loading angle as the stress magnitude s = sqrt(sigma:sigma / 3), which is
    // |p| under isotropic stress and does not vanish in pure shear, where p does.
    const auto &particles = system_.particles;
    if (particles.size() == 0)
      return 0;
    double speed = model_->clump >= 0 ? system_.clumps[model_->clump].velocity.norm() : 0.0;
    for (const auto &wall : system_.walls)
      speed = std::max(speed, wall.velocity.norm());
    const auto [low, high] = dem::sphere_extent(particles, 2);
    if (speed == 0 || high <= low)
      return 0;
    const double magnitude = std::sqrt(stress.squaredNorm() / 3);
    if (magnitude == 0)
      return std::numeric_limits<double>::infinity();
    const double diameter =
      2 * std::accumulate(particles.radius.begin(), particles.radius.end(), 0.0) / particles.size();
    const double density = system_.materials[particles.material_id[0]].density;
    return speed / (high - low) * diameter * std::sqrt(density / magnitude);
  }

  double DemRun::largest_inertial_number_before_peak() const
  {
    // As the campaign judges its tests: up to the peak of q, over the rows where q is at least half
    // of it (failure_analysis.h). A run whose actuators do not move records I = 0 throughout.
    const auto *q = history_.find(history_column::von_mises_stress);
    const auto *inertial = history_.find(history_column::inertial_number);
    if (q == nullptr || inertial == nullptr || q->values.empty())
      return 0;
    const std::vector<double> &steps = history_.find(history_column::step)->values;
    const std::size_t peak = std::max_element(q->values.begin(), q->values.end()) - q->values.begin();
    return max_inertial_number_before_failure(steps, q->values, inertial->values, steps[peak], q->values[peak]);
  }

  void DemRun::record_history()
  {
    if (last_history_step_ == system_.step_count)
      return;
    const dem::EnergyLedger e = system_.energy();
    const BondCounts bonds = count_bonds(system_.bonds);
    std::vector<double> row = {system_.time,
                               static_cast<double>(system_.step_count),
                               system_.dt,
                               e.kinetic,
                               e.elastic_contacts,
                               e.elastic_bonds,
                               e.gravity_potential,
                               e.friction,
                               e.viscous,
                               e.local_damping,
                               e.bond_breakage,
                               e.dissipated(),
                               e.external_work,
                               e.balance() - system_.initial_balance,
                               static_cast<double>(bonds.intact),
                               static_cast<double>(bonds.tension),
                               static_cast<double>(bonds.shear)};
    for (const auto &wall : system_.walls)
    {
      row.push_back(wall.point.dot(wall.normal.cwiseAbs()));
      row.push_back(wall.normal_stress() + 0.0); // + 0.0 turns -0 into 0
    }
    if (!model_->fixed_particles.empty())
    {
      const Vec3 reaction = dem::total_force(system_.particles, model_->fixed_particles);
      row.push_back(-reaction[2] / model_->base_area);
      row.push_back(reaction[0] / model_->base_area);
    }
    if (model_->clump >= 0)
    {
      const dem::Clump &clump = system_.clumps[model_->clump];
      const Vec3 force = clump.applied_force(system_.time);
      for (int a = 0; a < 3; ++a)
        row.push_back(clump.displacement[a]);
      for (int a = 0; a < 3; ++a)
        row.push_back(clump.velocity[a]);
      for (int a = 0; a < 3; ++a)
        row.push_back(force[a]);
      row.push_back(-force[2] / model_->base_area);
      row.push_back(force[0] / model_->base_area);
      const Vec3 spin = clump.angular_velocity;
      row.push_back(0.5 * clump.mass * clump.velocity.squaredNorm() +
                    0.5 * spin.dot(clump.inverse_inertia_world().inverse() * spin));
      row.push_back(-clump.displacement[2] / initial_sample_height_);
      row.push_back(clump.displacement[0] / initial_sample_height_);
    }
    const double volume = stress_volume();
    const dem::Mat3 stress = volume > 0 ? dem::love_weber_stress(system_, volume, true, platens_) : dem::Mat3::Zero();
    for (const auto &[r, c] : {std::pair{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}})
      row.push_back(stress(r, c));
    const double p = dem::mean_pressure(stress);
    row.push_back(p);
    row.push_back(dem::von_mises_stress(stress));
    row.push_back(volume);
    const dem::Fabric fabric = dem::contact_and_bond_fabric(system_);
    row.push_back(fabric.coordination);
    for (int a = 0; a < 3; ++a)
      row.push_back(fabric.tensor(a, a));
    row.push_back(dem::broken_bond_fraction(system_.bonds));
    row.push_back(inertial_number(stress));
    history_.append(row);
    last_history_step_ = system_.step_count;
  }

  void DemRun::write_history()
  {
    history_.write(files_.history().string(),
                   {{"format", "anticrack-history"},
                    {"scene_file", scene_.file},
                    {"parameters_sha256", scene_.parameters_sha256},
                    {"anticrack_version", version_info()["anticrack"].get<std::string>()}});
  }

  void DemRun::write_snapshot()
  {
    if (last_snapshot_step_ == system_.step_count)
      return;
    const Index step = system_.step_count;
    dem::io::write_snapshot((files_.snapshots() / numbered("snapshot", step, ".h5")).string(), system_);
    if (pvd_particles_)
    {
      const fs::path particles = files_.paraview() / numbered("particles", step, ".vtp");
      const fs::path bonds = files_.paraview() / numbered("bonds", step, ".vtp");
      dem::io::write_particles_vtp(particles.string(), system_);
      dem::io::write_bonds_vtp(bonds.string(), system_);
      pvd_particles_->add(system_.time, particles.string());
      pvd_bonds_->add(system_.time, bonds.string());
    }
    last_snapshot_step_ = step;
    ++snapshots_written_;
  }

  void DemRun::write_checkpoint()
  {
    if (last_checkpoint_step_ == system_.step_count)
      return;
    // History first: if the run dies before the checkpoint is renamed into place, the older
    // checkpoint is still valid and resuming drops the extra history rows.
    write_history();
    dem::io::write_checkpoint(files_.checkpoint().string(), system_);
    Json info;
    info["format"] = "anticrack-checkpoint-info";
    info["version"] = 1;
    info["scene"] = scene_info(scene_);
    info["step"] = system_.step_count;
    info["time"] = system_.time;
    if (protocol_)
      info["protocol_state"] = protocol_->state();
    write_json_atomically(files_.checkpoint_info().string(), info);
    last_checkpoint_step_ = system_.step_count;
    ++checkpoints_written_;
  }

  void DemRun::write_outputs(const bool first, const bool last)
  {
    const auto phase = timer_.scope("output");
    const auto &o = scene_.output;
    const Index step = system_.step_count;
    // A protocol that samples its own curve (dem::LabProtocol::samples_history) takes the rows.
    if (first || last || (sampled_by_protocol() ? history_row_due_ : multiple_of(step, o.history_interval)))
      record_history();
    history_row_due_ = false;
    if (o.snapshot_interval > 0 && (first || last || multiple_of(step, o.snapshot_interval)))
      write_snapshot();
    // No checkpoint at the first step of a run: there is nothing to resume yet.
    if (o.checkpoint_interval > 0 && !first && (last || multiple_of(step, o.checkpoint_interval)))
      write_checkpoint();
    if (!options_.quiet && o.progress_interval > 0 && step > first_step_ &&
        (last || multiple_of(step, o.progress_interval)))
      report_progress();
    if (options_.quiet && !options_.progress_label.empty())
      report_quiet_progress();
  }

  void DemRun::report_quiet_progress()
  {
    // A campaign test prints one line per minute of wall time, so that a long test shows it lives.
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - last_quiet_report_).count() < 60)
      return;
    last_quiet_report_ = now;
    std::ostringstream line;
    line.precision(4);
    line << options_.progress_label << ": step " << system_.step_count << ", t = " << system_.time << " s, "
         << system_.bonds.count_intact() << "/" << system_.bonds.size() << " bonds intact";
    if (protocol_)
      line << ", " << protocol_->stage(system_);
    std::cout << line.str() << "\n" << std::flush;
  }

  void DemRun::report_progress()
  {
    ProgressState state;
    state.step = system_.step_count;
    state.total_steps = total_steps_;
    state.time = system_.time;
    state.dt = system_.dt;
    state.intact_bonds = system_.bonds.count_intact();
    state.bonds = system_.bonds.size();
    state.kinetic_energy = system_.energy().kinetic;
    progress_->report(state);
  }

  void DemRun::prepare()
  {
    const fs::path &dir = files_.directory;
    std::error_code error;
    if (fs::exists(dir, error) && !fs::is_directory(dir, error))
      throw InputError("The output path <" + dir.string() + "> exists and is not a directory.");

    if (!options_.resume)
    {
      if (options_.overwrite)
        return;
      for (const fs::path &p : files_.all())
        if (fs::exists(p, error))
          throw InputError("The output directory <" + dir.string() + "> already holds a run (" +
                           p.filename().string() +
                           "). Use --resume to continue it, --overwrite to replace its outputs, or "
                           "another directory.");
      return;
    }

    // --resume: the checkpoint must exist and belong to this scene.
    if (!fs::exists(files_.checkpoint(), error) || !fs::exists(files_.checkpoint_info(), error))
      throw InputError("Cannot resume: <" + dir.string() +
                       "> has no checkpoint.h5 and checkpoint.json (set Output/Checkpoint "
                       "interval [steps] > 0 to write them).");
    // A torn or foreign index or checkpoint is refused naming it (util/input_error.h).
    const std::string restart = "Run again without --resume and with --overwrite to start the run afresh.";
    const Json info = interpret_json_file(files_.checkpoint_info().string(), "a DEM checkpoint's index", [](const Json &j) {
      j.at("scene").at("resume_key_sha256").get<std::string>();
      return j;
    }, restart);
    const std::string saved_key = info.value(Json::json_pointer("/scene/resume_key_sha256"), std::string());
    if (saved_key != scene_.resume_key_sha256)
      throw InputError(
        "Cannot resume: the checkpoint in <" + dir.string() + "> was written for a different scene (" +
        info.value(Json::json_pointer("/scene/file"), std::string("?")) + ", model parameters sha256 " + saved_key +
        "); <" + scene_.file + "> has " + scene_.resume_key_sha256 +
        ". Between a run and its resumption only the Output subsection, DEM/Steps and DEM/Threads "
        "may change.");
    try
    {
      dem::io::read_checkpoint(files_.checkpoint().string(), system_);
      system_.resume();
    }
    catch (const std::exception &e)
    {
      throw UnusableOutputFile(files_.checkpoint().string(),
                               "cannot be read back as this scene's checkpoint (" + std::string(e.what()) + ")", restart);
    }
    if (system_.step_count > total_steps_)
      throw InputError("Cannot resume: the checkpoint is at step " + std::to_string(system_.step_count) +
                       ", beyond DEM/Steps = " + std::to_string(total_steps_) + " of <" + scene_.file + ">.");
    resumed_from_step_ = system_.step_count;
    last_checkpoint_step_ = system_.step_count;
    if (protocol_ && info.contains("protocol_state"))
      protocol_->restore(info["protocol_state"].get<std::map<std::string, double>>());

    if (fs::exists(files_.history(), error))
    {
      try
      {
        history_.read(files_.history().string());
      }
      catch (const std::exception &e)
      {
        throw InputError("Cannot resume: " + std::string(e.what()));
      }
      history_.truncate_after_step(static_cast<double>(system_.step_count));
      if (history_.rows() > 0)
      {
        const auto *step = history_.find(history_column::step);
        last_history_step_ = static_cast<Index>(step->values.back());
      }
    }
  }

  int DemRun::run()
  {
    const auto &o = scene_.output;
    const fs::path &dir = files_.directory;
    if (options_.overwrite && !options_.resume)
      for (const fs::path &p : files_.all())
        fs::remove_all(p);
    fs::create_directories(dir);
    if (o.snapshot_interval > 0)
      fs::create_directories(files_.snapshots());
    if (o.snapshot_interval > 0 && o.write_paraview)
    {
      fs::create_directories(files_.paraview());
      pvd_particles_.emplace((files_.paraview() / "particles.pvd").string());
      pvd_bonds_.emplace((files_.paraview() / "bonds.pvd").string());
      if (resumed_from_step_)
      {
        pvd_particles_->load_existing(system_.time);
        pvd_bonds_->load_existing(system_.time);
      }
    }

    first_step_ = system_.step_count;
    progress_.emplace(std::cout, ProgressReporter::stdout_is_terminal(), first_step_);
    if (!options_.quiet)
      print_start();

    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    std::string status = "completed", message, failure_title = "Numerical failure of the DEM run";
    int exit_code = exit_success;
    const StopSignals stop_signals;
    try
    {
      if (!resumed_from_step_)
        write_outputs(true, total_steps_ == 0);
      // Steps run in chunks that end at the next output or control step (at most 1000 steps, so
      // that a stop request is honoured promptly).
      constexpr Index max_chunk = 1000;
      const Index control_interval = protocol_ ? protocol_->control_interval() : 0;
      while (system_.step_count < total_steps_)
      {
        const Index now = system_.step_count;
        Index next = std::min(total_steps_, now + max_chunk);
        const Index history_interval = sampled_by_protocol() ? 0 : o.history_interval;
        for (const Index interval : {history_interval, o.snapshot_interval, o.checkpoint_interval,
                                     o.progress_interval, control_interval})
          if (interval > 0)
            next = std::min(next, (now / interval + 1) * interval);
        {
          const auto phase = timer_.scope("time stepping");
          system_.run(next - now);
          if (protocol_ && multiple_of(system_.step_count, control_interval))
          {
            protocol_->control(system_);
            history_row_due_ = sampled_by_protocol() && protocol_->history_row_due(system_);
          }
          protocol_finished_ = protocol_ && protocol_->finished(system_);
        }
        write_outputs(false, system_.step_count == total_steps_ || protocol_finished_);
        if (protocol_finished_)
        {
          message = "the test ended at step " + std::to_string(system_.step_count) + ": " + protocol_->stage(system_);
          break;
        }
        if (StopSignals::requested())
        {
          status = "interrupted";
          message = "stopped by a signal at step " + std::to_string(system_.step_count);
          exit_code = exit_interrupted;
          record_history();
          if (o.checkpoint_interval > 0)
            write_checkpoint();
          break;
        }
      }
    }
    catch (const dem::NumericalError &e)
    {
      status = "failed";
      message = e.what();
      exit_code = exit_numerical_failure;
      // The state at the failure (possibly NaN) is the most telling row of the history.
      try
      {
        record_history();
      }
      catch (const std::exception &)
      {}
    }
    catch (const std::exception &e)
    {
      // Output failures (disk full, permissions) end the run like a numerical failure.
      failure_title = "The DEM run failed";
      status = "failed";
      message = e.what();
      exit_code = exit_numerical_failure;
    }
    progress_->finish();
    wall_seconds_ = elapsed();

    try
    {
      {
        const auto phase = timer_.scope("output");
        write_history();
      }
      // The yield point of this test (Ritter et al.'s (2020) failure criterion) and its companions.
      if (model_->clump >= 0)
      {
        const auto phase = timer_.scope("failure analysis");
        // Strains of the deformable layer between the rigid base and clump (u / h), as the
        // calibration reads them (params/campaign_data.cpp): one secant modulus for both.
        failure_analysis_ = analyse_test_history(history_, initial_layer_thickness_,
                                                 scene_.dem.loading.test->control);
      }
      summary_ = summary(status, message);
      write_json_atomically(files_.summary().string(), summary_);
    }
    catch (const std::exception &e)
    {
      std::cerr << "anticrack: could not write the run's summary or history in <" << dir.string()
                << ">: " << e.what() << "\n";
      return exit_code == exit_success ? exit_numerical_failure : exit_code;
    }

    if (status == "failed")
      print_framed(std::cerr, failure_title,
                   "  scene:   " + scene_.file + "\n  output:  " + dir.string() +
                     " (summary.json has \"status\": \"failed\", history.h5 ends at step " +
                     std::to_string(last_history_step_) + ")\n  at step " +
                     std::to_string(system_.step_count) + ", t = " + format_number(system_.time) +
                     " s:\n\n  " + message);
    else if (!options_.quiet)
      print_end(wall_seconds_);
    if (status == "interrupted")
      std::cout << "interrupted at step " << system_.step_count << " of " << total_steps_
                << (last_checkpoint_step_ == system_.step_count ?
                      "; continue with: anticrack run " + scene_.file + " -o " + dir.string() + " --resume" :
                      " (no checkpoint: Output/Checkpoint interval [steps] is 0)")
                << "\n";
    return exit_code;
  }

  Json DemRun::summary(const std::string &status, const std::string &message) const
  {
    const dem::EnergyLedger e = system_.energy();
    const BondCounts bonds = count_bonds(system_.bonds);
    const double balance_error = e.balance() - system_.initial_balance;
    const Index steps_done = system_.step_count - first_step_;

    Json s;
    s["status"] = status;
    if (!message.empty())
      s["message"] = message;
    s["command"] = options_.command_line;
    if (!options_.labels.is_null())
      s["labels"] = options_.labels;
    s["scene"] = scene_info(scene_);
    s["components"] = scene_.components;
    s["output_directory"] = files_.directory.string();
    s["resumed_from_step"] = resumed_from_step_ ? Json(*resumed_from_step_) : Json(nullptr);

    Json d;
    d["particles"] = system_.particles.size();
    d["fixed_particles"] = model_->fixed_particles.size();
    d["clump_members"] = model_->clump >= 0 ? system_.clumps[model_->clump].members.size() : 0;
    d["bonds"] = system_.bonds.size();
    d["intact_bonds"] = bonds.intact;
    d["broken_bonds_tension"] = bonds.tension;
    d["broken_bonds_shear"] = bonds.shear;
    d["steps"] = system_.step_count;
    d["steps_requested"] = total_steps_;
    d["final_time_s"] = system_.time;
    d["dt_s"] = system_.dt;
    d["critical_time_step_s"] = system_.critical_time_step();
    d["neighbor_builds"] = system_.neighbor_builds();

    Json energies;
    energies["kinetic"] = e.kinetic;
    energies["elastic_contacts"] = e.elastic_contacts;
    energies["elastic_bonds"] = e.elastic_bonds;
    energies["gravity_potential"] = e.gravity_potential;
    energies["friction"] = e.friction;
    energies["viscous"] = e.viscous;
    energies["local_damping"] = e.local_damping;
    energies["bond_breakage"] = e.bond_breakage;
    energies["dissipated"] = e.dissipated();
    energies["external_work"] = e.external_work;
    energies["balance"] = e.balance();
    energies["initial_balance"] = system_.initial_balance;
    d["energies_J"] = energies;
    d["energy_balance_error_J"] = balance_error;
    const double scale = system_.energy_scale(e);
    d["energy_balance_relative_error"] = scale > 0 ? std::abs(balance_error) / scale : 0.0;

    // Peak of every stress column of the history, e.g. the strength in a compression test.
    auto peak = [&](const std::string &column) {
      const auto *c = history_.find(column);
      Json p = nullptr;
      if (c == nullptr || c->values.empty())
        return p;
      const auto it = std::max_element(c->values.begin(), c->values.end());
      const std::size_t row = it - c->values.begin();
      p = Json::object();
      p["value_Pa"] = *it;
      p["time_s"] = history_.find(history_column::time)->values[row];
      p["step"] = static_cast<Index>(history_.find(history_column::step)->values[row]);
      return p;
    };

    const double largest_inertial = largest_inertial_number_before_peak();
    if (largest_inertial > 0)
      d["inertial_number"] = {{"largest_before_peak_q", largest_inertial},
                              {"quasi_static_limit", quasi_static_inertial_number},
                              {"quasi_static", largest_inertial < quasi_static_inertial_number}};

    Json walls = Json::array();
    for (const auto &wall : system_.walls)
    {
      Json w;
      w["name"] = wall.name;
      w["control"] = to_string(wall.control);
      w["normal"] = {wall.normal[0], wall.normal[1], wall.normal[2]};
      w["position_m"] = wall.point.dot(wall.normal.cwiseAbs());
      w["force_N"] = {wall.force[0], wall.force[1], wall.force[2]};
      w["area_m2"] = wall.area;
      w["normal_stress_Pa"] = wall.normal_stress();
      w["peak_normal_stress"] = peak("wall_" + wall.name + "_normal_stress");
      walls.push_back(w);
    }
    d["walls"] = walls;

    if (!model_->fixed_particles.empty())
    {
      Json base;
      base["area_m2"] = model_->base_area;
      const auto *normal = history_.find(history_column::base_normal_stress);
      const auto *shear = history_.find(history_column::base_shear_stress);
      base["normal_stress_Pa"] = normal->values.empty() ? Json(nullptr) : Json(normal->values.back());
      base["shear_stress_Pa"] = shear->values.empty() ? Json(nullptr) : Json(shear->values.back());
      base["peak_normal_stress"] = peak(history_column::base_normal_stress);
      base["peak_shear_stress"] = peak(history_column::base_shear_stress);
      d["base"] = base;
    }
    if (model_->clump >= 0)
    {
      const dem::Clump &clump = system_.clumps[model_->clump];
      const Vec3 force = clump.applied_force(system_.time);
      Json c;
      c["members"] = clump.members.size();
      c["mass_kg"] = clump.mass;
      c["centre_m"] = {clump.centre[0], clump.centre[1], clump.centre[2]};
      c["displacement_m"] = {clump.displacement[0], clump.displacement[1], clump.displacement[2]};
      c["velocity_m_per_s"] = {clump.velocity[0], clump.velocity[1], clump.velocity[2]};
      c["applied_force_N"] = {force[0], force[1], force[2]};
      d["clump"] = c;
      const auto &loading = scene_.dem.loading;
      Json l;
      l["adaptive_rate"] = loading.adaptive;
      l["fast_rate_N_per_s"] = scene_.dem.boundary.clump_force_rate;
      if (loading.adaptive)
      {
        l["slow_rate_N_per_s"] = loading.ramp.slow_fraction * loading.ramp.fast_rate;
        l["control_interval_steps"] = loading.ramp.interval;
        l["lag_tolerance"] = loading.ramp.lag_tolerance;
      }
      l["final_rate_N_per_s"] = dem::clump_ramp_rate(clump);
      l["stop_strain"] = loading.stop_strain;
      l["stopped_at_stop_strain"] = protocol_finished_;
      d["loading"] = l;
      d["specimen"] = {{"height_m", initial_sample_height_},
                       {"layer_thickness_m", initial_layer_thickness_},
                       {"mean_particle_diameter_m", mean_particle_diameter_},
                       {"love_weber_volume", platens_.empty() ? "sphere extent" : "base area x platen separation"}};
      if (failure_analysis_)
        d["failure_analysis"] = failure_analysis_json(*failure_analysis_);
    }
    // The loading programme's stage and results (triaxial peak, platen peak force, ...).
    if (protocol_)
    {
      Json lab;
      lab["stage"] = protocol_->stage(system_);
      lab["finished"] = protocol_->finished(system_);
      Json results = Json::object();
      for (const auto &[name, value] : protocol_->results(system_))
        results[name] = value;
      // Brazilian disc (Zhao & Feng 2022): splitting tensile strength 2 F / (pi D t), t the disc's thickness
      // (the domain's y length: the disc axis is y).
      const double diameter = scene_.dem.sample.disc_diameter;
      if (diameter > 0 && results.contains("peak_force_N"))
        results["brazilian_tensile_strength_Pa"] = dem::brazilian_tensile_strength(
          results["peak_force_N"].get<double>(), diameter, system_.domain.length()[1]);
      lab["results"] = results;
      d["lab_test"] = lab;
    }
    // The sample generator's report.
    Json sample;
    const SampleType &type = *scene_.dem.sample.type;
    sample["type"] = type.name;
    if (type.summarize)
      type.summarize(sample, scene_, *model_);
    sample["initial_bonds"] = model_->initial_bonds;
    if (scene_.dem.bedding.enabled)
      sample["bedding_bonds"] = model_->bedding_bonds;
    d["sample"] = sample;
    s["dem"] = d;

    Json outputs;
    outputs["summary"] = "summary.json";
    outputs["history"] = "history.h5";
    outputs["history_rows"] = history_.rows();
    outputs["snapshots_written"] = snapshots_written_;
    outputs["paraview"] = pvd_particles_ ? Json("paraview/particles.pvd, paraview/bonds.pvd") : Json(nullptr);
    outputs["checkpoint"] = last_checkpoint_step_ >= 0 ? Json("checkpoint.h5") : Json(nullptr);
    outputs["checkpoint_step"] = last_checkpoint_step_ >= 0 ? Json(last_checkpoint_step_) : Json(nullptr);
    s["outputs"] = outputs;

    Json timing;
    timing["wall_s"] = wall_seconds_;
    timing["steps"] = steps_done;
    timing["steps_per_s"] = wall_seconds_ > 0 ? steps_done / wall_seconds_ : 0.0;
    timing["threads"] = dem::DemSystem::threads();
    timing["phases"] = timer_.to_json();
    s["timing"] = timing;
    s["versions"] = version_info();
    return s;
  }

  void DemRun::print_start() const
  {
    std::ostringstream s;
    s << std::setprecision(4);
    s << "anticrack run: " << scene_.file << " -> " << files_.directory.string() << "\n  "
      << system_.particles.size() << " particles, " << system_.bonds.size() << " bonds, "
      << system_.walls.size() << " walls" << (model_->clump >= 0 ? ", 1 clump" : "") << "; dt = " << system_.dt
      << " s (critical " << system_.critical_time_step() << " s); " << dem::DemSystem::threads()
      << " threads\n";
    if (resumed_from_step_)
      s << "  resuming at step " << *resumed_from_step_ << " (t = " << system_.time << " s) of "
        << total_steps_ << "\n";
    else
      s << "  " << total_steps_ << " steps\n";
    std::cout << s.str() << std::flush;
  }

  void DemRun::print_end(const double wall) const
  {
    const BondCounts bonds = count_bonds(system_.bonds);
    const dem::EnergyLedger e = system_.energy();
    const double scale = system_.energy_scale(e);
    const Index steps_done = system_.step_count - first_step_;
    std::ostringstream s;
    s << std::setprecision(4);
    s << (system_.step_count == total_steps_ || protocol_finished_ ? "done: " : "stopped: ") << steps_done << " steps in " << format_duration(wall) << " ("
      << (wall > 0 ? steps_done / wall : 0.0) << " steps/s); t = " << system_.time << " s\n"
      << "  intact bonds " << bonds.intact << "/" << system_.bonds.size() << " (broken: " << bonds.tension
      << " in tension, " << bonds.shear << " in shear); energy balance error "
      << (scale > 0 ? 100 * std::abs(e.balance() - system_.initial_balance) / scale : 0.0) << " %\n";
    for (const auto &wall : system_.walls)
    {
      const auto *column = history_.find("wall_" + wall.name + "_normal_stress");
      if (column && !column->values.empty())
        s << "  wall " << wall.name << ": peak stress "
          << *std::max_element(column->values.begin(), column->values.end()) << " Pa\n";
    }
    const double largest_inertial = largest_inertial_number_before_peak();
    if (largest_inertial >= quasi_static_inertial_number)
      s << "  NOT QUASI-STATIC: the inertial number reached " << largest_inertial << " before the peak of q (limit "
        << quasi_static_inertial_number << ", Ritter et al. 2020): slow the loading down\n";
    s << "  outputs in " << files_.directory.string() << ": summary.json, history.h5 (" << history_.rows()
      << " rows)";
    if (snapshots_written_ > 0)
      s << ", " << snapshots_written_ << " snapshots";
    if (last_checkpoint_step_ >= 0)
      s << ", checkpoint.h5 (step " << last_checkpoint_step_ << ")";
    std::cout << s.str() << "\n" << std::flush;
  }

  // ---------------------------------------------------------------------------------------------

  int run_dem_scene(const SceneParameters &scene, const RunOptions &options)
  {
    const int threads = options.threads >= 0 ? options.threads : scene.dem.threads;
    return run_dem_model(scene, build_dem_model(scene, threads), options).exit_code;
  }

  DemRunRecord run_dem_model(const SceneParameters &scene, std::unique_ptr<DemModel> model, const RunOptions &options)
  {
    DemRun run(scene, std::move(model), options);
    run.prepare();
    const int exit_code = run.run();
    return run.record(exit_code);
  }

  void check_dem_scene(const SceneParameters &scene, const int threads)
  {
    std::unique_ptr<DemModel> model;
    try
    {
      model = build_dem_model(scene, threads >= 0 ? threads : scene.dem.threads);
    }
    catch (const SpecimenWithoutLoadPath &e)
    {
      // A campaign's realization without a load path is one of its outcomes, not bad input.
      if (!scene.campaign.enabled())
        throw;
      std::cout << "note: the first realization has no load path; the campaign records its tests as such and "
                   "goes on:\n  "
                << e.what() << "\n";
      return;
    }
    describe_dem_model(std::cout, scene, *model);
  }
} // namespace anticrack::dem
