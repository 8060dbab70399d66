#include "fem/scene/snowpack_scene.h"
#include "fem/scene/profile_snowpack.h"
#include "profile/layer_properties.h"

#include "fem/material/collapsed_layer_friction.h"
#include "fem/material/column_collapse.h"
#include "fem/scene/crack_band.h"
#include "fem/scene/layers.h"
#include "util/format.h"
#include "util/input_error.h"
#include "util/named_rows.h"
#include "util/entry_table.h"
#include "util/parameter_files.h"
#include "util/parameter_input.h"
#include "util/problems.h"
#include "util/sha256.h"

#include <deal.II/base/parameter_handler.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

namespace anticrack::fem
{
  using dealii::ParameterHandler;
  using dealii::Patterns::Anything;
  using dealii::Patterns::Bool;
  using dealii::Patterns::Double;
  using dealii::Patterns::Integer;
  using dealii::Patterns::Selection;

  namespace
  {
    constexpr unsigned int max_slab_layers = 8;
    constexpr double pi = 3.14159265358979323846;

    void declare_layer(ParameterHandler &prm, const std::string &default_model, const std::string &default_thickness,
                       bool slab)
    {
      if (slab)
        prm.declare_entry("Tensile strength [Pa]", "", Anything(),
                          "sigma_t: tensile strength of the slab layer; a dynamic PST ends with a slab fracture (SF) "
                          "when the largest principal stress in the layer reaches it (detected, no tension "
                          "cut-off). Empty: Sigrist 2006's density law, 240 kPa (rho / 917 kg/m^3)^2.44. Units: Pa.");
      prm.declare_entry("Thickness [m]", default_thickness, Double(0),
                        "h: layer thickness measured normal to the slope. Units: m.");
      prm.declare_entry("Model", default_model, Selection(layer_model_names().pattern()),
                        "Constitutive model of the layer: linear elastic, or cohesive Cam-Clay with softening "
                        "(docs/physics.md §2).");
      prm.declare_entry("Material file", "", Anything(),
                        "Material file of a calibration (`anticrack calibrate`, subsection Material), relative to "
                        "the scene's directory; when given it replaces the inline material entries below.");
      prm.declare_entry("Collapse height [m]", "0", Double(0),
                        "h_c: collapse height, how far the faces of a collapsing layer approach before its grains "
                        "lock up (0: no lock-up); weak layers collapse by 3-5 mm of 10-30 mm (docs/physics.md "
                        "§2). A material file with subsection Collapse gives it instead (its lock-up strain times "
                        "Thickness); this entry must then be 0. Units: m.");
      prm.declare_entry("Densification modulus [Pa]", "0", Double(0),
                        "K_d: bulk modulus of the lock-up once the collapse height is used up. Units: Pa.");
      prm.declare_entry("Friction coefficient", "", Anything(),
                        "mu: Coulomb friction of the failed layer's grains, from failure on: once its bonds break "
                        "(or the saw reaches it) the layer keeps no cohesion and no tension, and carries shear on "
                        "its plane by |tau| <= mu sigma_n, sigma_n its layer-normal compression (docs/physics.md "
                        "§2). Required, in [0, 2], when the layer locks up (a collapse height, here or from the "
                        "material file); 0: the failed layer is frictionless; empty (no lock-up only): the "
                        "Cam-Clay residual surface alone carries the failed layer (Gaume et al. 2018). "
                        "Dimensionless.");
      declare_material_entries(prm);
    }

  } // namespace

  double optional_number(ParameterHandler &prm, const std::string &entry, const std::string &section,
                         const std::string &scene_file)
  {
    const std::string text = prm.get(entry);
    try
    {
      return parse_optional_number(text).value_or(std::numeric_limits<double>::quiet_NaN());
    }
    catch (const std::invalid_argument &)
    {
      throw InputError("Invalid scene file <" + scene_file + ">: " + section + "/" + entry + " = " + text +
                       " is not a number");
    }
  }

  namespace
  {

