// Platen compression (docs/physics.md §1.5) as a LabProtocol (dem/lab/lab_protocol.h): two walls
// (platens) approach each other at constant speed (Zhao & Feng 2022, layered carbonaceous slate,
// section 4: the lower plate fixed and the upper one moving at 0.1 mm/min; here both move,
// symmetrically): uniaxial compression of a prism (bedded or not, dem/sample/bedding.h) or the
// Brazilian splitting of a disc lying between them (carved with dem/sample/specimen_carving.h; its
// strength from brazilian_tensile_strength in dem/lab/measurements.h). The test ends after the peak
// force, when the force has dropped below a fraction of the peak ("linear elasticity, then
// instantaneous splitting and falling", Zhao & Feng 2022, section 4.3).
#pragma once

#include "dem/lab/lab_protocol.h"

#include <map>
#include <string>

namespace anticrack::dem
{
  struct PlatenSettings
  {
    double platen_speed = 0;        ///< speed of each platen towards the other [m/s], > 0
    double post_peak_fraction = 0.5;///< ends when the force falls below this fraction of the peak [-], in (0, 1)
    /// Ends at this strain, gap shortening / initial gap between the platens [-], in (0, 1]
    double max_strain = 0.2;
    Index interval = 10;            ///< steps between control() calls [-], >= 1
  };

  /// What the platens measure (compressive positive).
  struct PlatenState
  {
    double force = 0;               ///< mean of the two platens' normal forces [N]
    double force_a = 0, force_b = 0;///< each platen's normal force [N]
    double displacement = 0;        ///< shortening of the gap between the platens since start() [m]
    double strain = 0;              ///< displacement / initial gap [-]
    double peak_force = 0;          ///< largest force seen at a control() call [N]
    double displacement_at_peak = 0;///< [m]
  };

  class PlatenCompression : public LabProtocol
  {
  public:
    /// Platens a and b: indices into system.walls of two parallel walls facing each other (normals
    /// opposite, each pointing into the gap). Throws SetupError for invalid settings or walls.
    PlatenCompression(const DemSystem &system, Index platen_a, Index platen_b, const PlatenSettings &settings);

    /// Sets both platens to velocity control at platen_speed towards each other and records the
    /// initial gap; call after system.initialise(), before the first step.
    void start(DemSystem &system) override;

    /// Tracks the peak force.
    void control(DemSystem &system) override;
    /// After the peak, once the force is below post_peak_fraction x peak; or at max_strain.
    [[nodiscard]] bool finished(const DemSystem &system) const override;
    [[nodiscard]] std::string stage(const DemSystem &system) const override;
    [[nodiscard]] std::map<std::string, double> state() const override;
    void restore(const std::map<std::string, double> &state) override;

    [[nodiscard]] PlatenState measure(const DemSystem &system) const;
    /// Peak force, the displacement there, the initial gap and the current strain.
    [[nodiscard]] std::map<std::string, double> results(const DemSystem &system) const override;
    [[nodiscard]] double initial_gap() const { return initial_gap_; }

  private:
    [[nodiscard]] double gap(const DemSystem &system) const;
    [[nodiscard]] bool post_peak(const DemSystem &system) const;

    Index a_, b_;
    PlatenSettings settings_;
    double initial_gap_ = 0;          ///< [m]
    double peak_force_ = 0;           ///< [N]
    double displacement_at_peak_ = 0; ///< [m]
  };
} // namespace anticrack::dem
