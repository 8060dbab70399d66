#include "dem/lab/simple_shear.h"

#include "dem/lab/measurements.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace anticrack::dem
{
  SimpleShear::SimpleShear(const Index clump, std::vector<Index> base, const SimpleShearSettings &settings)
    : LabProtocol(settings.interval), clump_(clump), base_(std::move(base)), settings_(settings)
  {
    const auto &s = settings_;
    auto require = [](bool ok, const std::string &what) {
      if (!ok)
        throw SetupError("simple shear: " + what);
    };
    require(s.normal_stress > 0, "the normal stress must be positive (compressive) [Pa]");
    require(s.area > 0 && s.height > 0, "the platen area and the specimen height must be positive");
    require(s.shear_velocity > 0, "the shear velocity must be positive [m/s]");
    require(s.consolidation_time > 0 && s.acceleration_time >= 0, "the consolidation time must be positive and "
                                                                  "the acceleration time >= 0 [s]");
    require(s.consolidation_tolerance > 0 && s.consolidation_tolerance < 1, "the consolidation tolerance must be in (0, 1)");
    require(s.final_shear_strain > 0, "the final shear strain must be positive");
    require(s.interval >= 1, "the control interval must be at least one step");
    require(!base_.empty(), "the specimen has no fixed base to measure the reactions on");
  }

  void SimpleShear::start(DemSystem &system)
  {
    Clump &platen = system.clumps.at(clump_);
    platen.rotation_locked = true;
    platen.held_axes = 0b011; // x and y prescribed, z free
    platen.velocity[0] = platen.velocity[1] = 0;
    const double t0 = system.time;
    platen.applied_force.time = {t0, t0 + settings_.consolidation_time};
    platen.applied_force.value = {Vec3::Zero(), Vec3(0, 0, -settings_.normal_stress * settings_.area)};
    platen.applied_force.extrapolate_linearly = false; // held at F_n after the ramp
  }

  void SimpleShear::control(DemSystem &system)
  {
    Clump &platen = system.clumps[clump_];
    if (!shearing())
    {
      const double target = settings_.normal_stress * settings_.area;
      const double reaction = -total_force(system.particles, base_)[2]; // compressive reaction of the base
      const bool ramp_done = system.time >= platen.applied_force.time.back();
      if (!(ramp_done && std::abs(reaction - target) <= settings_.consolidation_tolerance * target))
        return;
      shear_start_time_ = system.time;
      shear_start_displacement_ = platen.displacement[0];
    }
    // Shearing: the platen's x velocity, reached linearly over the acceleration time.
    const double ramp = settings_.acceleration_time > 0 ?
                          std::min(1.0, (system.time - shear_start_time_) / settings_.acceleration_time) :
                          1.0;
    const double before = platen.velocity[0];
    platen.velocity[0] = ramp * settings_.shear_velocity;
    // The steady sliding: the base's reactions over the second half of the shear strain.
    if (shear_strain(system) >= 0.5 * settings_.final_shear_strain)
    {
      const Vec3 base = total_force(system.particles, base_);
      steady_shear_force_sum_ += base[0];
      steady_normal_force_sum_ -= base[2];
      ++steady_samples_;
    }
    // The driving agent's work on the platen's kinetic energy (as in dem/lab/compaction_test.cpp).
    system.ledger.external_work += 0.5 * platen.mass * (platen.velocity[0] * platen.velocity[0] - before * before);
  }

  double SimpleShear::shear_strain(const DemSystem &system) const
  {
    if (!shearing())
      return 0;
    return (system.clumps[clump_].displacement[0] - shear_start_displacement_) / settings_.height;
  }

  bool SimpleShear::finished(const DemSystem &system) const
  {
    return shearing() && shear_strain(system) >= settings_.final_shear_strain;
  }

  std::string SimpleShear::stage(const DemSystem &system) const
  {
    std::ostringstream s;
    s.precision(6);
    if (!shearing())
      s << "consolidation to sigma_n = " << settings_.normal_stress << " Pa";
    else if (finished(system))
      s << "shear strain " << shear_strain(system) << " reached (final " << settings_.final_shear_strain << ")";
    else
      s << "shearing at " << settings_.shear_velocity << " m/s, gamma = " << shear_strain(system);
    return s.str();
  }

  std::map<std::string, double> SimpleShear::results(const DemSystem &) const
  {
    if (steady_samples_ == 0)
      return {};
    const double area = settings_.area * static_cast<double>(steady_samples_);
    return {{"steady_shear_stress_Pa", steady_shear_force_sum_ / area},
            {"steady_normal_stress_Pa", steady_normal_force_sum_ / area},
            {"steady_stress_ratio", steady_shear_force_sum_ / steady_normal_force_sum_},
            {"steady_samples", static_cast<double>(steady_samples_)}};
  }

  std::map<std::string, double> SimpleShear::state() const
  {
    return {{"shear_start_time", shear_start_time_},
            {"shear_start_displacement", shear_start_displacement_},
            {"steady_shear_force_sum", steady_shear_force_sum_},
            {"steady_normal_force_sum", steady_normal_force_sum_},
            {"steady_samples", static_cast<double>(steady_samples_)}};
  }

  void SimpleShear::restore(const std::map<std::string, double> &state)
  {
    if (const auto it = state.find("shear_start_time"); it != state.end())
      shear_start_time_ = it->second;
    if (const auto it = state.find("shear_start_displacement"); it != state.end())
      shear_start_displacement_ = it->second;
    if (const auto it = state.find("steady_shear_force_sum"); it != state.end())
      steady_shear_force_sum_ = it->second;
    if (const auto it = state.find("steady_normal_force_sum"); it != state.end())
      steady_normal_force_sum_ = it->second;
    if (const auto it = state.find("steady_samples"); it != state.end())
      steady_samples_ = static_cast<Index>(it->second);
  }
} // namespace anticrack::dem
