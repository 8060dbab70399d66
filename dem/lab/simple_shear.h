// Displacement-controlled simple shear at constant normal stress (Mede et al. 2018; docs/physics.md §1.5), on a
// layered specimen: fixed base, tested layer, rigid top platen (a clump), lateral periodicity.
//
// Stage 1, consolidation: the platen's rotation and its x and y velocities are held at zero; the
// normal force ramps linearly to F_n = sigma_n A over `consolidation_time` and is then held; the
// stage ends once the base's normal reaction is within `consolidation_tolerance` of F_n.
// Stage 2, shearing: the platen is driven along +x at `shear_velocity` (reached linearly over
// `acceleration_time`, to avoid a velocity jump) while z stays free under the constant normal force,
// so the specimen dilates or compacts as it wants (u_z of the clump). The test ends at the shear
// strain gamma = u_x / H = final_shear_strain. The base shear stress tau = sum f_x / A against gamma
// is the shear curve; its peak is the shear strength at this normal stress. Over the second half
// of the shear strain the base's mean reactions give the steady sliding: results() reports the
// steady shear and normal stresses and their ratio, the friction coefficient of the sheared layer
// once it slides steadily (of a collapsed weak layer: scenes/shs_collapsed_friction.prm).
#pragma once

#include "dem/lab/lab_protocol.h"

#include <vector>

namespace anticrack::dem
{
  struct SimpleShearSettings
  {
    double normal_stress = 1e4;          ///< sigma_n, compressive [Pa]
    double area = 1e-4;                  ///< A, the platen's (x-y) area [m^2]
    double height = 1e-2;                ///< H, the specimen's height for the shear strain [m]
    double shear_velocity = 1e-3;        ///< v along +x [m/s]
    double consolidation_time = 1e-3;    ///< duration of the normal-force ramp [s]
    double consolidation_tolerance = 0.02; ///< |R_z - F_n| / F_n that ends consolidation
    double acceleration_time = 1e-4;     ///< time over which the platen reaches v [s]
    double final_shear_strain = 0.1;     ///< gamma at which the test ends
    Index interval = 100;                ///< steps between control calls
  };

  class SimpleShear : public LabProtocol
  {
  public:
    /// Throws SetupError for settings out of range (named in the message).
    SimpleShear(Index clump, std::vector<Index> base, const SimpleShearSettings &settings);

    /// Holds the platen (rotation, x, y), starts the normal-force ramp. Call once before the first
    /// step of a fresh run.
    void start(DemSystem &system) override;

    void control(DemSystem &system) override;
    [[nodiscard]] bool finished(const DemSystem &system) const override;
    [[nodiscard]] std::string stage(const DemSystem &system) const override;
    /// steady_shear_stress_Pa, steady_normal_stress_Pa and steady_stress_ratio (the base's mean
    /// reactions over the second half of the shear strain), once that half has begun.
    [[nodiscard]] std::map<std::string, double> results(const DemSystem &system) const override;
    [[nodiscard]] std::map<std::string, double> state() const override;
    void restore(const std::map<std::string, double> &state) override;

    [[nodiscard]] bool shearing() const { return shear_start_time_ >= 0; }
    /// gamma = (u_x - u_x at the start of shearing) / H.
    [[nodiscard]] double shear_strain(const DemSystem &system) const;

  private:
    Index clump_;
    std::vector<Index> base_;
    SimpleShearSettings settings_;
    double shear_start_time_ = -1;       ///< time shearing began, < 0 while consolidating
    double shear_start_displacement_ = 0;///< u_x of the platen then [m]
    double steady_shear_force_sum_ = 0;  ///< sum over the steady samples of the base's sum f_x [N]
    double steady_normal_force_sum_ = 0; ///< ... and of its compressive reaction, -sum f_z [N]
    Index steady_samples_ = 0;           ///< control calls in the second half of the shear strain
  };
} // namespace anticrack::dem
