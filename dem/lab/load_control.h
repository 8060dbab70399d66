// Quasi-static load control of the virtual laboratory (docs/physics.md §1.5): a load ramp whose rate adapts,
// fast while the specimen responds elastically and slow while it is close to failure.
//
// Load-controlled tests (Ritter et al.'s (2020) clump force F(t) = Fdot t d) are quasi-static only if the
// specimen has time to carry every load increment to the base: the base reaction must follow the
// applied load and the inertial number I = gamma_dot d sqrt(rho/p) must stay small (I < 1e-4 in
// Ritter et al. 2020). A constant rate slow enough for the weakest moment of the test (bonds breaking one after
// the other just before the peak) wastes most of the run in the elastic range. The controller below
// therefore decides, every `interval` steps, between two rates:
//   * slow (slow_fraction x fast rate) while bonds break or while the base reaction lags the applied
//     load by more than `lag_tolerance` of it (the specimen is not in equilibrium);
//   * otherwise the rate recovers geometrically, x recovery_factor per quiet interval, up to fast.
// The failure point of such a run must agree with that of a run 4x slower throughout (the campaign's
// quasi-static check reports the difference): the adaptation is a way to spend steps where they
// matter, not a licence to load dynamically.
//
// The ramp is applied as piecewise-linear force history segments, so the load is continuous in time
// and a checkpoint (which stores the clump's current segment) continues bit for bit.
#pragma once

#include "dem/core/clumps.h"
#include "dem/lab/lab_protocol.h"
#include "dem/common/types.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace anticrack::dem
{
  struct RampControlSettings
  {
    double fast_rate = 0;        ///< load rate in the elastic range [load unit/s, N/s for a force]
    double slow_fraction = 1;    ///< slow rate / fast rate, in (0, 1]; 1 = constant rate
    Index interval = 100;        ///< steps between two decisions
    double recovery_factor = 1.25; ///< rate growth per quiet interval (> 1)
    double lag_tolerance = 0.02; ///< |applied - reaction| / |applied| above which the ramp slows
  };

  /// What the controller sees at a decision point.
  struct RampObservation
  {
    Index broken_bonds = 0;   ///< bonds broken since the previous decision
    double applied_load = 0;  ///< magnitude of the applied load now
    double reaction = 0;      ///< the base reaction projected on the load direction
  };

  /// The rate for the next interval, from the current one and what the last interval showed.
  inline double next_ramp_rate(const RampControlSettings &s, const double current_rate, const RampObservation &o)
  {
    const double slow = s.slow_fraction * s.fast_rate;
    const double lag =
      o.applied_load > 0 ? std::abs(o.applied_load - o.reaction) / o.applied_load : 0.0;
    if (o.broken_bonds > 0 || lag > s.lag_tolerance)
      return slow;
    return std::min(s.fast_rate, std::max(slow, current_rate * s.recovery_factor));
  }

  /// Continues a clump's applied force from its value at `time` along `direction` (unit) at `rate`
  /// [N/s]: the force history becomes the segment F(t) = F(time) + rate (t - time) direction.
  inline void continue_clump_ramp(Clump &clump, const double time, const Vec3 &direction, const double rate)
  {
    const Vec3 now = clump.applied_force(time);
    clump.applied_force.time = {time, time + 1.0};
    clump.applied_force.value = {now, now + rate * direction};
    clump.applied_force.extrapolate_linearly = true;
  }

  /// The mixed-mode test's loading programme (Ritter et al. 2020): the clump force ramps along `direction`,
  /// at a constant rate or adaptively (RampControlSettings), until the clump has moved by
  /// `stop_displacement` (0: never; the run's step limit ends it).
  ///
  /// Tilted-gravity actuator (Bobillier et al. 2020): with `actuator_gravity` g > 0 the load is the weight of an
  /// actuator whose density grows, under gravity g `direction` acting on every sphere (start() sets
  /// the system's gravity). Between two control steps the weight gained so far is an applied force
  /// ramp; at each control step it is moved into the clump's mass (and inertia) and the ramp restarts
  /// from zero: the load m g + F(t) is continuous, and the actuator's inertia grows with its weight
  /// as in Bobillier et al.'s (2020) linear density increase.
  class ClumpForceRamp : public LabProtocol
  {
  public:
    ClumpForceRamp(Index clump, std::vector<Index> base, const Vec3 &direction, const RampControlSettings &settings,
                   bool adaptive, double stop_displacement, double actuator_gravity = 0);

    void control(DemSystem &system) override;
    [[nodiscard]] bool finished(const DemSystem &system) const override;
    [[nodiscard]] std::string stage(const DemSystem &system) const override;
    [[nodiscard]] std::map<std::string, double> state() const override;
    void restore(const std::map<std::string, double> &state) override;

    /// Prepares a fresh run: the count of broken bonds, and for the tilted-gravity actuator the
    /// system's gravity and the actuator's initial mass. Call once before the first step.
    void start(DemSystem &system) override;

  private:
    void set_actuator_mass(DemSystem &system, double mass) const;

    Index clump_;
    std::vector<Index> base_;
    Vec3 direction_;
    RampControlSettings settings_;
    bool adaptive_;
    double stop_displacement_;
    double actuator_gravity_;
    double initial_actuator_mass_ = 0;  ///< m0 [kg]
    double specimen_weight_ = 0;        ///< g x the free spheres' mass [N], part of the expected reaction
    Index broken_bonds_at_last_control_ = 0;
  };

  /// The rate of the clump's current ramp segment [N/s] (0 without a ramp).
  inline double clump_ramp_rate(const Clump &clump)
  {
    const auto &h = clump.applied_force;
    if (h.time.size() < 2)
      return 0;
    const std::size_t n = h.time.size();
    return (h.value[n - 1] - h.value[n - 2]).norm() / (h.time[n - 1] - h.time[n - 2]);
  }
} // namespace anticrack::dem
