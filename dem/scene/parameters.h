// Scene files: deal.II ParameterHandler input (.prm), one parameter struct per subsection with
// declare_parameters / parse_parameters / check (the step-44 layout), gathered in SceneParameters.
//
// Every quantity is SI inside the code; an entry's unit is part of its name ("Radius [m]"), and
// every help string gives the symbol, the meaning and the unit. Pattern violations and unknown
// entries are caught by ParameterHandler while reading; read_scene() then checks what a single
// pattern cannot (upper corner above lower corner, the lattice fits the domain, no walls on a
// periodic axis, ...) and reports every problem at once, naming the file, the entry with its
// subsection path, the value and why it is refused. Nothing is written before this has passed.
//
// Only dem/scene/parameters.cpp and the variants' files (dem/scene/scene_entries.h) include deal.II:
// the rest of the application sees plain structs.
#pragma once

#include "dem/sample/bedding.h"
#include "dem/lab/load_control.h"
#include "dem/core/materials.h"
#include "dem/core/system.h"
#include "dem/common/types.h"
#include "dem/core/walls.h"
#include "dem/scene/lab_tests.h"
#include "dem/scene/sample_types.h"
#include "util/enum_table.h"
#include "util/format.h"

#include <nlohmann/json.hpp>

#include <any>
#include <array>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack
{
  class Problems;
}

namespace anticrack::dem
{
  /// The scene kinds that read DEM scenes (app/scenes.cpp has the table of all kinds).
  enum class SceneKind
  {
    dem,         ///< one run
    campaign,    ///< + subsection Campaign
    calibration  ///< + subsection Campaign and subsection Calibration (coupling/)
  };
  const EnumTable<SceneKind> &scene_kind_names();

  namespace parameters
  {
    struct Sample;
    struct Loading;
    struct Dem;
  }

  /// What a declaration of the DEM scene entries is for: one scene kind and one variant of each
  /// selection that has variants (DEM/Sample/Type, DEM/Loading/Test), so that a scene can set only
  /// what it uses; or, where a member is empty, every kind or variant (the documentation that
  /// `anticrack params` prints, and the union a foreign entry is looked up in).
  struct Declaration
  {
    std::optional<SceneKind> kind;
    std::optional<int> sample_type; ///< an index into sample_types()
    std::optional<int> loading_test; ///< an index into lab_tests()
    /// Entries another module adds to scenes of this kind (subsection Calibration of a calibration
    /// scene, coupling/calibration_scene.h): declared beside the DEM's, parsed by that module.
    void (*declare_more)(dealii::ParameterHandler &prm) = nullptr;

    [[nodiscard]] bool declares_campaign() const { return !kind || *kind != SceneKind::dem; }
  };

  namespace parameters
  {
    /// subsection Output: what is written during a run and how often.
    struct Output
    {
      Index snapshot_interval = 0;   ///< steps between HDF5 snapshots, 0 = none
      Index checkpoint_interval = 0; ///< steps between checkpoints, 0 = none
      Index history_interval = 100;  ///< steps between rows of history.h5
      Index progress_interval = 1000;///< steps between progress lines, 0 = quiet
      bool write_paraview = false;   ///< .vtp/.pvd files beside the snapshots

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// ParaView files need snapshot steps.
      void check(Problems &problems) const;
    };

    /// subsection DEM/Domain: the simulation box.
    struct Domain
    {
      Vec3 lower = Vec3::Zero();
      Vec3 upper = Vec3::Constant(0.02);
      std::array<bool, 3> periodic = {false, false, false};

      [[nodiscard]] Vec3 length() const { return upper - lower; }

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// The upper corner above the lower one along every axis.
      void check(Problems &problems) const;
    };

    /// subsection DEM/Material: density and the contact law of every sphere (and of the walls).
    struct Material
    {
      double density = 1e4;
      dem::ContactParameters contact;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// The density and the moduli of the chosen contact law, which patterns bound only by zero.
      void check(Problems &problems) const;
    };

