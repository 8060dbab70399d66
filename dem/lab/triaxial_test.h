// The triaxial test (docs/physics.md §1.5) as a LabProtocol (dem/lab/lab_protocol.h): a cuboid sample
// between six servo-controlled walls (dem/lab/box_walls.h; Elyashiv et al. 2020, "Numerical
// characterization of cohesive and non-cohesive 'sediments' ... using 3D DEM triaxial experiments",
// section 3.3): (b) isotropic consolidation to the confining pressure, (c) axial loading by the two z
// walls at a constant axial strain rate while the four lateral walls hold the confining pressure,
// until the prescribed axial strain (20 % in Elyashiv et al. 2020).
#pragma once

#include "dem/lab/box_walls.h"
#include "dem/lab/lab_protocol.h"

#include <array>
#include <map>
#include <string>

namespace anticrack::dem
{
  struct TriaxialSettings
  {
    double confining_pressure = 1e5;   ///< sigma_c [Pa], > 0 (Elyashiv et al. 2020: 100, 250, 500 kPa)
    double axial_strain_rate = 0;      ///< d(eps_axial)/dt [1/s], > 0
    double final_axial_strain = 0.2;   ///< the test ends at this axial strain [-], in (0, 1) (Elyashiv et al. 2020: 20 %)
    double consolidation_tolerance = 0.01; ///< |sigma_wall - sigma_c| / sigma_c for consolidation [-], in (0, 1)
    /// Kinetic / elastic energy (contacts, walls and bonds) below which the consolidated sample counts
    /// as at rest [-], > 0
    double kinetic_energy_ratio = 1e-4;
    double servo_relaxation = 0.5;     ///< alpha of servo_gain_for [-], in (0, 1] (PFC default 0.5)
    /// Cap on the servo wall speed [m/s], > 0; it also bounds how fast the lateral walls can follow
    /// the dilation during axial loading (keep it well above strain_rate x box length).
    double max_servo_speed = 0;
    Index interval = 10;               ///< steps between control() calls [-], >= 1
  };

  /// What the triaxial test measures, from the wall positions and forces (compressive positive).
  /// Strains are relative to the reference box: the box at the end of consolidation during axial
  /// loading, the box at start() during consolidation.
  struct TriaxialState
  {
    double axial_strain = 0;        ///< (H_ref - H) / H_ref, H the z distance of the z walls [-]
    double volumetric_strain = 0;   ///< (V_ref - V) / V_ref, V the volume between the walls [-]
    double axial_stress = 0;        ///< sigma_a, mean of the two z walls [Pa]
    double lateral_stress_x = 0;    ///< mean of the two x walls [Pa]
    double lateral_stress_y = 0;    ///< mean of the two y walls [Pa]
    double lateral_stress = 0;      ///< sigma_l, mean of the four lateral walls [Pa]
    double deviator_stress = 0;     ///< q = sigma_a - sigma_l [Pa]
    double mean_stress = 0;         ///< p = (sigma_a + sigma_x + sigma_y) / 3 [Pa]
    Vec3 box_length = Vec3::Zero(); ///< distances between opposite walls [m]
    double volume = 0;              ///< box volume between the walls [m^3]
    std::array<double, 6> wall_stress{}; ///< each wall's normal force / current face area [Pa], BoxFace order
  };

  enum class TriaxialStage
  {
    consolidation = 0, ///< six servo walls at sigma_c
    axial_loading = 1, ///< z walls at the strain rate, lateral servo walls at sigma_c
    done = 2           ///< final axial strain reached
  };

  class TriaxialTest : public LabProtocol
  {
  public:
    /// `walls`: indices into system.walls in BoxFace order (add_box_walls). Throws SetupError for
    /// invalid settings, missing walls or walls that are not the faces of a box (normals +-e_axis
    /// pointing inwards).
    TriaxialTest(const DemSystem &system, const std::array<Index, 6> &walls, const TriaxialSettings &settings);

    /// Puts the six walls under servo control at sigma_c (consolidation) with areas and gains for
    /// the current box; call after system.initialise(), before the first step.
    void start(DemSystem &system) override;

    /// Updates the face areas and the servo gains; ends consolidation (records the reference box,
    /// starts the z walls) once every wall stress is within tolerance and the sample is at rest;
    /// during axial loading sets the z wall speeds to strain_rate x H / 2 each.
    void control(DemSystem &system) override;
    [[nodiscard]] bool finished(const DemSystem &system) const override;
    [[nodiscard]] std::string stage(const DemSystem &system) const override;
    [[nodiscard]] std::map<std::string, double> state() const override;
    void restore(const std::map<std::string, double> &state) override;

    [[nodiscard]] TriaxialState measure(const DemSystem &system) const;
    /// Peak deviator stress of the axial loading (tracked at control steps), the axial strain and
    /// the mobilised friction angle there, and the current strains.
    [[nodiscard]] std::map<std::string, double> results(const DemSystem &system) const override;
    [[nodiscard]] TriaxialStage current_stage() const { return stage_; }
    /// Step count at which consolidation ended (-1 while consolidating).
    [[nodiscard]] Index consolidation_end_step() const { return consolidation_end_step_; }
    [[nodiscard]] const TriaxialSettings &settings() const { return settings_; }

  private:
    [[nodiscard]] Vec3 box_length(const DemSystem &system) const;
    void update_areas_and_gains(DemSystem &system) const;

    std::array<Index, 6> walls_;
    TriaxialSettings settings_;
    TriaxialStage stage_ = TriaxialStage::consolidation;
    double reference_height_ = 0;  ///< H_ref [m]
    double reference_volume_ = 0;  ///< V_ref [m^3]
    Index consolidation_end_step_ = -1;
    double peak_deviator_ = 0;            ///< [Pa]
    double peak_axial_strain_ = 0;        ///< [-]
    double peak_axial_stress_ = 0;        ///< sigma_1 at the peak [Pa]
    double peak_lateral_stress_ = 0;      ///< sigma_3 at the peak [Pa]
  };

} // namespace anticrack::dem