    Layer parse_layer(ParameterHandler &prm, const std::string &label, const std::string &section,
                      const std::string &scene_file, bool slab)
    {
      const std::filesystem::path scene_directory = std::filesystem::path(scene_file).parent_path();
      Layer layer;
      layer.label = label;
      layer.thickness = prm.get_double("Thickness [m]");
      layer.model = layer_model_names().value(prm.get("Model"));
      layer.collapse_height = prm.get_double("Collapse height [m]");
      layer.densification_modulus = prm.get_double("Densification modulus [Pa]");
      layer.friction_coefficient = optional_number(prm, "Friction coefficient", section, scene_file);
      layer.material = parse_material_entries(prm);
      const std::string file = prm.get("Material file");
      if (!file.empty())
      {
        const std::filesystem::path path = std::filesystem::path(file).is_absolute() ? std::filesystem::path(file) : scene_directory / file;
        layer.material_file = path.lexically_normal().string();
        try
        {
          const MaterialFile whole = read_whole_material_file(layer.material_file);
          layer.material = whole.material;
          layer.fracture_energy_density = whole.collapse.fracture_energy_density;
          layer.fracture_energy_density_interval = whole.collapse.fracture_energy_density_interval;
          layer.confidence = whole.uncertainty.confidence;
          if (whole.collapse.given())
          {
            // The calibrated layer's collapse is a strain (its compaction tests): its height here
            // is that strain times this layer's thickness.
            if (layer.collapse_height > 0 || layer.densification_modulus > 0)
              throw InputError("the material file gives the collapse (Material/Collapse/Lock-up strain = " +
                               format_number(whole.collapse.lock_up_strain) + ", Lock-up modulus [Pa] = " +
                               format_number(whole.collapse.lock_up_modulus) + "), and " + section +
                               "/Collapse height [m] and Densification modulus [Pa] must then be 0 (are " +
                               format_number(layer.collapse_height) + " and " +
                               format_number(layer.densification_modulus) + "): give it once");
            layer.collapse_height = whole.collapse.lock_up_strain * layer.thickness;
            layer.densification_modulus = whole.collapse.lock_up_modulus;
            layer.collapse_from_material_file = true;
          }
          if (!std::isnan(whole.collapse.friction_coefficient))
          {
            // The failed layer's friction measured in the DEM (the campaign's friction tests).
            if (!std::isnan(layer.friction_coefficient))
              throw InputError("the material file gives the failed layer's friction (Material/Collapse/Friction "
                               "coefficient = " + format_number(whole.collapse.friction_coefficient) + "), and " +
                               section + "/Friction coefficient must then be empty (is " +
                               format_number(layer.friction_coefficient) + "): give it once");
            layer.friction_coefficient = whole.collapse.friction_coefficient;
            layer.friction_from_material_file = true;
          }
        }
        catch (const InputError &e)
        {
          throw InputError("Invalid scene file <" + scene_file + ">: " + section + "/Material file = " + file +
                           ":\n" + e.what());
        }
      }
      if (layer.material.name.empty())
        layer.material.name = label;
      if (slab)
      {
        layer.tensile_strength = optional_number(prm, "Tensile strength [Pa]", section, scene_file);
        layer.tensile_strength_from_density = std::isnan(layer.tensile_strength);
        if (layer.tensile_strength_from_density && layer.material.density > 0)
          layer.tensile_strength = profile::sigrist_tensile_strength(layer.material.density);
      }
      return layer;
    }


    void check_layer(const Layer &layer, const std::string &section, bool thickness_may_be_zero,
                     double band_height, Problems &problems)
    {
      for (const std::string &entry : layer.unset_material_entries)
        problems.add(section + "/" + entry,
                     "must be given: an inline layer (no Material file) sets every entry its model (" +
                       std::string(layer_model_names().name(layer.model)) + ") uses; there are no defaults for physics");
      if (!thickness_may_be_zero && !(layer.thickness > 0))
        problems.add(section + "/Thickness [m]", "must be > 0 (is " + format_number(layer.thickness) + ")");
      if (!(layer.material.youngs_modulus > 0))
        problems.add(section + "/Young's modulus [Pa]", "must be > 0 (is " + format_number(layer.material.youngs_modulus) + ")");
      if (layer.collapse_height > 0 && !(layer.densification_modulus > 0))
        problems.add(section + "/Densification modulus [Pa]",
                     "must be > 0 when a collapse height is given (is " + format_number(layer.densification_modulus) + ")");
      // The lock-up and its friction belong to the cohesive Cam-Clay model (an elastic layer, as in
      // an energy release rate, ignores a material file's collapse).
      if (layer.model == Layer::Model::cohesive_cam_clay && layer.collapse_height > 0 &&
          std::isnan(layer.friction_coefficient))
        problems.add(section + "/Friction coefficient",
                     "must be given, in [0, 2], when the layer locks up (collapse height " +
                       format_number(layer.collapse_height) +
                       " m): the Coulomb friction of the failed layer's grains (0: frictionless)");
      if (!layer.tensile_strength_from_density && !std::isnan(layer.tensile_strength) && !(layer.tensile_strength > 0))
        problems.add(section + "/Tensile strength [Pa]",
                     "must be > 0, or empty for Sigrist 2006's density law (is " + format_number(layer.tensile_strength) + ")");
      if (!std::isnan(layer.friction_coefficient) && !(layer.friction_coefficient >= 0 && layer.friction_coefficient <= max_friction_coefficient))
        problems.add(section + "/Friction coefficient",
                     "must be in [0, 2] (is " + format_number(layer.friction_coefficient) + ")");
      if (layer.collapse_height > 0 && !(layer.collapse_height < 0.9 * band_height))
        problems.add(section + "/Collapse height [m]",
                     "the band that collapses (the weak layer's thickness; one element row of another layer) "
                     "must be able to close by the collapse height: it must be < 0.9 band heights, " +
                       format_number(0.9 * band_height) + " m (is " + format_number(layer.collapse_height) + ")");
      // The crack band scales ξ by the band height over the thickness the softening was measured
      // over (fem/scene/crack_band.h): without that thickness, ξ would be a mesh parameter.
      if (layer.model == Layer::Model::cohesive_cam_clay && !(layer.material.reference_thickness > 0))
        problems.add(section + (layer.material_file.empty() ? "/Reference thickness [m]" : "/Material file"),
                     "the reference thickness must be > 0 (is " + format_number(layer.material.reference_thickness) +
                       (layer.material_file.empty() ? "" : ", Material/Reference thickness [m] of " + layer.material_file) +
                       "): the thickness of the specimen over which the softening was measured, which the crack "
                       "band scales the hardening factor xi by (docs/physics.md §2)");
      if (layer.model == Layer::Model::cohesive_cam_clay && layer.collapse_height < 0.9 * band_height)
      {
        try
        {
          const CamClayParameters parameters = cam_clay_parameters(layer, band_height);
          // Small strain at collapse strains: the 1D column collapse against its finite-strain
          // reference (fem/material/column_collapse.h) must stay within the stated bounds.
          if (parameters.densification_strain > 0)
          {
            const ColumnCollapseComparison c = compare_column_collapse(parameters);
            if (!(c.work_error() <= max_collapse_work_error && c.peak_error() <= max_collapse_peak_error))
              problems.add(section + "/Collapse height [m]",
                           "the collapse strain h_c / H = " + format_number(c.closure_ratio) +
                             " is beyond the small-strain model's range: a 1D column collapse differs from its "
                             "finite-strain (Hencky) reference by " + format_number(100 * c.work_error(), 3) +
                             " % in the work to the lock-up and " + format_number(100 * c.peak_error(), 3) +
                             " % in the peak stress (allowed " + format_number(100 * max_collapse_work_error) +
                             " % and " + format_number(100 * max_collapse_peak_error) +
                             " %); use a thicker layer or a smaller collapse height (docs/physics.md §2)");
          }
        }
        catch (const std::exception &e)
        {
          problems.add(section, std::string("the cohesive Cam-Clay parameters are refused: ") + e.what());
        }
      }
    }
  } // namespace