    /// subsection DEM/Bond: parallel bonds created between touching spheres.
    struct Bond
    {
      dem::BondParameters bond;    ///< friction angle stored in radians
      double friction_angle_deg = 0;
      double gap_tolerance = 1e-6; ///< relative to the smaller radius

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// Moduli and friction angle of enabled bonds.
      void check(Problems &problems) const;
    };

    /// subsection DEM/Sample: where the spheres come from. The types and what each reads are in
    /// dem/scene/sample_types.h; the values of every type are kept here, for the model, the
    /// summary and the campaigns.
    struct Sample
    {
      const SampleType *type = &sample_types().front();
      std::array<Index, 3> lattice_size = {10, 10, 10};
      double radius = 1e-3;
      double spacing = 2e-3;
      Vec3 origin = Vec3::Zero();
      double velocity_amplitude = 0;
      std::string snapshot_file;
      // sticky hard spheres and ballistic deposition
      Index particle_count = 512;
      // sticky hard spheres
      double volume_fraction = 0.3;     ///< phi
      double stickiness = 0.2;          ///< tau, 0 = from the target coordination number
      double target_coordination = 0;   ///< z, 0 = use tau
      double well_width = 0.03;         ///< delta / sigma
      Index sweeps = 20000;
      double sweep_extension_limit = 1; ///< sweeps run on until levelled off, up to this many times `sweeps`
      double equilibration_tolerance = 0.015; ///< relative rise of z allowed over the last half (0: not checked)
      double cluster_move_fraction = 0; ///< of the Monte Carlo trial moves, in [0, 1)
      double box_edge = 0;              ///< L [m]; > 0 sets the radius from phi and N
      Vec3 box_aspect_ratios = Vec3::Ones(); ///< L_x : L_y : L_z of the sticky-hard-sphere box
      /// The sticky-hard-sphere radius: from Box edge [m] (L_z; the box's volume L_z^3 a_x a_y / a_z^2
      /// holds N spheres at phi) when it is set, else Radius [m].
      [[nodiscard]] double sticky_sphere_radius() const
      {
        if (!(box_edge > 0))
          return radius;
        const Vec3 &a = box_aspect_ratios;
        return std::cbrt(volume_fraction * std::pow(box_edge, 3) * a[0] * a[1] / (a[2] * a[2]) /
                         (static_cast<double>(particle_count) * sphere_volume(1.0)));
      }
      // ballistic deposition (radius = mean radius)
      bool rolling = false;             ///< deposition rule
      double radius_half_width = 0;     ///< [m]
      Index actuator_count = 0;         ///< > 0: spheres of a rolling actuator layer on top (Bobillier et al. 2020)
      double actuator_radius = 0;       ///< [m]
      // dense random packing
      double formation_friction = 0;    ///< mu while the packing forms
      double packing_pressure = 1e5;    ///< [Pa]
      double disc_diameter = 0;         ///< [m], > 0 carves a disc (axis y) for the Brazilian test
      /// The values of a type that no other module reads, in a struct of the type's own file
      /// (SampleType::parse_parameters sets it, build reads it with std::any_cast); the fields
      /// above are those the summary, the campaigns or the clump's rules read too.
      std::any settings;

      /// Declares Type and the entries of `type` (every entry of every type if null).
      static void declare_parameters(dealii::ParameterHandler &prm, const SampleType *type);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// The entries of this type, and what the type needs of the rest of `dem` (the DEM/ this sample
      /// belongs to): a lattice inside the domain and bonded by the gap tolerance, periods and boxes
      /// wide enough for the neighbour search, a packing pressure below the contact modulus.
      void check(Problems &problems, const Dem &dem) const;
    };

