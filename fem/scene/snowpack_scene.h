// Snowpack scenes: the layered snowpack, the propagation saw test (PST), the mesh, the analysis and
// the output of a finite-element run, read from a deal.II parameter file (.prm) that says
// `set Scene = snowpack` (app/scenes.cpp reads the kind). `Analysis/Type` is read in a first pass and
// declares only its own entries: an entry of another analysis is refused, naming the analyses it
// belongs to.
//
// Geometry (docs/physics.md §3). The model is built in slope-parallel coordinates: x runs along the slope,
// downslope positive, from the upslope end of the column (x = 0) to its downslope end (x = L); the
// last axis (y in 2D, z in 3D) is normal to the slope, pointing out of the snowpack, with 0 at the
// base of the substratum; in 3D, y spans the column width. Gravity is g (sin ψ e_x − cos ψ e_n).
// From the base up: substratum (may be absent), weak layer, slab layers (listed top first, as a
// snow profile is read). The base is fixed; every other face is free (an isolated PST column).
//
// Every entry's unit is in its name; the reader checks what single patterns cannot (a weak layer
// resolved by at least one element, a cut shorter than the column, a Cam-Clay weak layer for a
// propagation run, ...) and reports every problem at once with the file and the entry.
#pragma once

#include "fem/material/material_file.h"
#include "fem/scene/analysis_type.h"
#include "util/enum_table.h"