  double Snowpack::slab_thickness() const
  {
    double sum = 0;
    for (const Layer &layer : slab_layers)
      sum += layer.thickness;
    return sum;
  }

  double Snowpack::slab_weight_per_area() const
  {
    double weight = 0;
    for (const Layer &layer : slab_layers)
      weight += layer.material.density * layer.thickness * gravity;
    return weight;
  }

  double Snowpack::weak_layer_top() const { return substratum.thickness + weak_layer.thickness; }

  double Snowpack::total_thickness() const { return weak_layer_top() + slab_thickness(); }

  const EnumTable<Layer::Model> &layer_model_names()
  {
    static const EnumTable<Layer::Model> names{{"elastic", Layer::Model::elastic},
                                               {"cohesive cam-clay", Layer::Model::cohesive_cam_clay}};
    return names;
  }

  const EnumTable<SawTest::ColumnEnds> &column_end_names()
  {
    static const EnumTable<SawTest::ColumnEnds> names{{"free", SawTest::ColumnEnds::free},
                                                      {"periodic", SawTest::ColumnEnds::periodic}};
    return names;
  }

  const EnumTable<SawTest::CutSide> &cut_side_names()
  {
    static const EnumTable<SawTest::CutSide> names{{"upslope", SawTest::CutSide::upslope},
                                                   {"downslope", SawTest::CutSide::downslope}};
    return names;
  }

  const EnumTable<SawTest::Saw> &saw_names()
  {
    static const EnumTable<SawTest::Saw> names{{"fixed", SawTest::Saw::fixed},
                                               {"advancing", SawTest::Saw::advancing},
                                               {"quasi-static", SawTest::Saw::quasi_static},
                                               {"bisection", SawTest::Saw::bisection},
                                               {"practice", SawTest::Saw::practice}};
    return names;
  }

  std::string slab_layer_section(const unsigned int k) { return "Slab layer " + std::to_string(k + 1); }

  const AnalysisType &analysis_type_named(const std::string &name) { return row_named(analysis_types(), name); }

  std::string analysis_type_pattern() { return names_pattern(analysis_types()); }

  const EnumTable<Analysis::LinearSolver> &linear_solver_names()
  {
    static const EnumTable<Analysis::LinearSolver> names{{"direct", Analysis::LinearSolver::direct},
                                                         {"amg", Analysis::LinearSolver::amg}};
    return names;
  }