    /// subsection DEM/Integration: time stepping, damping and stability checks.
    struct Integration
    {
      dem::IntegrationSettings settings;

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// Local damping below 1, a positive safety factor.
      void check(Problems &problems) const;
    };

    /// The names of the wall controls in a scene file (DEM/Walls/<face>/Control).
    const EnumTable<dem::WallControl> &wall_control_names();

    /// subsection DEM/Walls/<face>: a planar wall on one face of the domain box.
    struct WallFace
    {
      bool active = false;
      dem::WallControl control = dem::WallControl::fixed;
      double velocity = 0;      ///< along the inward normal [m/s]
      double target_stress = 0; ///< compressive [Pa]
      double servo_gain = 0;    ///< [m/(s N)]
      double max_speed = 0;     ///< [m/s]

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
    };

    /// subsection DEM/Walls: one WallFace per face, in the order of `face_names`.
    struct Walls
    {
      static constexpr std::array<const char *, 6> face_names = {"x-", "x+", "y-", "y+", "z-", "z+"};
      std::array<WallFace, 6> face;

      /// Axis (0, 1, 2) and side (-1 lower, +1 upper) of face f.
      static int axis(int f) { return f / 2; }
      static int side(int f) { return f % 2 == 0 ? -1 : 1; }
      /// "DEM/Walls/<face>": where messages find face f.
      static std::string path(int f) { return std::string("DEM/Walls/") + face_names[f]; }

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// Active walls off the periodic axes of `domain`, servo walls with a gain and a speed cap.
      void check(Problems &problems, const Domain &domain) const;
    };

    /// subsection DEM/Boundary particles: fixed base and a loaded rigid clump on top.
    struct BoundaryParticles
    {
      std::optional<double> fix_below;   ///< [m], z of the centre
      std::optional<double> clump_above; ///< [m], z of the centre
      std::optional<double> base_thickness;     ///< [mean radii] above the domain's lower z
      std::optional<double> actuator_thickness; ///< [mean radii] below the sample's top
      double clump_force_rate = 0;       ///< dF/dt [N/s]
      Vec3 clump_force_direction = -Vec3::UnitZ(); ///< normalised when parsed (if nonzero)
      bool clump_rotation_locked = false;

      [[nodiscard]] bool has_fixed_base() const { return fix_below || base_thickness; }

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// The base and the clump chosen once each, below one another, thicknesses positive.
      void check(Problems &problems) const;
    };

    /// subsection DEM/Loading: adaptive quasi-static ramp of the clump force and the end of a test.
    /// The tests and what each reads are in dem/scene/lab_tests.h; the values of every test are
    /// kept here, for the model, the summary and the campaigns.
    struct Loading
    {
      const LabTest *test = &lab_tests().front();
      bool adaptive = false;
      dem::RampControlSettings ramp;  ///< fast_rate = Boundary particles/Clump force rate [N/s]
      double stop_strain = 0;         ///< |u_clump| / H0 at which the run ends, 0 = never
      // simple shear (dem/lab/simple_shear.h)
      double normal_stress = 1e4;        ///< [Pa]
      double shear_velocity = 1e-3;      ///< [m/s]
      double consolidation_time = 1e-3;  ///< [s]
      double final_shear_strain = 0.1;
      // triaxial and platen compression (dem/lab/triaxial_test.h, dem/lab/platen_compression_test.h)
      double confining_pressure = 1e5;   ///< [Pa]
      double axial_strain_rate = 1;      ///< [1/s]
      double final_axial_strain = 0.2;   ///< also the platen test's strain limit
      double max_servo_speed = 0;        ///< [m/s], 0 = 10 x strain rate x box length
      double platen_speed = 1e-2;        ///< [m/s]
      double post_peak_fraction = 0.5;
      // compaction (dem/lab/compaction_test.h)
      double compaction_strain_rate = 0; ///< [1/s]
      double curve_strain_interval = 0;  ///< strain between the compaction curve's history rows
      /// The values of a test that no other module reads (see Sample::settings).
      std::any settings;

