#include "fem/scene/profile_snowpack.h"

#include "profile/layer_properties.h"
#include "profile/profile_reader.h"
#include "util/format.h"
#include "util/input_error.h"
#include "util/parameter_files.h"

#include <deal.II/base/parameter_handler.h>

#include <cmath>

namespace anticrack::fem
{
  using dealii::ParameterHandler;
  namespace Patterns = dealii::Patterns;

  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// Which layer of the profile is the weak layer.
    enum class WeakLayerFrom
    {
      saw_test, ///< the layer the profile's saw test `Propagation saw test` failed in (the layer holding its depth)
      role,     ///< the one layer a layer table marks `weak`
      depth     ///< the layer holding `Weak layer depth [m]`
    };
    const EnumTable<WeakLayerFrom> &weak_layer_from_names()
    {
      static const EnumTable<WeakLayerFrom> names{
        {"saw test", WeakLayerFrom::saw_test}, {"role", WeakLayerFrom::role}, {"depth", WeakLayerFrom::depth}};
      return names;
    }

    std::string modulus_law_pattern()
    {
      std::string names;
      for (const profile::ModulusLaw &law : profile::modulus_laws())
        names += std::string(names.empty() ? "" : "|") + law.name;
      return names;
    }

    nlohmann::ordered_json sourced(const profile::Sourced &s)
    {
      return {{"value", s.value}, {"measured", s.measured}, {"source", s.source}};
    }
  } // namespace

  void declare_profile_entries(ParameterHandler &prm)
  {
    prm.enter_subsection("Profile");
    prm.declare_entry("Profile file", "", Patterns::Anything(),
                      "A snow profile (docs/profile.md): CAAML v6.0 SnowProfileIACS as SnowPilot and niViz export "
                      "it, or a CSV layer table; relative to the scene's directory. Given, the slab is the profile's "
                      "layers above its weak layer (Number of slab layers and the Slab layer subsections must then "
                      "not be set) and the weak layer's thickness is the profile's. Empty: the slab of the Slab "
                      "layer subsections.");
    prm.declare_entry("Weak layer from", "saw test", Patterns::Selection(weak_layer_from_names().pattern()),
                      "Which layer of the profile is the weak layer: saw test, the layer that the profile's "
                      "propagation saw test `Propagation saw test` failed in; role, the layer a layer table marks `weak`; "
                      "depth, the layer holding `Weak layer depth [m]`.");
    prm.declare_entry("Propagation saw test", "1", Patterns::Integer(1),
                      "The profile's propagation saw test (1: the first in the file) that names the weak layer, "
                      "whose observation the run records, and whose slope and column length the scene takes when "
                      "`Geometry from saw test` is true. Dimensionless.");
    prm.declare_entry("Weak layer depth [m]", "0", Patterns::Double(0),
                      "Depth below the snow surface within the weak layer (Weak layer from = depth). Units: m.");
    prm.declare_entry("Slab modulus law", profile::modulus_laws().front().name, Patterns::Selection(modulus_law_pattern()),
                      "Young's modulus of each slab layer from its density: Gerling 2017 (Gerling, Löwe & van "
                      "Herwijnen 2017, 6.0e-10 rho^4.6 MPa), Scapozza 2004 (0.1873 exp(0.0149 rho) MPa), Bergfeld "
                      "2023 (6.5e3 (rho/916.7)^4.4 MPa); docs/physics.md §3. At 250 kg/m^3 they give 64, 7.8 and "
                      "21 MPa.");
    prm.declare_entry("Slab Poisson's ratio", "", Patterns::Anything(),
                      "nu of every slab layer of the profile: no law of density is established, so it must be "
                      "given, in [0, 0.5). Dimensionless.");
    prm.declare_entry("Geometry from saw test", "false", Patterns::Bool(),
                      "true: Snowpack/Slope angle [deg] and PST/Column length [m] are the profile's (its slope, "
                      "the saw test's column), and must not be set in the scene.");
    prm.leave_subsection();
  }

  void apply_profile(ParameterHandler &prm, SnowpackScene &scene, const std::set<std::string> &given,
                     const std::string &scene_file)
  {
    prm.enter_subsection("Profile");
    const std::string file_entry = prm.get("Profile file");
    const WeakLayerFrom from = weak_layer_from_names().value(prm.get("Weak layer from"));
    const unsigned int saw_test = static_cast<unsigned int>(prm.get_integer("Propagation saw test"));
    const double weak_depth = prm.get_double("Weak layer depth [m]");
    const profile::ModulusLaw &law = profile::modulus_law(prm.get("Slab modulus law"));
    const std::string nu_text = prm.get("Slab Poisson's ratio");
    const bool geometry_from_test = prm.get_bool("Geometry from saw test");
    prm.leave_subsection();
    const std::string where = "Invalid scene file <" + scene_file + ">: Snowpack/Profile/";
    if (file_entry.empty())
    {
      // Without a profile its entries must keep their defaults (a listing of every entry, as
      // `anticrack params` prints it, is a valid scene); a value that would change something is refused.
      const bool changed = from != WeakLayerFrom::saw_test || saw_test != 1 || weak_depth != 0 || !nu_text.empty() ||
                           geometry_from_test || std::string(law.name) != profile::modulus_laws().front().name;
      if (changed)
        throw InputError(where + "Profile file is empty, so the other entries of Snowpack/Profile have no profile to apply "
                         "to: give the Profile file, or leave them at their defaults");
      return;
    }
    // What the profile replaces must not be given too: one source for each value.
    for (const std::string &entry : given)
      if (entry == "Snowpack/Number of slab layers" || entry.rfind("Snowpack/Slab layer ", 0) == 0 ||
          entry == "Snowpack/Weak layer/Thickness [m]" ||
          (geometry_from_test && (entry == "Snowpack/Slope angle [deg]" || entry == "PST/Column length [m]")))
        throw InputError(where + "Profile file = " + file_entry + " gives the slab" +
                         (geometry_from_test ? ", the weak layer's thickness, the slope and the column" : " and the weak layer's thickness") +
                         ": remove " + entry + " from the scene");
    prm.enter_subsection("Profile");
    const double nu = optional_number(prm, "Slab Poisson's ratio", "Snowpack/Profile", scene_file);
    prm.leave_subsection();
    if (!(nu >= 0 && nu < 0.5))
      throw InputError(where + "Slab Poisson's ratio = `" + nu_text + "` must be given, in [0, 0.5), with a profile");

    const profile::SnowProfile p = profile::read_profile(path_relative_to_scene(file_entry, scene_file));
    // The weak layer.
    int weak = -1;
    std::string chosen;
    if (from == WeakLayerFrom::saw_test || geometry_from_test)
      if (saw_test > p.saw_tests.size())
        throw InputError(where + "Propagation saw test = " + std::to_string(saw_test) + ": " + p.file + " holds " +
                         std::to_string(p.saw_tests.size()) + " propagation saw test(s)");
    if (from == WeakLayerFrom::saw_test)
    {
      const profile::SawTestObservation &t = p.saw_tests[saw_test - 1];
      weak = p.layer_at_depth(t.failed_depth_m);
      chosen = "the layer saw test " + std::to_string(saw_test) + " failed in (at " + format_number(100 * t.failed_depth_m, 4) + " cm)";
    }
    else if (from == WeakLayerFrom::role)
    {
      for (std::size_t k = 0; k < p.layers.size(); ++k)
        if (p.layers[k].role == profile::LayerRole::weak)
        {
          if (weak >= 0)
            throw InputError(where + "Weak layer from = role: " + p.file + " marks layers " + std::to_string(weak + 1) +
                             " and " + std::to_string(k + 1) + " `weak`; mark one");
          weak = static_cast<int>(k);
        }
      if (weak < 0)
        throw InputError(where + "Weak layer from = role: " + p.file + " marks no layer `weak`");
      chosen = "the layer marked weak";
    }
    else
    {
      weak = p.layer_at_depth(weak_depth);
      if (weak < 0)
        throw InputError(where + "Weak layer depth [m] = " + format_number(weak_depth) + " is not in " + p.file +
                         " (0 to " + format_number(p.height_m()) + " m)");
      chosen = "the layer at " + format_number(100 * weak_depth, 4) + " cm";
    }
    if (weak == 0)
      throw InputError(where + "Profile file = " + file_entry + ": the weak layer (" + chosen +
                       ") is the top layer of the profile: there is no slab above it");

    // The slab, top first, each layer with its properties and their sources.
    Snowpack &s = scene.snowpack;
    s.slab_layers.clear();
    nlohmann::ordered_json layers = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < p.layers.size(); ++k)
    {
      const profile::ProfileLayer &l = p.layers[k];
      nlohmann::ordered_json record{{"depth_top_m", l.depth_top_m}, {"thickness_m", l.thickness_m},
                                    {"grain_form", l.grain_form},
                                    {"hand_hardness", l.hardness ? l.hardness->text : ""},
                                    {"role", static_cast<int>(k) < weak ? "slab" : static_cast<int>(k) == weak ? "weak" : "below"}};
      if (l.grain_size_mm)
        record["grain_size_m"] = 1e-3 * *l.grain_size_mm;
      // The weak layer's own density, beside the calibrated material's (the report compares them) and
      // the DEM specimen's solid fraction (coupling/profile_specimen.h): measured in it (a density
      // sample counts if it lies mostly in the layer, profile::weak_layer_density) or inferred, or
      // why it cannot be had (e.g. surface hoar).
      if (static_cast<int>(k) == weak)
      {
        try
        {
          record["density_kg_m3"] = sourced(profile::weak_layer_density(p, k));
        }
        catch (const profile::ProfileError &e)
        {
          record["density_note"] = e.what();
        }
      }
      if (static_cast<int>(k) < weak)
      {
        const profile::LayerProperties props = profile::layer_properties(p, k, law, nu);
        Layer layer;
        layer.label = "slab layer " + std::to_string(k + 1) + " (profile, " + format_number(100 * l.depth_top_m, 4) +
                      "-" + format_number(100 * l.depth_bottom_m(), 4) + " cm" +
                      (l.grain_form.empty() ? "" : ", " + l.grain_form) + ")";
        layer.thickness = l.thickness_m;
        layer.model = Layer::Model::elastic;
        layer.material.name = layer.label;
        layer.material.density = props.density.value;
        layer.material.youngs_modulus = props.youngs_modulus.value;
        layer.material.poisson_ratio = props.poisson_ratio.value;
        layer.tensile_strength = props.tensile_strength.value;
        layer.tensile_strength_from_density = true;
        s.slab_layers.push_back(layer);
        record["density_kg_m3"] = sourced(props.density);
        record["youngs_modulus_Pa"] = sourced(props.youngs_modulus);
        record["poisson_ratio"] = sourced(props.poisson_ratio);
        record["tensile_strength_Pa"] = sourced(props.tensile_strength);
      }
      layers.push_back(record);
    }
    // A calibrated layer's collapse is a strain (its material file's lock-up strain): its height is
    // that strain times this thickness, not the scene's (the reader computed it with the scene's).
    const double thickness = p.layers[static_cast<std::size_t>(weak)].thickness_m;
    if (s.weak_layer.collapse_from_material_file && s.weak_layer.thickness > 0)
      s.weak_layer.collapse_height *= thickness / s.weak_layer.thickness;
    s.weak_layer.thickness = thickness;

    nlohmann::ordered_json r{{"file", p.file}, {"format", p.format}, {"id", p.id}, {"weak_layer", chosen},
                             {"weak_layer_index", weak + 1}, {"slab_modulus_law", law.citation}, {"layers", layers}};
    if (p.slope_angle_deg)
      r["slope_angle_deg"] = *p.slope_angle_deg;
    if (saw_test <= p.saw_tests.size())
    {
      const profile::SawTestObservation &t = p.saw_tests[saw_test - 1];
      r["observed_saw_test"] = {{"index", saw_test},
                                {"failed_depth_m", t.failed_depth_m},
                                {"propagation", t.propagation},
                                {"cut_length_m", t.cut_length_m},
                                {"column_length_m", t.column_length_m}};
    }
    if (geometry_from_test)
    {
      if (!p.slope_angle_deg)
        throw InputError(where + "Geometry from saw test = true: " + p.file + " gives no slope angle; set "
                         "Snowpack/Slope angle [deg] and Geometry from saw test = false");
      if (!(*p.slope_angle_deg >= 0 && *p.slope_angle_deg <= 60))
        throw InputError(where + "Geometry from saw test = true: " + p.file + " gives a slope of " +
                         format_number(*p.slope_angle_deg) + " deg, outside Snowpack/Slope angle [deg]'s [0, 60]");
      s.slope_angle = *p.slope_angle_deg * pi / 180;
      scene.pst.column_length = p.saw_tests[saw_test - 1].column_length_m;
    }
    scene.profile_record = r;
  }
} // namespace anticrack::fem