  namespace
  {
    /// subsection Mesh: each entry declared and read from this one table.
    const std::vector<BoundEntry<MeshParameters>> &mesh_entries()
    {
      static const std::vector<BoundEntry<MeshParameters>> table = {
        {"Dimension", "2", &MeshParameters::dimension, 2, 3,
         "Spatial dimension: 2, plane strain in the slope-normal plane; 3, the whole column. Dimensionless."},
        {"Polynomial degree", "1", &MeshParameters::polynomial_degree, 1, 2,
         "p: polynomial degree of the Lagrange elements FE_Q. Dimensionless."},
        {"Element length [m]", "0.01", &MeshParameters::element_length, 0, no_upper_bound,
         "dx: element size along the slope (and across in 3D). Units: m."},
        {"Weak layer elements", "4", &MeshParameters::weak_layer_elements, 1, 64,
         "n_w: element rows through the weak-layer thickness. The layer deforms as one band "
         "(its inner nodes follow its faces linearly, docs/fem.md): more rows sample its state "
         "at more points. Dimensionless."},
        {"Slab element height [m]", "0.04", &MeshParameters::slab_element_height, 0, no_upper_bound,
         "h_s: largest element height in the slab layers (each layer gets the fewest rows no "
         "higher). Units: m."},
        {"Substratum element height [m]", "0.05", &MeshParameters::substratum_element_height, 0, no_upper_bound,
         "h_b: largest element height in the substratum (it gets the fewest rows no higher). "
         "Units: m."}};
      return table;
    }

    /// subsection Analysis/Newton: its numbers, each declared and read from this one table (the
    /// linear solver, a name, is read on its own).
    const std::vector<BoundEntry<Analysis>> &newton_entries()
    {
      static const std::vector<BoundEntry<Analysis>> table = {
        {"Tolerance", "1e-8", &Analysis::newton_tolerance, 1e-14, 1e-2,
         "tol: Newton converges when |residual| / |external force| is below it. Dimensionless."},
        {"Maximum iterations", "25", &Analysis::newton_max_iterations, 2, 500,
         "Largest number of Newton iterations per load step. Dimensionless."}};
      return table;
    }

    /// subsection Analysis/Newton of the analyses with a yielding weak layer: the gravity ramp.
    const std::vector<BoundEntry<Analysis>> &gravity_ramp_entries()
    {
      static const std::vector<BoundEntry<Analysis>> table = {
        {"Gravity steps", "4", &Analysis::gravity_steps, 1, 10000,
         "Initial number of load steps of the gravity ramp (a step that fails is halved). Dimensionless."}};
      return table;
    }

    /// subsection Analysis/Crack detection (analyses with a yielding weak layer).
    const std::vector<BoundEntry<Analysis>> &crack_detection_entries()
    {
      static const std::vector<BoundEntry<Analysis>> table = {
        {"Failure fraction", "0.9", &Analysis::failure_fraction, 0.01, 1,
         "f_fail: a weak-layer element has failed when its softening has gone this fraction of the way from "
         "p0 to the residual strength. Dimensionless."},
        {"Self-propagation lead [m]", "0", &Analysis::self_propagation_lead, 0, no_upper_bound,
         "d_lead: the crack runs by itself once its tip leads the saw by this much; 0: the slab thickness. "
         "Units: m."}};
      return table;
    }

    /// subsection Output: each entry declared and read from this one table.
    const std::vector<BoundEntry<OutputParameters>> &output_entries()
    {
      static const std::vector<BoundEntry<OutputParameters>> table = {
        {"Field interval [s]", "0.01", &OutputParameters::field_interval, 0, no_upper_bound,
         "Simulated time between field outputs fields/*.pvtu; 0: none. Units: s."},
        {"Series interval [s]", "1e-3", &OutputParameters::series_interval, 0, no_upper_bound,
         "Simulated time between rows of the time series series.h5 (explicit dynamics). Units: s."},
        {"Progress interval", "1000", &OutputParameters::progress_interval, 0, no_upper_bound,
         "Steps between progress lines on the console; 0: quiet. Units: steps."},
        {"Checkpoint interval", "10000", &OutputParameters::checkpoint_interval, 0, no_upper_bound,
         "Explicit steps between checkpoints (DIR/checkpoint.json and DIR/checkpoint/), from which "
         "`anticrack run --resume` continues; 0: none. Units: steps."}};
      return table;
    }
  } // namespace