      /// Declares Test and the entries of `test` (every entry of every test if null).
      static void declare_parameters(dealii::ParameterHandler &prm, const LabTest *test);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// The entries of this test, and what the test needs of the rest of `dem` (the DEM/ this
      /// loading belongs to): its walls and periodic axes, a fixed base and a clump, gravity.
      void check(Problems &problems, const Dem &dem) const;
    };

    /// subsection DEM/Bedding: bonds crossing a family of parallel planes get their own strengths
    /// (Zhao & Feng 2022, dem/sample/bedding.h).
    struct Bedding
    {
      bool enabled = false;
      double inclination_deg = 0;   ///< angle between the bedding planes and the x-y plane
      dem::BeddingSpec spec;        ///< normal from the inclination (rotated about y)

      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// Enabled bedding weakens bonds (`bond` must be enabled) at a positive spacing.
      void check(Problems &problems, const Bond &bond) const;
    };

    /// subsection DEM.
    struct Dem
    {
      Index steps = 1000;
      int threads = 0;
      std::uint64_t seed = 1;
      Domain domain;
      Material material;
      Bond bond;
      Sample sample;
      Integration integration;
      Walls walls;
      BoundaryParticles boundary;
      Loading loading;
      Bedding bedding;

      /// A clump to load: Boundary particles/Clump above [m] or Actuator thickness, or the sample's
      /// actuator layer.
      [[nodiscard]] bool has_clump() const
      {
        return boundary.clump_above || boundary.actuator_thickness || sample.actuator_count > 0;
      }

      static void declare_parameters(dealii::ParameterHandler &prm, const Declaration &declaration);
      void parse_parameters(dealii::ParameterHandler &prm);
    };
  } // namespace parameters

  namespace parameters
  {
    /// subsection Campaign: a virtual-laboratory campaign, loading angles x realizations x
    /// microstructures of the scene's mixed-mode test (dem/campaign/campaign.h).
    struct Campaign
    {
      enum class QuasiStaticCheck
      {
        none,
        first_realization, ///< every angle and microstructure of realization 0
        all
      };
      std::vector<double> loading_angles_deg; ///< psi; empty = the scene is a single run
      Index realizations = 1;                 ///< seeds DEM/Random seed + 0, 1, ...
      /// Each microstructure: (entry of DEM/Sample, value) pairs that override the scene's sample.
      std::vector<std::vector<std::pair<std::string, std::string>>> microstructures;
      std::string microstructures_text;       ///< as written, for messages
      QuasiStaticCheck quasi_static_check = QuasiStaticCheck::none;
      double quasi_static_slowdown = 4;       ///< rate divisor of the reference runs
      double quasi_static_tolerance = 0.02;   ///< allowed relative difference of the failure stress
      /// Displacement-controlled compaction test per realization (dem/lab/compaction_test.h), 0 = none.
      double compaction_strain_rate = 0;      ///< [1/s]
      double compaction_final_strain = 0;     ///< -u_z / H0 at which it ends
      double compaction_curve_strain_interval = 0; ///< strain between its curve's history rows

      [[nodiscard]] bool has_compaction_tests() const { return compaction_strain_rate > 0; }
      /// Simple shear of the collapsed layer per realization (dem/lab/simple_shear.h), 0 = none: the
      /// layer crushed under a normal stress above its strength, then sheared at it.
      double friction_normal_stress = 0;      ///< sigma_n [Pa]
      double friction_shear_velocity = 0;     ///< v of the platen [m/s]
      double friction_consolidation_time = 0; ///< the normal-force ramp [s]
      double friction_final_shear_strain = 0; ///< gamma at which the test ends
      /// Entries of DEM/Sample (entry, value) that the friction tests' sample sets after the
      /// microstructure's: a collapsed layer slides steadily only when it is thick enough
      /// (docs/calibration.md, "Friction of the collapsed layer"). Empty: the microstructure's sample.
      std::vector<std::pair<std::string, std::string>> friction_sample;
      std::string friction_sample_text; ///< as written, for messages and records

