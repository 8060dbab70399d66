// Virtual-laboratory rock and soil tests driven by walls (docs/physics.md §1.5), as LabProtocols
// (dem/lab/lab_protocol.h):
//   * TriaxialTest: a cuboid sample between six servo-controlled walls (Elyashiv et al. 2020, "Numerical
//     characterization of cohesive and non-cohesive 'sediments' ... using 3D DEM triaxial
//     experiments", section 3.3): (b) isotropic consolidation to the confining pressure,
//     (c) axial loading by the two z walls at a constant axial strain rate while the four lateral
//     walls hold the confining pressure, until the prescribed axial strain (20 % in Elyashiv et al. 2020).
//   * PlatenCompression: two walls (platens) approach each other at constant speed (Zhao & Feng 2022,
//     Zhao & Feng, layered carbonaceous slate, section 4: the lower plate fixed and the upper one moving at 0.1 mm/min; here both move,
//     symmetrically): uniaxial compression of a prism (bedded or not, dem/sample/bedding.h) or the
//     Brazilian splitting of a disc lying between them; the test ends after the peak force, when the
//     force has dropped below a fraction of the peak ("linear elasticity, then instantaneous splitting
//     and falling", Zhao & Feng 2022, section 4.3).
//   * Specimen carving (carve_cylinder, carve_box): cuts a disc or a prism out of a packing.
//
// Sign convention: stresses and forces reported here are compressive positive (the walls push on
// the sample), strains compressive positive (shortening, volume loss), as in soil mechanics and in
// Elyashiv et al.'s (2020) figures; the Love-Weber tensor of dem/lab/measurements.h is tension positive.
//
// Protocols follow the life cycle of dem/lab/load_control.h: construct after the walls exist, call
// start(system) once after system.initialise() (it needs the time step) and before the first step
// (the run calls control() only after the first interval); then the run calls control() every
// control_interval() steps and stops when finished() says so. A run resumed from a checkpoint calls
// restore(state()) instead of start(): the walls' control modes, speeds, gains and areas are part of
// the DemSystem the checkpoint restores.
#pragma once

#include "dem/lab/lab_protocol.h"
#include "dem/core/system.h"

#include <array>
#include <map>
#include <string>

namespace anticrack::dem
{
  // ---------------------------------------------------------------------------------------------
  // Walls and specimens

  /// Order of the walls of a box: index 2 axis + (0 for the lower face, 1 for the upper face).
  enum BoxFace : int
  {
    x_lower = 0,
    x_upper = 1,
    y_lower = 2,
    y_upper = 3,
    z_lower = 4,
    z_upper = 5
  };

  /// Appends six fixed planar walls on the faces of system.domain, named "x-", "x+", "y-", "y+",
  /// "z-", "z+", normals pointing into the box, sphere-wall law `contact`, each with the area of its
  /// face [m^2]; returns their indices into system.walls in BoxFace order. Walls change the
  /// per-wall state of the system: call before system.initialise() (or initialise again). Throws
  /// SetupError if an axis of the domain is periodic (a wall needs an open axis).
  std::array<Index, 6> add_box_walls(DemSystem &system, const ContactParameters &contact);

  /// Removes every sphere whose centre lies outside the infinite cylinder of the given axis (0, 1, 2
  /// for x, y, z) through `centre` with `radius` [m] (a centre exactly on the surface stays). Returns
  /// the number of spheres removed; the remaining ones keep their order (ids are compacted).
  /// Carving is a specimen-preparation step: it refuses (SetupError) systems that already have bonds,
  /// clumps or have stepped, because bonds, clump member lists and per-pair state hold particle ids
  /// (bond the carved specimen afterwards, which also leaves no bonds to the removed material). It
  /// clears the contact list and the per-particle run state sized by the old count; call
  /// system.initialise() afterwards.
  Index carve_cylinder(DemSystem &system, int axis, const Vec3 &centre, double radius);

  /// Removes every sphere whose centre lies outside the box [lower, upper] (faces included stay);
  /// same rules and return value as carve_cylinder.
  Index carve_box(DemSystem &system, const Vec3 &lower, const Vec3 &upper);

  /// Servo gain [m/(s N)] of a wall so that, if the spheres stood still, one step would remove the
  /// fraction `relaxation` of the force error (PFC's servo, Itasca PFC manual "servo-control of
  /// walls": G = alpha A / (k_n N_c dt) in stress units):
  ///   speed = gain (sigma_target A - F_n),  dF_n per step = K_w speed dt  =>  gain = alpha / (K_w dt),
  /// with K_w the summed normal stiffness of the sphere-wall contacts (overlap > 0) now, at least
  /// that of one contact with the mean sphere (so that a wall that touches nothing still has a
  /// finite gain; its speed is then limited by the wall's max_speed). The sample behind the wall
  /// is softer than the wall contacts, so the true fraction per step is smaller: stable for
  /// relaxation <= 1.
  double servo_gain_for(const DemSystem &system, const Wall &wall, double relaxation);

  /// Mobilised friction angle [rad] of a cohesionless sample at principal stresses major >= minor > 0
  /// (compressive positive): sin(phi) = (sigma_1 - sigma_3) / (sigma_1 + sigma_3) (Mohr-Coulomb).
  double mobilised_friction_angle(double major, double minor);

  /// Splitting tensile strength of a Brazilian disc [Pa]: sigma_t = 2 F / (pi D t) (ISRM 1978;
  /// Zhao & Feng 2022, section 5), F the failure load [N], D the diameter [m], t the thickness [m].
  double brazilian_tensile_strength(double force, double diameter, double thickness);

  // ---------------------------------------------------------------------------------------------
  // Triaxial test (Elyashiv et al. 2020)

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
    void start(DemSystem &system);

    [[nodiscard]] Index control_interval() const override { return settings_.interval; }
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

  // ---------------------------------------------------------------------------------------------
  // Platen compression: uniaxial compression and Brazilian disc (Zhao & Feng 2022)

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
    void start(DemSystem &system);

    [[nodiscard]] Index control_interval() const override { return settings_.interval; }
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
