// A virtual-laboratory loading programme (docs/physics.md §1.5): the part of a test that steers the
// boundaries while the DEM system runs. The run calls control() every control_interval() steps
// (after the step count reached a multiple of it) and stops once finished() says so; everything
// else (measurements, outputs, checkpoints) belongs to the run.
//
// Protocols: dem/lab/load_control.h (the adaptive clump force ramp of the mixed-mode test, Ritter et al. 2020),
// dem/lab/lab_tests.h (triaxial test with six servo walls, Elyashiv et al. 2020; Brazilian disc and uniaxial
// compression between platens, Zhao & Feng 2022; simple shear at constant normal stress, Mede et al. 2018;
// tilted-gravity actuator, Bobillier et al. 2020).
#pragma once

#include "dem/core/system.h"

#include <map>
#include <string>

namespace anticrack::dem
{
  class LabProtocol
  {
  public:
    virtual ~LabProtocol() = default;

    /// Steps between two control() calls (>= 1).
    [[nodiscard]] virtual Index control_interval() const = 0;

    /// Adjusts walls, clumps, gravity, ... for the next interval.
    virtual void control(DemSystem &system) = 0;

    /// True once the test has reached its end; the run then stops.
    [[nodiscard]] virtual bool finished(const DemSystem &system) const = 0;

    /// What the protocol is doing (e.g. "consolidation", "axial loading") or why it finished.
    [[nodiscard]] virtual std::string stage(const DemSystem &system) const = 0;

    /// The test's own results so far, by name with the unit in the name (e.g. peak deviator stress
    /// of a triaxial test); summary.json reports them.
    [[nodiscard]] virtual std::map<std::string, double> results(const DemSystem & /*system*/) const { return {}; }

    /// Protocol state that a checkpoint must carry besides the DemSystem, by name.
    [[nodiscard]] virtual std::map<std::string, double> state() const { return {}; }
    virtual void restore(const std::map<std::string, double> & /*state*/) {}
  };
} // namespace anticrack::dem
