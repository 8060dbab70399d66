#include "dem/lab/load_control.h"

#include <sstream>

namespace anticrack::dem
{
  ClumpForceRamp::ClumpForceRamp(const Index clump, std::vector<Index> base, const Vec3 &direction,
                                 const RampControlSettings &settings, const bool adaptive,
                                 const double stop_displacement, const double actuator_gravity)
    : LabProtocol(settings.interval), clump_(clump), base_(std::move(base)), direction_(direction.normalized()), settings_(settings),
      adaptive_(adaptive), stop_displacement_(stop_displacement), actuator_gravity_(actuator_gravity)
  {
    if (settings_.interval < 1)
      throw SetupError("clump force ramp: the control interval must be at least one step");
    if (!(actuator_gravity_ >= 0))
      throw SetupError("clump force ramp: the actuator gravity must be >= 0 (0 = a plain force ramp)");
  }

  void ClumpForceRamp::start(DemSystem &system)
  {
    broken_bonds_at_last_control_ = system.bonds.size() - system.bonds.count_intact();
    if (actuator_gravity_ > 0)
    {
      system.settings.gravity = actuator_gravity_ * direction_;
      initial_actuator_mass_ = system.clumps[clump_].mass;
      double free_mass = 0;
      for (Index p = 0; p < system.particles.size(); ++p)
        if (system.particles.clump_id[p] < 0 && !(system.particles.blocked[p] & block_translation))
          free_mass += system.particles.mass[p];
      specimen_weight_ = actuator_gravity_ * free_mass;
    }
  }

  void ClumpForceRamp::set_actuator_mass(DemSystem &system, const double mass) const
  {
    // Density change of a rigid body: mass, inertia and the members' masses scale together.
    Clump &clump = system.clumps[clump_];
    const double factor = mass / clump.mass;
    clump.mass = mass;
    clump.principal_inertia *= factor;
    for (const Index p : clump.members)
    {
      system.particles.mass[p] *= factor;
      system.particles.inertia[p] *= factor;
    }
  }

  void ClumpForceRamp::control(DemSystem &system)
  {
    Clump &clump = system.clumps[clump_];
    const Vec3 applied = clump.applied_force(system.time);
    double rate = clump_ramp_rate(clump);
    if (adaptive_)
    {
      // Decide the rate of the next interval from the breakage and the lag of the base reaction
      // (projected on the load direction) during the last one.
      Vec3 reaction = Vec3::Zero();
      for (const Index p : base_)
        reaction += system.particles.force[p];
      const Index broken = system.bonds.size() - system.bonds.count_intact();
      RampObservation seen;
      seen.broken_bonds = broken - broken_bonds_at_last_control_;
      seen.applied_load = applied.norm() + (actuator_gravity_ > 0 ? clump.mass * actuator_gravity_ : 0.0) +
                          specimen_weight_;
      seen.reaction = reaction.dot(direction_);
      broken_bonds_at_last_control_ = broken;
      rate = next_ramp_rate(settings_, rate, seen);
    }
    if (actuator_gravity_ > 0)
    {
      // The weight gained since the last control step becomes actuator mass; the ramp restarts from
      // zero, so that the load m g + F(t) stays continuous in time.
      set_actuator_mass(system, clump.mass + applied.norm() / actuator_gravity_);
      clump.applied_force.time = {system.time, system.time + 1.0};
      clump.applied_force.value = {Vec3::Zero(), rate * direction_};
      clump.applied_force.extrapolate_linearly = true;
    }
    else if (adaptive_)
      continue_clump_ramp(clump, system.time, direction_, rate);
  }

  bool ClumpForceRamp::finished(const DemSystem &system) const
  {
    return stop_displacement_ > 0 && system.clumps[clump_].displacement.norm() >= stop_displacement_;
  }

  std::string ClumpForceRamp::stage(const DemSystem &system) const
  {
    std::ostringstream s;
    s.precision(6);
    if (finished(system))
      s << "the clump moved by " << system.clumps[clump_].displacement.norm() << " m (stop at "
        << stop_displacement_ << " m)";
    else
      s << "clump force ramp at " << clump_ramp_rate(system.clumps[clump_]) << " N/s";
    return s.str();
  }

  std::map<std::string, double> ClumpForceRamp::state() const
  {
    return {{"broken_bonds_at_last_control", static_cast<double>(broken_bonds_at_last_control_)},
            {"initial_actuator_mass", initial_actuator_mass_},
            {"specimen_weight", specimen_weight_}};
  }

  void ClumpForceRamp::restore(const std::map<std::string, double> &state)
  {
    auto get = [&](const char *name, double fallback) {
      const auto it = state.find(name);
      return it == state.end() ? fallback : it->second;
    };
    broken_bonds_at_last_control_ = static_cast<Index>(get("broken_bonds_at_last_control", 0));
    initial_actuator_mass_ = get("initial_actuator_mass", initial_actuator_mass_);
    specimen_weight_ = get("specimen_weight", specimen_weight_);
  }
} // namespace anticrack::dem
