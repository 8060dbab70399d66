// Displacement-controlled compaction of a layered specimen (docs/physics.md §1.5): fixed base,
// tested layer, rigid top platen (the clump), driven down along −z at a constant strain rate to a
// final strain, so that the test follows the post-peak branch of the collapse and the compaction up
// to the lock-up of the collapsed layer.
//
// Why displacement control. A load-controlled ramp (dem/lab/load_control.h) finds the peak, but
// past it the specimen runs away under the applied load: the post-peak stresses it records are
// those of an inertial collapse and depend on the loading rate and the output interval, not on the
// material. With the platen's velocity prescribed, the base reaction at every strain is the
// specimen's resistance at that strain; once the strain rate is below its quasi-static limit
// (inertial number I = γ̇ d √(ρ/σ) ≪ 1, MiDi 2004), the stress-strain curve, and everything
// measured on it (the strength drop, its plastic strain, the dissipated energy, the lock-up strain:
// params/compaction_analysis.h), no longer depends on the rate.
//
// Quasi-static. The rate must be slow enough for a stress wave to cross the layer many times before
// the peak (h/c ≈ 0.15 ms for the SHS layer of scenes/shs_weak_layer.prm, whose peak comes after
// 0.2 % strain: at 20 /s the peak never reaches the base). A rate that adapts to the equilibrium of
// the platen's and the base's forces, as the clump force ramp's does, was tried and measured: on the
// collapse plateau the two differ by more than 5 % at any affordable rate (force chains form and
// buckle), so it never left its slow rate. The rate is therefore constant, and the campaign's
// quasi-static check (the same test at γ̇ / slowdown) measures what it leaves (docs/calibration.md).
//
// The platen: rotation locked, all three velocity components prescribed (x and y held at zero,
// z = −rate H0 reached linearly over the first `acceleration_strain` of strain, to avoid a velocity
// jump). The strain of the run is −u_z / H0 of the platen over the specimen height H0. The test ends
// once the collapsed layer has locked up (dem::CompactionStages on the base's normal stress at every
// control call: past compaction_lock_up_stress_ratio times its first peak) or at `final_strain`.
//
// Sampling in strain. The curve's history rows come every `curve_strain_interval` of strain, not
// every so many steps: the time step scales with the sphere size, so a fixed number of steps put 4
// rows on the rise to the peak at 512 spheres and 7 at 2048 (at 5 /s, 200 steps), and the peak, the
// drop and the secant modulus read from the curve changed with the number of spheres and the output
// interval. The control calls come every `acceleration_strain` / 25 of strain (4e-6 by default, a
// few steps), whatever the curve's interval, so that the platen's motion is one and the same test
// however the curve is sampled; each row lies within that strain past its due strain.
#pragma once

#include "dem/lab/compaction_curve.h"
#include "dem/lab/lab_protocol.h"

#include <vector>

namespace anticrack::dem
{
  struct CompactionSettings
  {
    double strain_rate = 0;              ///< γ̇ = v / H0 [1/s], > 0
    double height = 0;                   ///< H0, the specimen's height [m], > 0
    double final_strain = 0;             ///< −u_z / H0 at which the test ends, in (0, 1)
    double acceleration_strain = 1e-4;   ///< strain over which the platen reaches its speed, >= 0
    double curve_strain_interval = 0;    ///< strain between two history rows, in (0, final_strain / 20]
  };

  class CompactionTest : public LabProtocol
  {
  public:
    /// Throws SetupError for settings out of range (named in the message).
    /// `base`: the fixed spheres whose reaction is the base normal stress; `area`: the base's [m²].
    CompactionTest(Index clump, std::vector<Index> base, double area, const CompactionSettings &settings);

    /// Locks the platen's rotation and prescribes its velocity. Call once before the first step of
    /// a fresh run.
    void start(DemSystem &system) override;
    void control(DemSystem &system) override;
    [[nodiscard]] bool finished(const DemSystem &system) const override;
    [[nodiscard]] std::string stage(const DemSystem &system) const override;
    [[nodiscard]] std::map<std::string, double> results(const DemSystem &system) const override;
    [[nodiscard]] std::map<std::string, double> state() const override;
    void restore(const std::map<std::string, double> &state) override;
    [[nodiscard]] bool samples_history() const override { return true; }
    bool history_row_due(const DemSystem &system) override;

    /// Strain between two control calls at full speed: acceleration_strain / 25, or without an
    /// acceleration a quarter of the curve's interval.
    [[nodiscard]] double control_strain() const
    {
      return settings_.acceleration_strain > 0 ? settings_.acceleration_strain / 25 : settings_.curve_strain_interval / 4;
    }

    /// −u_z / H0 of the platen since the start of the test.
    [[nodiscard]] double strain(const DemSystem &system) const;

  private:
    Index clump_;
    std::vector<Index> base_;
    double area_;
    CompactionSettings settings_;
    CompactionStages stages_;
    double start_time_ = 0;          ///< [s]
    double start_displacement_ = 0;  ///< u_z of the platen at the start [m]
    double next_row_strain_ = 0;     ///< the strain at which the next history row is due
  };
} // namespace anticrack::dem
