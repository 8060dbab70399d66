// A virtual-laboratory loading programme (docs/physics.md §1.5): the part of a test that steers the
// boundaries while the DEM system runs. The run calls control() every control_interval() steps
// (after the step count reached a multiple of it) and stops once finished() says so; everything
// else (measurements, outputs, checkpoints) belongs to the run.
//
// Life cycle: construct after the walls and clumps exist, call start(system) once after
// system.initialise() (it may need the time step) and before the first step (the run calls control()
// only after the first interval); then the run calls control() every control_interval() steps and
// stops when finished() says so. A run resumed from a checkpoint calls restore(state()) instead of
// start(): the walls' and clumps' control modes, speeds, gains, areas and force histories are part of
// the DemSystem the checkpoint restores.
//
// Sign convention: the stresses and forces the wall-driven tests report are compressive positive (the
// walls push on the sample), strains compressive positive (shortening, volume loss), as in soil
// mechanics and in Elyashiv et al.'s (2020) figures; the Love-Weber tensor of dem/lab/measurements.h is
// tension positive.
//
// Protocols: dem/lab/load_control.h (the adaptive clump force ramp of the mixed-mode test, Ritter et al.
// 2020, and the tilted-gravity actuator, Bobillier et al. 2020), dem/lab/triaxial_test.h (six servo
// walls, Elyashiv et al. 2020), dem/lab/platen_compression_test.h (Brazilian disc and uniaxial
// compression between platens, Zhao & Feng 2022), dem/lab/simple_shear.h (simple shear at constant
// normal stress, Mede et al. 2018).
#pragma once

#include "dem/core/system.h"

#include <map>
#include <string>

namespace anticrack::dem
{
  class LabProtocol
  {
  public:
    /// `control_interval`: steps between two control() calls; each protocol checks that it is >= 1.
    explicit LabProtocol(Index control_interval) : control_interval_(control_interval) {}
    virtual ~LabProtocol() = default;

    /// Steps between two control() calls (>= 1).
    [[nodiscard]] Index control_interval() const { return control_interval_; }

    /// Prepares a fresh run (see the life cycle above).
    virtual void start(DemSystem &system) = 0;

    /// Adjusts walls, clumps, gravity, ... for the next interval.
    virtual void control(DemSystem &system) = 0;

    /// True once the test has reached its end; the run then stops.
    [[nodiscard]] virtual bool finished(const DemSystem &system) const = 0;

    /// What the protocol is doing (e.g. "consolidation", "axial loading") or why it finished.
    [[nodiscard]] virtual std::string stage(const DemSystem &system) const = 0;

    /// The test's own results so far, by name with the unit in the name (e.g. peak deviator stress
    /// of a triaxial test); summary.json reports them.
    [[nodiscard]] virtual std::map<std::string, double> results(const DemSystem & /*system*/) const { return {}; }

    /// True for a protocol that samples its own curve in its own measure (the compaction test: every
    /// Curve strain interval of strain). The run then writes a history row when history_row_due()
    /// says so after a control call (and at the first and last step), in place of every
    /// Output/History interval [steps], so that what is read from the curve depends neither on the
    /// time step nor on an output interval.
    [[nodiscard]] virtual bool samples_history() const { return false; }
    /// Asked after each control() when samples_history(): true if the history needs a row now.
    virtual bool history_row_due(const DemSystem & /*system*/) { return false; }

    /// Protocol state that a checkpoint must carry besides the DemSystem, by name.
    [[nodiscard]] virtual std::map<std::string, double> state() const { return {}; }
    virtual void restore(const std::map<std::string, double> & /*state*/) {}

  protected:
    /// For a protocol whose interval follows from the time step, known only at start() (>= 1).
    void set_control_interval(Index steps) { control_interval_ = steps; }

  private:
    Index control_interval_;
  };
} // namespace anticrack::dem