  void declare_snowpack_scene(ParameterHandler &prm, const AnalysisType *const type)
  {
    // The analyses whose entries are declared: the scene's, or every one.
    std::vector<const AnalysisType *> analyses;
    for (const AnalysisType &t : analysis_types())
      if (!type || &t == type)
        analyses.push_back(&t);
    const auto any_analysis = [&](bool AnalysisType::*property) {
      return std::any_of(analyses.begin(), analyses.end(), [&](const AnalysisType *t) { return t->*property; });
    };
    const bool yielding = any_analysis(&AnalysisType::yielding_weak_layer);
    const bool dynamic = any_analysis(&AnalysisType::time_integration);

    // The kind is read by app/scenes.cpp before this declaration; declaring it lets the file say it.
    prm.declare_entry("Scene", "snowpack", Selection("snowpack"),
                      "What the scene is: `snowpack`, a layered snowpack and its saw test with the FE solver. "
                      "A scene without it that has a subsection Snowpack is read as one, with a note.");
    prm.enter_subsection("Snowpack");
    prm.declare_entry("Slope angle [deg]", "0", Double(0, 60),
                      "psi: inclination of the slope; +x points downslope. Units: deg.");
    prm.declare_entry("Gravity [m/s^2]", "9.81", Double(0), "g: gravitational acceleration. Units: m/s^2.");
    prm.declare_entry("Number of slab layers", "1", Integer(1, max_slab_layers),
                      "Number of slab layers, given top first in subsections `Slab layer 1`, `Slab layer 2`, ... "
                      "Dimensionless.");
    for (unsigned int k = 0; k < max_slab_layers; ++k)
    {
      prm.enter_subsection(slab_layer_section(k));
      declare_layer(prm, "elastic", "0.4", true);
      prm.leave_subsection();
    }
    prm.enter_subsection("Weak layer");
    declare_layer(prm, "cohesive cam-clay", "0.02", false);
    prm.leave_subsection();
    prm.enter_subsection("Substratum");
    declare_layer(prm, "elastic", "0.1", false);
    prm.leave_subsection();
    declare_profile_entries(prm);
    prm.leave_subsection();

    prm.enter_subsection("PST");
    prm.declare_entry("Column length [m]", "2.5", Double(0),
                      "L: length of the isolated column along the slope. Units: m.");
    prm.declare_entry("Column width [m]", "0.3", Double(0),
                      "W: width of the column across the slope (3D only). Units: m.");
    prm.declare_entry("Column ends", "free", Selection(column_end_names().pattern()),
                      "free: the isolated column of a PST, or an open-sided specimen; periodic: the column "
                      "repeats along the slope (and across it in 3D), an infinite slope or a laterally periodic "
                      "specimen (analyses that do not march in time).");
    prm.declare_entry("Cut from", "upslope", Selection(cut_side_names().pattern()),
                      "End of the column where the saw enters.");
    if (dynamic)
      prm.declare_entry("Saw", "advancing", Selection(saw_names().pattern()),
                        "fixed: the whole cut is made at once after the gravity equilibrium; advancing: the saw "
                        "moves at `Saw speed` up to `Cut length` (or until the crack runs by itself); quasi-static: "
                        "Newton saw steps of one element (halved down to 1/64) up to `Cut length` until equilibrium "
                        "is lost, then explicit dynamics from the last equilibrium with the next cut; bisection: "
                        "fixed cuts (the saw stopped), each made before the gravity ramp and followed in time to its "
                        "outcome, bisected between 0 and `Cut length` to one element length: the shortest cut from "
                        "which the test ends by itself (the crack runs, or the slab breaks), with its bracket; "
                        "practice: the same fixed cuts, started where an advancing saw's crack ran by itself (DIR/saw/) "
                        "and stepped away from it until the answer changes, then bisected: the critical cut as PST "
                        "practice reads it, and the saw's onset of the tip's lead as a second figure. Each trial in "
                        "DIR/fixed_cuts/cut_A/. docs/fem.md \"The critical cut\".");
    prm.declare_entry("Cut length [m]", "0.3", Double(0),
                      "a: the longest cut (energy release rate, quasi-static saw steps), the length of a fixed cut "
                      "or the longest cut of an advancing saw (explicit dynamics). Units: m.");
    if (dynamic)
    {
      prm.declare_entry("Saw speed [m/s]", "1", Double(0),
                        "v_saw: speed of an advancing saw (Saw = advancing, practice). Units: m/s.");
      prm.declare_entry("First trial cut [m]", "", Anything(),
                        "Saw = bisection: the first fixed cut tried, near the expected critical cut; the next "
                        "trials step away from it by one, two, four element lengths until the answer changes, "
                        "then bisect (a few trials when it is close; the answer does not depend on it). Empty: "
                        "the bisection starts at `Cut length`. Units: m.");
    }
    prm.leave_subsection();

    prm.enter_subsection("Mesh");
    declare_entries(prm, mesh_entries());
    prm.leave_subsection();

    prm.enter_subsection("Analysis");
    prm.declare_entry("Type", (type ? *type : default_analysis_type()).name,
                      Selection(type ? std::string(type->name) : analysis_type_pattern()),
                      name_paragraphs(analysis_types()));
    if (yielding)
      prm.declare_entry("Crack band regularisation", "true", Bool(),
                        "Softening slab or substratum layers (the weak layer is always one band through its "
                        "thickness): true: they soften and collapse in one element row with the energy and the "
                        "collapse height of the calibrated layer, xi_e = xi h_e / h_ref (crack band, Bažant & Oh "
                        "1983; docs/physics.md §2, mesh-independent); false: over their whole thickness.");
    prm.enter_subsection("Newton");
    declare_entries(prm, newton_entries());
    prm.declare_entry("Linear solver", "direct", Selection(linear_solver_names().pattern()),
                      "direct: MUMPS; amg: GMRES with BoomerAMG (large problems).");
    if (yielding)
      declare_entries(prm, gravity_ramp_entries());
    prm.leave_subsection();
    if (yielding)
    {
      prm.enter_subsection("Crack detection");
      declare_entries(prm, crack_detection_entries());
      prm.leave_subsection();
    }
    for (const AnalysisType *t : analyses)
      t->declare_parameters(prm);
    prm.leave_subsection();

    prm.enter_subsection("Output");
    declare_entries(prm, output_entries());
    prm.leave_subsection();
  }