#include <any>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace anticrack::fem
{
  /// One layer of the snowpack with the constitutive model it uses.
  struct Layer
  {
    enum class Model
    {
      elastic,           ///< linear elastic (E, ν)
      cohesive_cam_clay  ///< elasticity + cohesive Cam-Clay with softening (docs/physics.md §2)
    };
    std::string label;          ///< "slab layer 1", "weak layer", "substratum" (for messages)
    double thickness = 0;       ///< [m]
    Model model = Model::elastic;
    ContinuumMaterial material; ///< from a material file or inline
    std::string material_file;  ///< the file it came from, "" if inline
    /// Lock-up of the collapsed pores (fem/material/cohesive_cam_clay.h): the collapse height of the layer
    /// [m] (how far its faces approach before the grains lock up; 0: no lock-up) and the lock-up's
    /// bulk modulus [Pa].
    double collapse_height = 0;
    /// collapse_height and densification_modulus come from the material file's Material/Collapse
    /// (its lock-up strain times thickness, its lock-up modulus), not from the scene.
    bool collapse_from_material_file = false;
    /// w_f [J/m³] of the material file's Material/Collapse (the DEM compaction tests'), 0 if none.
    double fracture_energy_density = 0;
    MaterialInterval fracture_energy_density_interval; ///< its interval (NaN if the file has none)
    double confidence = 0.95;                          ///< level of the file's intervals
    double densification_modulus = 0;
    /// μ: Coulomb friction of the failed layer on its normal compression, from failure on
    /// (fem/material/collapsed_layer_friction.h); from the scene or the material file; NaN when
    /// neither gives it, which is refused for a layer that locks up.
    double friction_coefficient = std::numeric_limits<double>::quiet_NaN();
    bool friction_from_material_file = false; ///< μ is the material file's (Material/Collapse), measured in the DEM
    /// σ_t [Pa] of a slab layer: a dynamic PST ends with a slab fracture when the largest
    /// principal stress in the layer reaches it. From the scene, or (entry empty) the density law
    /// of Sigrist 2006 (fem/closed_forms.h); NaN for the weak layer and the substratum.
    double tensile_strength = std::numeric_limits<double>::quiet_NaN();
    bool tensile_strength_from_density = false; ///< σ_t is Sigrist 2006's density law
    /// Entries of subsection Material that the layer's model uses and that an inline layer (no
    /// material file) left unset: refused by the scene check (no defaults for physics).
    std::vector<std::string> unset_material_entries;
  };

  /// The layered snowpack.
  struct Snowpack
  {
    std::vector<Layer> slab_layers; ///< top first
    Layer weak_layer;
    Layer substratum;               ///< thickness 0: the weak layer rests on the fixed base
    double slope_angle = 0;         ///< ψ [rad], downslope along +x
    double gravity = 9.81;          ///< [m/s²]

    double slab_thickness() const;
    /// g Σ ρ_i H_i over the slab layers [Pa]: the slab's weight per unit slope-parallel area.
    double slab_weight_per_area() const;
    /// Height of the slab's base (= top of the weak layer) above the model base [m].
    double weak_layer_top() const;
    double total_thickness() const;
  };

  /// The propagation saw test.
  struct SawTest
  {
    enum class CutSide
    {
      upslope,  ///< the saw enters at x = 0
      downslope ///< the saw enters at x = L
    };
    enum class Saw
    {
      fixed,        ///< the cut of `cut_length` is made at once (after the gravity equilibrium)
      advancing,    ///< the saw advances at `saw_speed` from 0 up to `cut_length`
      quasi_static, ///< Newton saw steps until equilibrium is lost, then explicit dynamics
      bisection,    ///< fixed cuts, each loaded by gravity, bisected to the critical cut
      practice      ///< an advancing saw, then fixed cuts from where its crack ran to the critical cut
    };
    enum class ColumnEnds
    {
      free,    ///< the isolated column of a PST (and an open-sided specimen)
      periodic ///< the column repeats along the slope (and across it in 3D): an infinite slope, a
               ///< laterally periodic specimen
    };
    double column_length = 2.5; ///< L [m]
    double column_width = 0.3;  ///< [m], 3D only
    CutSide cut_side = CutSide::upslope;
    Saw saw = Saw::advancing;
    double cut_length = 0.3;    ///< fixed cut, or the largest cut of an advancing saw [m]
    double saw_speed = 1;       ///< [m/s]
    /// Saw = bisection: the first fixed cut tried (near the answer: a few trials), or none: the
    /// bisection starts at `cut_length` [m].
    std::optional<double> first_trial_cut;
    ColumnEnds column_ends = ColumnEnds::free;
  };

  /// The structured, graded mesh.
  struct MeshParameters
  {
    unsigned int dimension = 2;          ///< 2 (plane strain) or 3
    unsigned int polynomial_degree = 1;  ///< of FE_Q
    double element_length = 0.01;        ///< along the slope (and across in 3D) [m]
    unsigned int weak_layer_elements = 4;///< elements through the weak-layer thickness
    double slab_element_height = 0.04;   ///< target height of slab elements [m]
    double substratum_element_height = 0.05; ///< target height of substratum elements [m]
  };

  /// What the run computes.
  struct Analysis
  {
    /// The analysis (fem/scene/analysis_type.h): a row of analysis_types(), set by the reader.
    const AnalysisType *type = nullptr;
    /// Values of an analysis that no solver reads, as its parse_parameters stores them (the
    /// analyses of fem/analysis/ keep theirs in the fields below, which the solvers read).
    std::any settings;
    /// Crack band regularisation of softening layers (fem/scene/crack_band.h); false: the local
    /// model, softening and collapse spread over the layer thickness in every element (for showing
    /// the mesh dependence the regularisation removes).
    bool crack_band = true;

    // energy release rate
    /// G_c [J/m²]: Analysis/Fracture energy [J/m^2], or (that entry 0) the weak layer's material
    /// file's fracture energy density times the layer's thickness.
    double fracture_energy = 0;
    double fracture_energy_entry = 0;    ///< the entry as given (0: from the material file)
    /// fracture_energy's interval when it comes from the material file (its w_f interval times the
    /// thickness), NaN otherwise.
    MaterialInterval fracture_energy_interval;
    bool fracture_energy_from_material_file = false;

    // Newton (gravity equilibrium and quasi-static steps)
    double newton_tolerance = 1e-8;      ///< on |r| / |f_ext|
    unsigned int newton_max_iterations = 25;
    enum class LinearSolver
    {
      direct, ///< MUMPS
      amg     ///< GMRES with BoomerAMG (hypre)
    };
    LinearSolver linear_solver = LinearSolver::direct;
    unsigned int gravity_steps = 4;      ///< initial number of load steps of the gravity ramp
    double saw_step = 0;                 ///< quasi-static cut increment [m]; 0 = one element length

    // explicit dynamics
    double end_time = 1;                 ///< [s] after the saw starts
    double cfl_safety = 0.5;             ///< Δt = safety · min h / c_p
    double linear_bulk_viscosity = 0.06; ///< c_1 of the bulk viscosity pressure
    double quadratic_bulk_viscosity = 1.2; ///< c_2 of the bulk viscosity pressure
    double mass_damping = 0;             ///< α_M of the damping force −α_M M v [1/s]
    /// Arr (or "no propagation"): once the saw has stopped, the crack tip has advanced less than
    /// arrest_speed · arrest_duration over the last arrest_duration [m/s, s].
    double arrest_speed = 0.5;
    double arrest_duration = 0.1;

    // crack detection (both PSTs: subsection Analysis/Crack detection)
    /// A weak-layer element counts as failed when its softening has used this fraction of the way
    /// from p0 to the residual strength (the crack tip is the farthest failed element).
    double failure_fraction = 0.9;
    /// The crack runs by itself once its tip leads the saw by this distance [m]; 0 = slab thickness.
    double self_propagation_lead = 0;
  };

  struct OutputParameters
  {
    double field_interval = 0.01;        ///< [s] between field outputs (explicit), 0 = none
    double series_interval = 1e-3;       ///< [s] between time-series rows (explicit)
    unsigned int progress_interval = 1000; ///< steps between progress lines, 0 = quiet
    unsigned int checkpoint_interval = 10000; ///< explicit steps between checkpoints, 0 = none
  };

  struct SnowpackScene
  {
    std::string file;   ///< where it was read from
    /// SHA-256 of every entry except Output and Analysis/Explicit/End time, and of the material
    /// files: a checkpoint resumes only a scene with the same key (the end time may be extended).
    std::string resume_key_sha256;
    Snowpack snowpack;
    SawTest pst;
    MeshParameters mesh;
    Analysis analysis;
    OutputParameters output;
    /// The snow profile the slab came from (Snowpack/Profile, fem/scene/profile_snowpack.h): every
    /// layer with its values and their sources, the weak layer, the observed saw test; null if none.
    Json profile_record;
  };

  /// The names of each selection of a snowpack scene (util/enum_table.h): one table per selection,
  /// for the entry's pattern, the parse, messages and summary.json.
  const EnumTable<Layer::Model> &layer_model_names();
  const EnumTable<SawTest::CutSide> &cut_side_names();
  const EnumTable<SawTest::Saw> &saw_names();
  const EnumTable<SawTest::ColumnEnds> &column_end_names();
  const EnumTable<Analysis::LinearSolver> &linear_solver_names();

  /// An entry of the current subsection that a scene gives only in some cases (so it has no
  /// default): NaN when empty; a value that is not a finite number throws InputError naming
  /// `section`/`entry` of `scene_file`.
  double optional_number(dealii::ParameterHandler &prm, const std::string &entry, const std::string &section,
                         const std::string &scene_file);

  /// "Slab layer k+1": the subsection of Snowpack that holds slab layer k (top first, from 0).
  std::string slab_layer_section(unsigned int k);

  /// Declares the entries of a snowpack scene whose Analysis/Type is `type` (nullptr: the entries
  /// of every type, as `anticrack params --every-variant` lists them).
  void declare_snowpack_scene(dealii::ParameterHandler &prm, const AnalysisType *type);

  /// The Analysis/Type that the scene text sets (default_analysis_type() when it sets none);
  /// throws anticrack::InputError naming the file and line of a value that is no type.
  const AnalysisType &analysis_type_in(const std::string &text, const std::string &file);

  /// Reads and checks a snowpack scene; throws anticrack::InputError (file, entry, value, range).
  /// Material files are looked up relative to the scene's directory.
  SnowpackScene read_snowpack_scene(const std::string &file);

  /// The same from the text of a scene; `file` names it in messages and locates material files.
  SnowpackScene read_snowpack_scene_text(const std::string &text, const std::string &file);
} // namespace anticrack::fem
