#include "dem/lab/compaction_test.h"

#include "dem/lab/measurements.h"

#include <algorithm>
#include <sstream>

namespace anticrack::dem
{
  CompactionTest::CompactionTest(const Index clump, std::vector<Index> base, const double area,
                                 const CompactionSettings &settings)
    : LabProtocol(1), clump_(clump), base_(std::move(base)), area_(area), settings_(settings)
  {
    // The test runs on a little past the fit's lock-up (the same rows, dem::CompactionStages), so
    // that the history holds the row that passes it.
    stages_.lock_up_ratio = 1.1 * compaction_lock_up_stress_ratio;
    const auto &s = settings_;
    auto require = [](bool ok, const std::string &what) {
      if (!ok)
        throw SetupError("compaction test: " + what);
    };
    require(s.strain_rate > 0, "the strain rate must be positive [1/s]");
    require(s.height > 0, "the specimen height must be positive [m]");
    require(s.final_strain > 0 && s.final_strain < 1, "the final strain must lie in (0, 1)");
    require(s.acceleration_strain >= 0 && s.acceleration_strain < s.final_strain,
            "the acceleration strain must lie in [0, final strain)");
    require(s.curve_strain_interval > 0 && s.curve_strain_interval <= s.final_strain / compaction_minimum_samples,
            "the curve strain interval must lie in (0, final strain / " + std::to_string(compaction_minimum_samples) +
              "]: the fit needs that many rows");
    require(!base_.empty() && area_ > 0, "the specimen needs a fixed base of positive area for its normal stress");
  }

  void CompactionTest::start(DemSystem &system)
  {
    Clump &platen = system.clumps.at(clump_);
    platen.rotation_locked = true;
    platen.angular_momentum.setZero();
    platen.angular_velocity.setZero();
    platen.held_axes = 0b111;
    platen.velocity.setZero();
    platen.applied_force = ForceHistory{};
    start_time_ = system.time;
    start_displacement_ = platen.displacement[2];
    next_row_strain_ = settings_.curve_strain_interval;
    // A control call every control_strain at full speed (system.dt is the start's; the run
    // re-evaluates it, and a row is due by strain, not by count). Not tied to the curve's interval:
    // the calls step the platen's acceleration, and a different staircase is a different test
    // (docs/work_precision.md: the post-peak curve moves by up to 10 % under such a perturbation).
    set_control_interval(
      std::max<Index>(1, static_cast<Index>(control_strain() / (settings_.strain_rate * system.dt))));
  }

  bool CompactionTest::history_row_due(const DemSystem &system)
  {
    const double e = strain(system);
    if (e < next_row_strain_)
      return false;
    // The next row one interval past this strain: rows never come closer than the interval.
    next_row_strain_ = e + settings_.curve_strain_interval;
    // The stages on the rows, the samples the fit reads (dem::CompactionStages).
    // Compressive: the specimen pushes the base down.
    stages_.add(-total_force(system.particles, base_)[2] / area_);
    return true;
  }

  void CompactionTest::control(DemSystem &system)
  {
    // The speed is reached linearly over the acceleration strain.
    const double acceleration_time = settings_.acceleration_strain / settings_.strain_rate;
    const double ramp =
      acceleration_time > 0 ? std::min(1.0, (system.time - start_time_) / acceleration_time) : 1.0;
    Clump &platen = system.clumps[clump_];
    const Vec3 before = platen.velocity;
    platen.velocity = Vec3(0, 0, -ramp * settings_.strain_rate * settings_.height);
    // The driving agent's work on the platen's kinetic energy ½ m v² (dem/core/system.cpp books
    // only its work against the specimen's forces): the energy balance stays closed while the
    // platen accelerates.
    system.ledger.external_work += 0.5 * platen.mass * (platen.velocity.squaredNorm() - before.squaredNorm());
  }

  double CompactionTest::strain(const DemSystem &system) const
  {
    return -(system.clumps[clump_].displacement[2] - start_displacement_) / settings_.height;
  }

  bool CompactionTest::finished(const DemSystem &system) const
  {
    return stages_.locked_up || strain(system) >= settings_.final_strain;
  }

  std::string CompactionTest::stage(const DemSystem &system) const
  {
    std::ostringstream s;
    s.precision(6);
    if (stages_.locked_up)
      s << "locked up at compaction strain " << strain(system) << " (the base stress exceeds "
        << stages_.lock_up_ratio << " x its first peak " << stages_.peak << " Pa)";
    else if (finished(system))
      s << "compaction strain " << strain(system) << " reached (final " << settings_.final_strain
        << ") before the lock-up";
    else
      s << "compaction at " << settings_.strain_rate << " 1/s, strain " << strain(system);
    return s.str();
  }

  std::map<std::string, double> CompactionTest::results(const DemSystem &system) const
  {
    return {{"compaction_strain", strain(system)}, {"compaction_strain_rate_per_s", settings_.strain_rate}};
  }

  std::map<std::string, double> CompactionTest::state() const
  {
    return {{"compaction_start_time", start_time_},
            {"compaction_start_displacement", start_displacement_},
            {"compaction_peak", stages_.peak},
            {"compaction_rising_samples", static_cast<double>(stages_.rising_samples)},
            {"compaction_collapsed", stages_.collapsed ? 1.0 : 0.0},
            {"compaction_locked_up", stages_.locked_up ? 1.0 : 0.0},
            {"compaction_next_row_strain", next_row_strain_},
            {"compaction_control_interval", static_cast<double>(control_interval())}};
  }

  void CompactionTest::restore(const std::map<std::string, double> &state)
  {
    if (const auto it = state.find("compaction_start_time"); it != state.end())
      start_time_ = it->second;
    if (const auto it = state.find("compaction_start_displacement"); it != state.end())
      start_displacement_ = it->second;
    auto flag = [&](const char *name) { const auto it = state.find(name); return it != state.end() && it->second > 0.5; };
    if (const auto it = state.find("compaction_next_row_strain"); it != state.end())
      next_row_strain_ = it->second;
    if (const auto it = state.find("compaction_control_interval"); it != state.end())
      set_control_interval(std::max<Index>(1, static_cast<Index>(it->second)));
    if (const auto it = state.find("compaction_peak"); it != state.end())
      stages_.peak = it->second;
    if (const auto it = state.find("compaction_rising_samples"); it != state.end())
      stages_.rising_samples = static_cast<std::size_t>(it->second);
    stages_.collapsed = flag("compaction_collapsed");
    stages_.locked_up = flag("compaction_locked_up");
  }
} // namespace anticrack::dem