  SnowpackScene read_snowpack_scene(const std::string &file)
  {
    return read_snowpack_scene_text(read_scene_file(file), file);
  }

  const AnalysisType &analysis_type_in(const std::string &text, const std::string &file)
  {
    const AnalysisType *type = &default_analysis_type();
    for (const ParameterSetting &setting : scan_parameter_settings(text)) // the last one counts, as in deal.II
      if (setting.path == std::vector<std::string>{"Analysis", "Type"})
      {
        try
        {
          type = &analysis_type_named(setting.value);
        }
        catch (const std::invalid_argument &)
        {
          throw InputError("Invalid scene file <" + file + ">, line " + std::to_string(setting.line) +
                           ": Analysis/Type = `" + setting.value + "` is none of " +
                           analysis_type_pattern());
        }
      }
    return *type;
  }

  namespace
  {
    /// Every entry the text sets that its analysis does not declare though another one does, with
    /// the analyses it belongs to; entries no snowpack scene knows are left to deal.II's message.
    void collect_entries_of_other_analyses(const std::string &text, const AnalysisType &type, Problems &problems)
    {
      const auto entries_of = [](const AnalysisType *t) {
        ParameterHandler prm;
        declare_snowpack_scene(prm, t);
        return declared_entries(prm);
      };
      const auto declared = entries_of(&type), known = entries_of(nullptr);
      for (const ParameterSetting &setting : scan_parameter_settings(text))
        if (!declared.count(setting.path) && known.count(setting.path))
        {
          const std::string owners = quoted_names(
            analysis_types(), [&](const AnalysisType &other) { return entries_of(&other).count(setting.path) > 0; });
          problems.add(setting.path_text() + " (line " + std::to_string(setting.line) + ")",
                       "belongs to Analysis/Type = " + owners + ", not to this scene's `" + type.name + "`");
        }
    }
  } // namespace

