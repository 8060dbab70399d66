#include "dem/load_control.h"

#include <sstream>

namespace anticrack::dem
{
  ClumpForceRamp::ClumpForceRamp(const Index clump, std::vector<Index> base, const Vec3 &direction,
                                 const RampControlSettings &settings, const bool adaptive,
                                 const double stop_displacement)
    : clump_(clump), base_(std::move(base)), direction_(direction.normalized()), settings_(settings),
      adaptive_(adaptive), stop_displacement_(stop_displacement)
  {
    if (settings_.interval < 1)
      throw SetupError("clump force ramp: the control interval must be at least one step");
  }

  void ClumpForceRamp::start(const DemSystem &system)
  {
    broken_bonds_at_last_control_ = system.bonds.size() - system.bonds.count_intact();
  }

  void ClumpForceRamp::control(DemSystem &system)
  {
    if (!adaptive_)
      return;
    // Decide the rate of the next interval from the breakage and the lag of the base reaction
    // (projected on the load direction) during the last one.
    Clump &clump = system.clumps[clump_];
    Vec3 reaction = Vec3::Zero();
    for (const Index p : base_)
      reaction += system.particles.force[p];
    const Index broken = system.bonds.size() - system.bonds.count_intact();
    RampObservation seen;
    seen.broken_bonds = broken - broken_bonds_at_last_control_;
    seen.applied_load = clump.applied_force(system.time).norm();
    seen.reaction = reaction.dot(direction_);
    broken_bonds_at_last_control_ = broken;
    continue_clump_ramp(clump, system.time, direction_, next_ramp_rate(settings_, clump_ramp_rate(clump), seen));
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
    return {{"broken_bonds_at_last_control", static_cast<double>(broken_bonds_at_last_control_)}};
  }

  void ClumpForceRamp::restore(const std::map<std::string, double> &state)
  {
    const auto it = state.find("broken_bonds_at_last_control");
    if (it != state.end())
      broken_bonds_at_last_control_ = static_cast<Index>(it->second);
  }
} // namespace anticrack::dem