      [[nodiscard]] bool has_friction_tests() const { return friction_normal_stress > 0; }

      [[nodiscard]] bool enabled() const { return !loading_angles_deg.empty(); }

      static const EnumTable<QuasiStaticCheck> &check_names();
      static void declare_parameters(dealii::ParameterHandler &prm);
      void parse_parameters(dealii::ParameterHandler &prm);
      /// Angles where a scene of `kind` needs them, and what a campaign needs of `dem`: a
      /// load-controlled clump test with a fixed base, a clump, a rate and a stop strain.
      void check(Problems &problems, SceneKind kind, const Dem &dem) const;
    };
  } // namespace parameters

  /// Everything a scene file says, plus where it came from.
  struct SceneParameters
  {
    // --- provenance
    std::string file;                  ///< as given on the command line
    std::string file_sha256;           ///< of the file's bytes
    std::string canonical_parameters;  ///< every entry, sorted, as ParameterHandler prints it
    std::string parameters_sha256;     ///< of canonical_parameters
    /// Hash of the parameters that define the model, i.e. all but the Output subsection and
    /// DEM/Steps, DEM/Threads: a run may be resumed with more steps, other threads or outputs.
    std::string resume_key_sha256;

    // --- content
    SceneKind kind = SceneKind::dem;
    void (*declare_more)(dealii::ParameterHandler &prm) = nullptr; ///< as read (Declaration::declare_more)
    std::vector<std::string> components;
    parameters::Output output;
    parameters::Dem dem;
    parameters::Campaign campaign;

    static void declare_parameters(dealii::ParameterHandler &prm, const Declaration &declaration);
    void parse_parameters(dealii::ParameterHandler &prm);
    /// Everything a single pattern cannot check: each subsection's check, then the rules between
    /// subsections that belong to none (the clump's).
    void check(Problems &problems) const;
  };

  /// Reads, parses and validates a scene file; throws InputError with a complete message.
  /// `overrides` (entry path with '/' between subsections, value) are set after the file is read,
  /// as if the file said so: a campaign's microstructures are the scene with other sample entries.
  /// `kind`: what the scene file says it is (`set Scene = ...`), or the kind app/scenes.cpp
  /// inferred for a scene that does not say; an entry that belongs to another kind or to another
  /// variant (DEM/Sample/Type, DEM/Loading/Test) is refused with a message that names both.
  /// `declare_more`: see Declaration::declare_more.
  SceneParameters read_scene(const std::string &file, SceneKind kind,
                             const std::vector<std::pair<std::string, std::string>> &overrides = {},
                             void (*declare_more)(dealii::ParameterHandler &prm) = nullptr);

  /// Throws InputError unless the scene has a runnable component (Components = dem).
  void require_dem_component(const SceneParameters &scene);

  /// What a scene file of `kind` declares: its kind and the variants it chose (DEM/Sample/Type,
  /// DEM/Loading/Test; their defaults where it does not choose).
  Declaration scene_declaration(const std::string &file, SceneKind kind);
  Declaration scene_declaration(const std::string &file, SceneKind kind, void (*declare_more)(dealii::ParameterHandler &prm));

  /// Declares the entries of a DEM scene (what `anticrack params` lists).
  void declare_dem_scene(dealii::ParameterHandler &prm, const Declaration &declaration);

  /// Provenance for summary.json: the scene file (as given and absolute), its SHA-256 and those of
  /// the canonical parameters and of the resume key.
  nlohmann::ordered_json scene_info(const SceneParameters &scene);

  /// A vector for messages: "a, b, c", each as util/format.h's format_number() writes it.
  std::string format_vector(const Vec3 &v);
} // namespace anticrack::dem