  SnowpackScene read_snowpack_scene_text(const std::string &text, const std::string &file)
  {
    {
      Problems foreign("scene file <" + file + ">");
      collect_entries_of_other_analyses(text, analysis_type_in(text, file), foreign);
      foreign.throw_if_any();
    }
    // Parsed against every entry: those that the analysis does not declare (refused above when set)
    // keep their documented defaults, which are the struct's.
    ParameterHandler prm;
    declare_snowpack_scene(prm, nullptr);
    try
    {
      parse_parameter_text(prm, text, file);
    }
    catch (const InputError &)
    {
      throw;
    }
    catch (const std::exception &e)
    {
      throw InputError("Invalid scene file <" + file + ">: " + e.what());
    }

    SnowpackScene scene;
    scene.file = file;
    Snowpack &s = scene.snowpack;
    prm.enter_subsection("Snowpack");
    s.slope_angle = prm.get_double("Slope angle [deg]") * pi / 180;
    s.gravity = prm.get_double("Gravity [m/s^2]");
    const unsigned int n_slab = prm.get_integer("Number of slab layers");
    for (unsigned int k = 0; k < n_slab; ++k)
    {
      prm.enter_subsection(slab_layer_section(k));
      s.slab_layers.push_back(
        parse_layer(prm, "slab layer " + std::to_string(k + 1), "Snowpack/" + slab_layer_section(k), file, true));
      prm.leave_subsection();
    }
    prm.enter_subsection("Weak layer");
    s.weak_layer = parse_layer(prm, "weak layer", "Snowpack/Weak layer", file, false);
    prm.leave_subsection();
    prm.enter_subsection("Substratum");
    s.substratum = parse_layer(prm, "substratum", "Snowpack/Substratum", file, false);
    prm.leave_subsection();
    prm.leave_subsection();
    std::set<std::string> given; // the entries the text sets
    for (const ParameterSetting &setting : scan_parameter_settings(text))
      given.insert(setting.path_text());
    {
      // An inline layer gives every entry its model uses: elasticity and density, and for a cohesive
      // Cam-Clay layer its surface and softening (the material file's entries but the name and the
      // yield surface plane, which has one value).
      auto note_unset = [&](Layer &layer, const std::string &section) {
        if (!layer.material_file.empty())
          return;
        for (const MaterialEntry &e : material_entries())
        {
          const bool elastic_entry = e.number == &ContinuumMaterial::density || e.number == &ContinuumMaterial::youngs_modulus ||
                                     e.number == &ContinuumMaterial::poisson_ratio;
          const bool used = elastic_entry || (layer.model == Layer::Model::cohesive_cam_clay && e.number) ||
                            (layer.model == Layer::Model::cohesive_cam_clay && e.text == &ContinuumMaterial::hardening_law);
          if (used && !given.count(section + "/" + e.name()))
            layer.unset_material_entries.push_back(e.name());
        }
      };
      for (unsigned int k = 0; k < s.slab_layers.size(); ++k)
        note_unset(s.slab_layers[k], "Snowpack/" + slab_layer_section(k));
      note_unset(s.weak_layer, "Snowpack/Weak layer");
      note_unset(s.substratum, "Snowpack/Substratum");
    }

    SawTest &pst = scene.pst;
    prm.enter_subsection("PST");
    pst.column_length = prm.get_double("Column length [m]");
    pst.column_width = prm.get_double("Column width [m]");
    pst.cut_side = cut_side_names().value(prm.get("Cut from"));
    pst.column_ends = column_end_names().value(prm.get("Column ends"));
    pst.saw = saw_names().value(prm.get("Saw"));
    pst.cut_length = prm.get_double("Cut length [m]");
    pst.saw_speed = prm.get_double("Saw speed [m/s]");
    if (const double first = optional_number(prm, "First trial cut [m]", "PST", file); !std::isnan(first))
      pst.first_trial_cut = first;
    prm.leave_subsection();
    // A snow profile replaces the slab (and, if asked, the slope and column): fem/scene/profile_snowpack.h.
    prm.enter_subsection("Snowpack");
    apply_profile(prm, scene, given, file);
    prm.leave_subsection();

    MeshParameters &mesh = scene.mesh;
    prm.enter_subsection("Mesh");
    parse_entries(prm, mesh_entries(), mesh);
    prm.leave_subsection();

    Analysis &analysis = scene.analysis;
    prm.enter_subsection("Analysis");
    analysis.type = &analysis_type_named(prm.get("Type"));
    analysis.crack_band = prm.get_bool("Crack band regularisation");
    prm.enter_subsection("Newton");
    parse_entries(prm, newton_entries(), analysis);
    analysis.linear_solver = linear_solver_names().value(prm.get("Linear solver"));
    parse_entries(prm, gravity_ramp_entries(), analysis);
    prm.leave_subsection();
    prm.enter_subsection("Crack detection");
    parse_entries(prm, crack_detection_entries(), analysis);
    prm.leave_subsection();
    // Entries of the other analyses are declared too (with their defaults); each reads only its own.
    analysis.type->parse_parameters(prm, scene);
    prm.leave_subsection();

    OutputParameters &output = scene.output;
    prm.enter_subsection("Output");
    parse_entries(prm, output_entries(), output);
    prm.leave_subsection();

    {
      std::ostringstream json_text;
      prm.print_parameters(json_text, ParameterHandler::ShortJSON);
      auto json = nlohmann::json::parse(json_text.str());
      json.erase("Output");
      json.erase("Scene");
      auto &explicit_entries = json["Analysis"]["Explicit"];
      for (auto entry = explicit_entries.begin(); entry != explicit_entries.end();)
        entry = entry.key().rfind("End time", 0) == 0 ? explicit_entries.erase(entry) : std::next(entry);
      std::string key = json.dump();
      for (const Layer *layer : {&s.weak_layer, &s.substratum})
        if (!layer->material_file.empty())
          key += util::sha256_of_file(layer->material_file);
      for (const Layer &layer : s.slab_layers)
        if (!layer.material_file.empty())
          key += util::sha256_of_file(layer.material_file);
      if (!scene.profile_record.is_null()) // the profile's content, not only its name
        key += util::sha256_of_file(scene.profile_record["file"].get<std::string>());
      scene.resume_key_sha256 = util::sha256_hex(key);
    }

    // --- what single patterns cannot check
    Problems problems("scene file <" + file + ">");
    for (unsigned int k = 0; k < s.slab_layers.size(); ++k)
      check_layer(s.slab_layers[k], "Snowpack/" + slab_layer_section(k), false,
                  band_height(scene, slab_layer_id(s, k)), problems);
    check_layer(s.weak_layer, "Snowpack/Weak layer", false, band_height(scene, layer_weak), problems);
    if (s.substratum.thickness > 0)
      check_layer(s.substratum, "Snowpack/Substratum", true, band_height(scene, layer_substratum), problems);
    // Q1 locks volumetrically as nu -> 1/2 (plane strain and 3D): the energy release rate's critical
    // cut of err_flat.prm on Q1 is off Q2's by 0.4 % at nu = 0.45, 2 % at 0.49 and 13 % at 0.499
    // (docs/work_precision.md), about 0.04 % / (1 - 2 nu); 1 % is reached at nu = 0.48.
    constexpr double largest_q1_poisson_ratio = 0.48;
    if (mesh.polynomial_degree == 1)
    {
      const auto check_locking = [&](const Layer &layer, const std::string &section) {
        if (layer.material.poisson_ratio > largest_q1_poisson_ratio)
          problems.add(section + (layer.material_file.empty() ? "/Poisson's ratio" : "/Material file"),
                       "nu = " + format_number(layer.material.poisson_ratio) + " locks Q1 elements (the energy release "
                       "rate is 2 % off at nu = 0.49, 13 % at 0.499; docs/work_precision.md): nu <= " +
                       format_number(largest_q1_poisson_ratio) + " with Mesh/Polynomial degree = 1, or set Mesh/Polynomial "
                       "degree = 2");
      };
      for (unsigned int k = 0; k < s.slab_layers.size(); ++k)
        check_locking(s.slab_layers[k], "Snowpack/" + slab_layer_section(k));
      check_locking(s.weak_layer, "Snowpack/Weak layer");
      if (s.substratum.thickness > 0)
        check_locking(s.substratum, "Snowpack/Substratum");
    }
    if (!(pst.column_length > 0))
      problems.add("PST/Column length [m]", "must be > 0 (is " + format_number(pst.column_length) + ")");
    if (mesh.dimension == 3 && !(pst.column_width > 0))
      problems.add("PST/Column width [m]", "must be > 0 in 3D (is " + format_number(pst.column_width) + ")");
    if (!(pst.cut_length < pst.column_length))
      problems.add("PST/Cut length [m]", "must be shorter than the column, " + format_number(pst.column_length) +
                                           " m (is " + format_number(pst.cut_length) + ")");
    if (pst.column_ends == SawTest::ColumnEnds::periodic && analysis.type->time_integration)
      problems.add("PST/Column ends", std::string("must be `free` for the analysis `") + analysis.type->name +
                                        "` (its lumped mass and explicit steps know no periodic ends; allowed with "
                                        "the analyses that do not march in time)");
    if ((pst.saw == SawTest::Saw::advancing || pst.saw == SawTest::Saw::practice) && analysis.type->time_integration &&
        !(pst.saw_speed > 0))
      problems.add("PST/Saw speed [m/s]", "must be > 0 for an advancing saw (Saw = advancing or practice; is " +
                                            format_number(pst.saw_speed) + ")");
    if (pst.first_trial_cut && pst.saw != SawTest::Saw::bisection)
      problems.add("PST/First trial cut [m]", "is read with Saw = bisection only (Saw = practice starts where its "
                                              "advancing saw's crack ran): leave it empty");
    else if (pst.first_trial_cut && !(*pst.first_trial_cut > 0 && *pst.first_trial_cut <= pst.cut_length))
      problems.add("PST/First trial cut [m]", "must lie in (0, Cut length = " + format_number(pst.cut_length) +
                                              "] (is " + format_number(*pst.first_trial_cut) + ")");
    if (!(mesh.element_length > 0) || !(mesh.element_length <= pst.column_length / 4))
      problems.add("Mesh/Element length [m]", "must lie in (0, column length / 4 = " +
                                                format_number(pst.column_length / 4) + "] (is " +
                                                format_number(mesh.element_length) + ")");
    if (!(mesh.slab_element_height > 0))
      problems.add("Mesh/Slab element height [m]", "must be > 0");
    if (!(mesh.substratum_element_height > 0))
      problems.add("Mesh/Substratum element height [m]", "must be > 0");
    if (analysis.type->yielding_weak_layer && s.weak_layer.model != Layer::Model::cohesive_cam_clay)
      problems.add("Snowpack/Weak layer/Model", std::string("must be `cohesive cam-clay` for the analysis `") + analysis.type->name +
                                                 "` (only a yielding weak layer can fail)");
    // A crack is a weak-layer element whose softening has gone Failure fraction of the way to the
    // residual: under the signed law compaction hardens, so a collapsing layer never gets there.
    if (analysis.type->yielding_weak_layer && s.weak_layer.model == Layer::Model::cohesive_cam_clay &&
        s.weak_layer.material.hardening_law != "collapse")
      problems.add(s.weak_layer.material_file.empty() ? "Snowpack/Weak layer/Hardening law" : "Snowpack/Weak layer/Material file",
                   "must be `collapse` for the analysis `" + std::string(analysis.type->name) + "` (is `" +
                     s.weak_layer.material.hardening_law + "`" +
                     (s.weak_layer.material_file.empty() ? "" : " in " + s.weak_layer.material_file) +
                     "): its crack detection needs a layer that softens as it collapses; under `signed` "
                     "compaction hardens and no collapsing element can fail");
    analysis.type->check(scene, problems);
    problems.throw_if_any();
    return scene;
  }
} // namespace anticrack::fem
