#include "coupling/pipeline_scene.h"

#include "coupling/calibration_scene.h"
#include "dem/scene/parameters.h"
#include "fem/scene/snowpack_scene.h"
#include "util/format.h"
#include "util/input_error.h"
#include "util/parameter_files.h"
#include "util/parameter_input.h"
#include "util/problems.h"

#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace anticrack::coupling
{
  namespace fs = std::filesystem;
  namespace Patterns = dealii::Patterns;

  namespace
  {
    constexpr const char *weak_layer_entry = "Weak layer scene";
    constexpr const char *snowpack_entry = "Snowpack scenes";
    constexpr const char *bond_strength_entry = "Bond tensile strength [Pa]";
    constexpr const char *particle_density_entry = "Particle density [kg/m^3]";
    constexpr const char *bond_modulus_entry = "Bond modulus [Pa]";
    constexpr const char *grain_diameter_entry = "Grain diameter [m]";
    constexpr const char *specimen_entry = "Weak layer specimen";
    constexpr const char *density_class_entry = "Density class width [kg/m^3]";
    constexpr const char *thickness_classes_entry = "Thickness classes [grains]";
    constexpr const char *lateral_extent_entry = "Lateral extent [thicknesses]";
    constexpr const char *friction_thickness_entry = "Friction thickness [grains]";
    constexpr const char *friction_lateral_extent_entry = "Friction lateral extent [thicknesses]";
    constexpr const char *friction_solid_fraction_entry = "Friction thickness solid fraction";

    /// The weak layer's DEM scene, read as its kind reads it with `changes` (throws InputError).
    dem::SceneParameters weak_layer_dem_scene(const std::string &file,
                                              const std::vector<std::pair<std::string, std::string>> &changes)
    {
      if (scene_kind_in_file(file) == "calibration")
        return dem::read_scene(file, dem::SceneKind::calibration, changes, CalibrationParameters::declare_parameters);
      return dem::read_scene(file, dem::SceneKind::campaign, changes);
    }

    /// Weak layer k's scene text with the user's changes, then its specimen's, then the snow ratio's;
    /// `by` names who added them in the blocks' comments, `on` (may be empty) what the user's changes
    /// apply to.
    std::string weak_layer_text(const PipelineScene &scene, std::size_t k, const std::string &by, const std::string &on)
    {
      const std::string user = scene_text_with_changes(read_scene_file(scene.weak_layer_scene), scene.weak_layer_changes,
                                                       by + ": Pipeline/Weak layer scene changes" + on);
      const WeakLayerVariant &v = scene.weak_layers.at(k);
      const std::string specimen =
        !v.specimen ? user :
                      scene_text_with_changes(user, v.specimen_changes,
                                              by + ": the specimen of the pits' weak layers of " + v.specimen->name() +
                                                " (Pipeline/Weak layer specimen = profile; coupling/profile_specimen.h)");
      return scene_text_with_changes(specimen, scene.snow_ratio_changes,
                                     by + ": the DEM at the snow's bond modulus over tensile strength (Snow "
                                          "units; coupling/snow_units.h)");
    }

    /// The weak layers to calibrate: the scene's own, or one per class of the pits' (`pits`, one per
    /// snowpack scene, with Weak layer specimen = profile), each snowpack scene pointed at its own.
    void add_weak_layers(PipelineScene &scene, const std::vector<ProfileWeakLayer> &pits)
    {
      if (!scene.specimen_from_profile)
      {
        scene.weak_layers = {{"weak layer", "weak_layer", std::nullopt, {}}};
        return;
      }
      for (std::size_t k = 0; k < pits.size(); ++k)
      {
        const ProfileSpecimen specimen = profile_specimen(pits[k], scene.specimen_rules, scene.snow.particle_density);
        auto same = std::find_if(scene.weak_layers.begin(), scene.weak_layers.end(),
                                 [&](const WeakLayerVariant &v) { return *v.specimen == specimen; });
        if (same == scene.weak_layers.end())
          same = scene.weak_layers.insert(scene.weak_layers.end(),
                                          {"weak layer " + specimen.name(), specimen.directory(), specimen, {}});
        SnowpackWeakLayer &w = scene.snowpack_weak_layers[k];
        w.variant = static_cast<std::size_t>(same - scene.weak_layers.begin());
        w.grain_diameter = pits[k].grain_size;
        w.record = specimen_record(pits[k], specimen);
      }
      // One class: the pipeline's usual stage and folder.
      if (scene.weak_layers.size() == 1)
        scene.weak_layers.front().name = "weak layer", scene.weak_layers.front().directory = "weak_layer";
    }

    /// "a scene of kind `campaign`" or "a scene that does not say its kind".
    std::string kind_text(const std::string &file)
    {
      const std::string kind = scene_kind_in_file(file);
      return kind.empty() ? "a scene that does not say its kind" : "a scene of kind `" + kind + "`";
    }
  } // namespace

  void declare_pipeline_scene(dealii::ParameterHandler &prm)
  {
    prm.declare_entry("Scene", "pipeline", Patterns::Selection("pipeline"),
                      "What this scene is: the chain DEM weak layer -> calibration -> FE analyses.");
    prm.enter_subsection("Pipeline");
    prm.declare_entry(weak_layer_entry, "", Patterns::Anything(),
                      "A scene of kind `calibration` (DEM sample, campaign and the options of its calibration) or `campaign` (calibrated with the default options), "
                      "relative to this file: the weak layer of every snowpack scene below.",
                      /*has_to_be_set=*/true);
    prm.declare_entry(snowpack_entry, "", Patterns::List(Patterns::Anything()),
                      "Scenes of kind `snowpack`, comma-separated, relative to this file: each runs with the "
                      "calibrated material as its weak layer (Snowpack/Weak layer/Material file), the rest of "
                      "the scene as it is.",
                      /*has_to_be_set=*/true);
    prm.declare_entry("Snowpack scene changes", "", Patterns::Anything(),
                      "Entries set in every snowpack scene as the pipeline runs it, a comma-separated list of "
                      "`path = value` (e.g. `Mesh/Element length [m] = 0.02, Mesh/Weak layer elements = 2` for a "
                      "coarser, faster mesh); each stage's scene.prm shows them. Empty: the scenes as they are.");
    prm.declare_entry("Weak layer scene changes", "", Patterns::Anything(),
                      "Entries set in the weak layer's scene as the pipeline runs it, a comma-separated list of "
                      "`path = value` (e.g. `Campaign/Compaction strain rate [1/s] = 5, Campaign/Compaction final "
                      "strain = 0.35` to add the compaction tests to a campaign scene); the stage runs a copy, "
                      "weak_layer/scene.prm, that shows them. Empty: the scene as it is.");
    prm.declare_entry("Uncertainty", "sensitivities", Patterns::Selection("sensitivities|none"),
                      "sensitivities: every snowpack scene again with each calibrated parameter raised by one "
                      "standard error, for intervals on its answers (coupling/pipeline_uncertainty.h); none: the "
                      "answers without intervals.");
    prm.declare_entry(specimen_entry, "scene", Patterns::Selection("scene|profile"),
                      "scene: the weak layer scene's sample under every snowpack scene; profile: each snowpack "
                      "scene's weak layer from its pit (Snowpack/Profile): the sample's solid fraction from the "
                      "layer's density, its thickness in grains from the layer's thickness over its grain size, "
                      "the snow units' length from the grain size, one calibration per class of pits "
                      "(subsection Profile specimen; coupling/profile_specimen.h).");
    prm.enter_subsection("Profile specimen");
    prm.declare_entry(density_class_entry, "25", Patterns::Double(1),
                      "Delta rho: the pits' weak layers are sampled at the centre of their density's class, "
                      "Delta rho round(rho / Delta rho), so that pits of a class share one calibration. 25 kg/m^3 "
                      "is finer than the scatter of a density inferred from hand hardness (Geldsetzer & Jamieson "
                      "2000). Units: kg/m^3.");
    prm.declare_entry(thickness_classes_entry, "5, 10", Patterns::List(Patterns::Double(3), 1),
                      "the specimen's thicknesses in grains, ascending: a layer of n = thickness / grain size "
                      "grains is sampled at the largest class at or below n (the smallest for a thinner layer). "
                      "A thick layer's collapse localises in a compaction band (Ritter et al. 2020), its "
                      "strength is the bulk's, and the FE crack band carries the softening from the specimen's "
                      "thickness to the element rows. Dimensionless.");
    prm.declare_entry(lateral_extent_entry, "2.8", Patterns::Double(1),
                      "c: the specimen's lateral edges over its thickness (periodic laterally); the strengths "
                      "level off from about 2.8 thicknesses (docs/work_precision.md, the lateral-extent study). "
                      "Dimensionless.");
    prm.declare_entry(friction_thickness_entry, "15", Patterns::Double(3),
                      "n_f: the friction tests (Campaign/Friction normal stress) shear a specimen of their own, "
                      "max(n, n_f) grains thick: a collapsed 10-grain layer sticks and slips with tau/sigma "
                      "swinging through zero, a 15-grain one slides at a steady ratio (docs/calibration.md, the "
                      "thickness study). Dimensionless.");
    prm.declare_entry(friction_solid_fraction_entry, "0.218", Patterns::Double(0, 1),
                      "phi_f: the solid fraction at which n_f was measured; a looser class's friction specimen "
                      "is n_f phi_f / phi grains thick, so that it holds as much ice per area, and as many grain "
                      "layers once the normal stress has collapsed it: at phi = 0.164 and n_f = 15 a 15-grain "
                      "cube, about 5 grains once collapsed, stuck and slipped (tau/sigma 0.19, -0.17, 0.12). "
                      "Never thinner than n_f; 0 = n_f at every phi. Dimensionless.");
    prm.declare_entry(friction_lateral_extent_entry, "1", Patterns::Double(1),
                      "c_f: the friction specimen's lateral edges over its thickness (periodic laterally); a "
                      "wider box adds slip events at large shear strain (docs/calibration.md). Dimensionless.");
    prm.leave_subsection();
    prm.leave_subsection();
    prm.enter_subsection("Snow units");
    prm.declare_entry(bond_strength_entry, "0", Patterns::Double(0),
                      "sigma_c: tensile strength of the snow's bonds. Every modulus and strength of the DEM scales by "
                      "it over the DEM's bond tensile strength (coupling/snow_units.h). Units: Pa.",
                      /*has_to_be_set=*/true);
    prm.declare_entry(bond_modulus_entry, "0", Patterns::Double(0),
                      "E_bar: modulus of the snow's bonds. The weak layer's DEM is run at E_bar / sigma_c (its bond "
                      "and contact moduli and its grains' density scaled together, the time step unchanged; "
                      "coupling/snow_units.h): the DEM's response depends on the ratio. Units: Pa.",
                      /*has_to_be_set=*/true);
    prm.declare_entry(grain_diameter_entry, "0", Patterns::Double(0),
                      "d: diameter of the snow's grains; every length of the DEM (the softening's reference "
                      "thickness) scales by it over the DEM's mean sphere diameter. Units: m.",
                      /*has_to_be_set=*/true);
    prm.declare_entry(particle_density_entry, "0", Patterns::Double(0),
                      "rho: density of the snow's grains (ice: 917); the layer's density is the DEM's solid "
                      "fraction times it. Units: kg/m^3.",
                      /*has_to_be_set=*/true);
    prm.leave_subsection();
  }

  CalibrateOptions weak_layer_calibration(const PipelineScene &scene, const std::string &file,
                                          const std::vector<std::pair<std::string, std::string>> &changes)
  {
    if (scene_kind_in_file(file) == "calibration")
      return read_calibration_scene(file, changes);
    const dem::SceneParameters campaign = dem::read_scene(file, dem::SceneKind::campaign, changes);
    dem::require_dem_component(campaign);
    if (!campaign.campaign.enabled())
      throw InputError(scene.file + ": Pipeline/Weak layer scene names " + scene.weak_layer_scene +
                       ", which has no campaign (Campaign/Loading angles [deg] is empty)");
    CalibrateOptions options;
    options.input = file;
    return options;
  }

  std::string weak_layer_scene_text(const PipelineScene &scene, std::size_t k)
  {
    return weak_layer_text(scene, k, "by the pipeline " + scene.file, ", on " + scene.weak_layer_scene);
  }

  std::string weak_layer_material_inputs(const PipelineScene &scene, std::size_t k)
  {
    return weak_layer_text(scene, k, "by the pipeline", "") + snow_units_text(scene.snow);
  }

  std::string snow_units_text(const SnowUnits &snow)
  {
    // 17 digits: every double to the bit, so that the cache key tells any two snows apart.
    return "\nSnow units: " + format_number(snow.bond_tensile_strength, 17) + " " +
           format_number(snow.particle_density, 17) + " " + format_number(snow.bond_modulus, 17) + " " +
           format_number(snow.grain_diameter, 17);
  }

  std::string snowpack_scene_text(const PipelineScene &scene, const std::string &file, const std::string &material_file)
  {
    // The stage runs a copy of the scene from its own folder: relocatable_scene_text makes the
    // material files of its other layers absolute.
    std::string text = scene_text_with_changes(relocatable_scene_text(file), scene.snowpack_changes,
                                               "by the pipeline " + scene.file + ": Pipeline/Snowpack scene changes");
    if (material_file.empty())
      return text;
    text += "\n# Added by the pipeline: the weak layer is the calibrated material (the inline\n"
            "# weak-layer material entries above are replaced by it).\n"
            "subsection Snowpack\n  subsection Weak layer\n    set Material file = " +
            material_file + "\n";
    const fem::MaterialCollapse collapse = fem::read_whole_material_file(material_file).collapse;
    if (collapse.given())
      text += "    # Its Material/Collapse (the DEM compaction tests' lock-up strain and modulus) gives the\n"
              "    # collapse height (lock-up strain x Thickness) and the densification modulus.\n"
              "    set Collapse height [m] = 0\n    set Densification modulus [Pa] = 0\n";
    if (!std::isnan(collapse.friction_coefficient))
      text += "    # Its Material/Collapse/Friction coefficient (the DEM friction tests' mu) is the failed\n"
              "    # layer's friction.\n"
              "    set Friction coefficient =\n";
    text += "  end\nend\n";
    const std::string analysis = fem::read_snowpack_scene_text(read_scene_file(file), file).analysis.type->name;
    if (collapse.fracture_energy_density > 0 && analysis == std::string("energy release rate"))
      text += "# The fracture energy is the material file's too (fracture energy density x Thickness).\n"
              "subsection Analysis\n  set Fracture energy [J/m^2] = 0\nend\n";
    return text;
  }

  PipelineScene read_pipeline_scene(const std::string &file)
  {
    dealii::ParameterHandler prm;
    declare_pipeline_scene(prm);
    parse_parameter_text(prm, read_scene_file(file), file);
    Problems problems("scene file <" + file + ">");
    for (const std::string &missing : prm.get_entries_wrongly_not_set())
      problems.add(demangled_parameter_path(missing), "must be set (a pipeline has no defaults for it)");
    problems.throw_if_any();

    PipelineScene scene;
    scene.file = file;
    prm.enter_subsection("Pipeline");
    scene.weak_layer_scene = path_relative_to_scene(dealii::Utilities::trim(prm.get(weak_layer_entry)), file);
    for (const std::string &s : dealii::Utilities::split_string_list(prm.get(snowpack_entry)))
      scene.snowpack_scenes.push_back(path_relative_to_scene(s, file));
    scene.uncertainty = prm.get("Uncertainty") == "sensitivities";
    scene.snowpack_changes = entry_changes_in_list(prm.get("Snowpack scene changes"), "Pipeline/Snowpack scene changes", problems);
    scene.weak_layer_changes =
      entry_changes_in_list(prm.get("Weak layer scene changes"), "Pipeline/Weak layer scene changes", problems);
    scene.specimen_from_profile = prm.get(specimen_entry) == "profile";
    prm.enter_subsection("Profile specimen");
    scene.specimen_rules.density_class_width = prm.get_double(density_class_entry);
    const std::string thickness_classes = prm.get(thickness_classes_entry);
    for (const std::string &c : dealii::Utilities::split_string_list(thickness_classes))
      scene.specimen_rules.thickness_classes.push_back(dealii::Utilities::string_to_double(c));
    scene.specimen_rules.lateral_extent = prm.get_double(lateral_extent_entry);
    scene.specimen_rules.friction_thickness = prm.get_double(friction_thickness_entry);
    scene.specimen_rules.friction_lateral_extent = prm.get_double(friction_lateral_extent_entry);
    scene.specimen_rules.friction_solid_fraction = prm.get_double(friction_solid_fraction_entry);
    prm.leave_subsection();
    prm.leave_subsection();
    if (!std::is_sorted(scene.specimen_rules.thickness_classes.begin(), scene.specimen_rules.thickness_classes.end()))
      problems.add(std::string("Pipeline/Profile specimen/") + thickness_classes_entry, thickness_classes,
                   "must be ascending");
    prm.enter_subsection("Snow units");
    scene.snow.bond_tensile_strength = prm.get_double(bond_strength_entry);
    scene.snow.particle_density = prm.get_double(particle_density_entry);
    scene.snow.bond_modulus = prm.get_double(bond_modulus_entry);
    scene.snow.grain_diameter = prm.get_double(grain_diameter_entry);
    prm.leave_subsection();

    if (scene.snowpack_scenes.empty())
      problems.add(std::string("Pipeline/") + snowpack_entry, "names no scene (at least one snowpack scene)");
    // Each stage's scene by its own reader: every problem is found before anything runs.
    const auto check_exists = [&](const std::string &path, const std::string &entry) {
      if (!fs::exists(path))
        problems.add(entry, "names " + path + ", which does not exist");
      return fs::exists(path);
    };
    if (!(scene.snow.bond_tensile_strength > 0))
      problems.add(std::string("Snow units/") + bond_strength_entry, scene.snow.bond_tensile_strength, "must be > 0");
    if (!(scene.snow.particle_density > 0))
      problems.add(std::string("Snow units/") + particle_density_entry, scene.snow.particle_density, "must be > 0");
    if (!(scene.snow.bond_modulus > 0))
      problems.add(std::string("Snow units/") + bond_modulus_entry, scene.snow.bond_modulus, "must be > 0");
    if (!(scene.snow.grain_diameter > 0))
      problems.add(std::string("Snow units/") + grain_diameter_entry, scene.snow.grain_diameter, "must be > 0");
    const std::string weak_entry = std::string("Pipeline/") + weak_layer_entry;
    if (check_exists(scene.weak_layer_scene, weak_entry))
    {
      const std::string kind = scene_kind_in_file(scene.weak_layer_scene);
      if (kind != "calibration" && kind != "campaign")
        problems.add(weak_entry, "names " + scene.weak_layer_scene + ", " + kind_text(scene.weak_layer_scene) +
                                   "; it must be of kind `calibration` or `campaign` (calibrated with the "
                                   "default options)");
    }
    std::vector<ProfileWeakLayer> pits; // the pits' weak layers, with Weak layer specimen = profile
    for (const std::string &s : scene.snowpack_scenes)
    {
      const std::string entry = std::string("Pipeline/") + snowpack_entry;
      scene.snowpack_weak_layers.emplace_back();
      if (!check_exists(s, entry))
        continue;
      if (scene_kind_in_file(s) != "snowpack")
      {
        problems.add(entry, "names " + s + ", " + kind_text(s) + "; it must be of kind `snowpack` (set Scene = snowpack)");
        continue;
      }
      // As the pipeline runs it: with the changes (an unknown entry or value is refused here).
      const fem::SnowpackScene snowpack = fem::read_snowpack_scene_text(snowpack_scene_text(scene, s, ""), s);
      // The calibrated weak layer is a cohesive Cam-Clay material; an elastic one takes only its
      // elasticity, which only an analysis without a yielding weak layer (the energy release rate,
      // elastic layers throughout) may ask for: the criterion the pipeline's uncertainty stage uses too.
      if (snowpack.snowpack.weak_layer.model != fem::Layer::Model::cohesive_cam_clay && snowpack.analysis.type->yielding_weak_layer)
        problems.add(entry, "names " + s + ", whose weak layer is not a cohesive Cam-Clay layer (Snowpack/Weak layer/Model); "
                            "only an energy release rate scene may have an elastic one");
      if (scene.specimen_from_profile)
      {
        try
        {
          pits.push_back(profile_weak_layer(snowpack.profile_record, s));
        }
        catch (const InputError &e)
        {
          problems.add(std::string("Pipeline/") + specimen_entry + " = profile", e.what());
        }
      }
    }
    if (scene.specimen_from_profile && scene.uncertainty && scene.snowpack_scenes.size() > 1)
      problems.add(std::string("Pipeline/") + specimen_entry + " = profile",
                   "with several snowpack scenes, each may have a weak layer of its own class: set Pipeline/Uncertainty "
                   "= none (the uncertainty stage carries one calibration's intervals)");
    problems.throw_if_any();
    add_weak_layers(scene, pits);
    try
    {
      weak_layer_calibration(scene, scene.weak_layer_scene, scene.weak_layer_changes);
    }
    catch (const InputError &e)
    {
      throw InputError("Invalid scene file <" + file + ">: Pipeline/" + weak_layer_entry + " = " + scene.weak_layer_scene +
                       (scene.weak_layer_changes.empty() ? "" : " with Pipeline/Weak layer scene changes") + ":\n" +
                       e.what());
    }
    // The DEM at the snow's ratio: its entries after the user's changes (the last setting wins).
    scene.snow_ratio_changes =
      snow_ratio_changes(weak_layer_dem_scene(scene.weak_layer_scene, scene.weak_layer_changes), scene.snow,
                         "Invalid scene file <" + file + ">: Snow units with Pipeline/" + weak_layer_entry + " = " +
                           scene.weak_layer_scene);
    const dem::SceneParameters weak_layer_dem = weak_layer_dem_scene(scene.weak_layer_scene, scene.weak_layer_changes);
    for (WeakLayerVariant &v : scene.weak_layers)
    {
      if (!v.specimen)
        continue;
      const std::string where = "Invalid scene file <" + file + ">: Pipeline/" + specimen_entry + " = profile, class " +
                                v.specimen->name() + ", with Pipeline/" + weak_layer_entry + " = " + scene.weak_layer_scene;
      v.specimen_changes = specimen_changes(*v.specimen, weak_layer_dem, where);
    }
    // Each weak layer's scene as its stage runs it; the classes' problems all at once.
    Problems specimens("scene file <" + file + ">: Pipeline/" + specimen_entry + " = profile with Pipeline/" +
                       weak_layer_entry + " = " + scene.weak_layer_scene);
    for (const WeakLayerVariant &v : scene.weak_layers)
    {
      if (scene.snow_ratio_changes.empty() && v.specimen_changes.empty())
        continue;
      auto changes = scene.weak_layer_changes;
      changes.insert(changes.end(), v.specimen_changes.begin(), v.specimen_changes.end());
      changes.insert(changes.end(), scene.snow_ratio_changes.begin(), scene.snow_ratio_changes.end());
      try
      {
        weak_layer_calibration(scene, scene.weak_layer_scene, changes);
      }
      catch (const InputError &e)
      {
        if (!v.specimen)
          throw;
        std::string pits_of_class;
        for (std::size_t k = 0; k < scene.snowpack_scenes.size(); ++k)
          if (&scene.weak_layers[scene.snowpack_weak_layers[k].variant] == &v)
            pits_of_class += (pits_of_class.empty() ? "" : ", ") + fs::path(scene.snowpack_scenes[k]).filename().string();
        specimens.add("the specimen of class " + v.specimen->name() + " (the weak layers of " + pits_of_class +
                      ") cannot be made: " + e.what());
      }
    }
    specimens.throw_if_any();
    return scene;
  }
} // namespace anticrack::coupling
