#include "coupling/profile_specimen.h"

#include "dem/scene/parameters.h"
#include "util/format.h"
#include "util/parameter_files.h"
#include "util/input_error.h"

#include <algorithm>
#include <cmath>

namespace anticrack::coupling
{
  namespace
  {
    std::string text(double value) { return format_number(value, 17); }
  } // namespace

  ProfileWeakLayer profile_weak_layer(const nlohmann::ordered_json &profile_record, const std::string &scene_file)
  {
    if (!profile_record.is_object() || !profile_record.contains("layers"))
      throw InputError("snowpack scene " + scene_file + " has no profile (Snowpack/Profile/Profile file): with "
                       "Pipeline/Weak layer specimen = profile, every snowpack scene's weak layer comes from its pit");
    ProfileWeakLayer w;
    w.scene = scene_file;
    w.profile_file = profile_record.value("file", std::string());
    w.layer = profile_record.at("weak_layer_index").get<int>();
    const nlohmann::ordered_json &l = profile_record.at("layers").at(static_cast<std::size_t>(w.layer - 1));
    w.grain_form = l.value("grain_form", std::string());
    w.thickness = l.at("thickness_m").get<double>();
    const std::string where = "snowpack scene " + scene_file + ": its weak layer, layer " + std::to_string(w.layer) +
                              " of " + w.profile_file + (w.grain_form.empty() ? "" : " (" + w.grain_form + ")");
    const std::string why = ", which Pipeline/Weak layer specimen = profile needs for the DEM specimen (the "
                            "solid fraction from the density, the thickness in grains from the grain size); "
                            "give it in the profile, or run this scene with Pipeline/Weak layer specimen = scene";
    if (!l.contains("grain_size_m") || !(l.at("grain_size_m").get<double>() > 0))
      throw InputError(where + ", gives no grain size" + why);
    w.grain_size = l.at("grain_size_m").get<double>();
    if (!l.contains("density_kg_m3"))
      throw InputError(where + ", has no density (" + l.value("density_note", std::string("none measured or inferred")) +
                       ")" + why);
    w.density = l.at("density_kg_m3").at("value").get<double>();
    w.density_source = l.at("density_kg_m3").value("source", std::string());
    if (!(w.thickness > 0) || !(w.density > 0))
      throw InputError(where + ", has a thickness of " + format_number(w.thickness) + " m and a density of " +
                       format_number(w.density) + " kg/m^3; both must be > 0");
    return w;
  }

  std::string ProfileSpecimen::name() const
  {
    return format_number(density, 6) + " kg/m^3, " + format_number(thickness_in_grains, 6) + " grains";
  }

  std::string ProfileSpecimen::directory() const
  {
    return "weak_layer_" + format_number(density, 6) + "kgm3_" + format_number(thickness_in_grains, 6) + "grains";
  }

  bool ProfileSpecimen::operator==(const ProfileSpecimen &other) const
  {
    return density == other.density && thickness_in_grains == other.thickness_in_grains &&
           lateral_extent == other.lateral_extent && solid_fraction == other.solid_fraction &&
           friction_thickness_in_grains == other.friction_thickness_in_grains &&
           friction_lateral_extent == other.friction_lateral_extent;
  }

  ProfileSpecimen profile_specimen(const ProfileWeakLayer &layer, const SpecimenRules &rules, double grain_density)
  {
    ProfileSpecimen s;
    s.density = rules.density_class_width * std::round(layer.density / rules.density_class_width);
    if (!(s.density > 0)) // a layer lighter than half a class: the lightest class
      s.density = rules.density_class_width;
    s.solid_fraction = s.density / grain_density;
    const double n = layer.thickness / layer.grain_size;
    s.thickness_in_grains = rules.thickness_classes.front();
    for (const double c : rules.thickness_classes)
      if (c <= n)
        s.thickness_in_grains = c;
    s.lateral_extent = rules.lateral_extent;
    // A collapsed specimen holds n phi / phi_d grain layers: a looser class needs more grains of
    // height to slide like the specimen n_f was measured on (SpecimenRules::friction_solid_fraction).
    const double looser = std::max(1.0, rules.friction_solid_fraction / s.solid_fraction);
    s.friction_thickness_in_grains = std::max(s.thickness_in_grains, rules.friction_thickness * looser);
    s.friction_lateral_extent = rules.friction_lateral_extent;
    return s;
  }

  namespace
  {
    /// N = 6 φ c² n³ / π, rounded.
    std::size_t box_particle_count(double solid_fraction, double lateral_extent, double thickness_in_grains)
    {
      return static_cast<std::size_t>(
        std::llround(6 * solid_fraction * lateral_extent * lateral_extent * std::pow(thickness_in_grains, 3) / M_PI));
    }
  } // namespace

  std::size_t specimen_particle_count(const ProfileSpecimen &s)
  {
    return box_particle_count(s.solid_fraction, s.lateral_extent, s.thickness_in_grains);
  }

  std::size_t friction_specimen_particle_count(const ProfileSpecimen &s)
  {
    return box_particle_count(s.solid_fraction, s.friction_lateral_extent, s.friction_thickness_in_grains);
  }

  double compaction_final_strain(const ProfileSpecimen &specimen, const dem::SceneParameters &scene, double diameter,
                                 const std::string &where)
  {
    // The rigid base and actuator layers (mean radii) do not compact; the layer between them does,
    // under uniaxial strain (periodic sides), so its solid fraction after a strain e is phi / (1 - e).
    const auto &b = scene.dem.boundary;
    const double rigid = (b.base_thickness.value_or(0) + b.actuator_thickness.value_or(0)) * 0.5 * diameter;
    const double scene_height = scene.dem.sample.box_edge, height = specimen.thickness_in_grains * diameter;
    const double scene_layer = scene_height - rigid, layer = height - rigid;
    if (!(layer > 0))
      throw InputError(where + ": a specimen of " + format_number(specimen.thickness_in_grains) +
                       " grains has no layer between its base and actuator (DEM/Boundary particles/Base and Actuator "
                       "thickness [mean radii]): raise Pipeline/Profile specimen/Thickness classes [grains]");
    const double scene_final = scene.campaign.compaction_final_strain * scene_height / scene_layer;
    const double final_fraction = scene.dem.sample.volume_fraction / (1 - scene_final);
    const double final_strain = 1 - specimen.solid_fraction / final_fraction;
    if (!(final_strain > 0 && final_strain < 1))
      throw InputError(where + ": the class's solid fraction " + format_number(specimen.solid_fraction) +
                       " is at or above the final solid fraction " + format_number(final_fraction) +
                       " of the scene's compaction test (Campaign/Compaction final strain)");
    return final_strain * layer / height;
  }

  std::vector<std::pair<std::string, std::string>> specimen_changes(const ProfileSpecimen &specimen,
                                                                    const dem::SceneParameters &scene,
                                                                    const std::string &where)
  {
    const auto &sample = scene.dem.sample;
    if (std::string(sample.type->name) != "sticky hard spheres")
      throw InputError(where + ": Pipeline/Weak layer specimen = profile makes the weak layer's sample a sticky-hard-"
                               "sphere box of the pit's solid fraction and thickness; the weak layer scene's sample is `" +
                       std::string(sample.type->name) + "` (DEM/Sample/Type)");
    // The scene's box: L_z = Box edge, L_x, L_y by the aspect ratios (dem/scene/samples/sticky_hard_spheres.cpp).
    const auto &a = sample.box_aspect_ratios;
    const double scene_height = sample.box_edge > 0 ? sample.box_edge : 0;
    if (!(scene_height > 0))
      throw InputError(where + ": Pipeline/Weak layer specimen = profile needs the weak layer scene's sample sized by "
                               "DEM/Sample/Box edge [m] (it is 0: sized by Radius [m])");
    const double scene_area = scene_height * scene_height * a[0] * a[1] / (a[2] * a[2]);
    const double diameter = 2 * sample.sticky_sphere_radius();
    const double height = specimen.thickness_in_grains * diameter;
    const double area = std::pow(specimen.lateral_extent * height, 2);
    // A larger box levels off later: the sweeps grow with N over the scene's N, never below the scene's.
    const auto sweeps_for = [&](std::size_t count) {
      const double count_ratio = static_cast<double>(count) / static_cast<double>(sample.particle_count);
      return static_cast<long long>(std::ceil(static_cast<double>(sample.sweeps) * std::max(1.0, count_ratio)));
    };
    const std::size_t count = specimen_particle_count(specimen);
    const auto sweeps = sweeps_for(count);
    std::vector<std::pair<std::string, std::string>> changes = {
      {"DEM/Sample/Volume fraction", text(specimen.solid_fraction)},
      {"DEM/Sample/Particle count", std::to_string(count)},
      {"DEM/Sample/Box edge [m]", text(height)},
      {"DEM/Sample/Box aspect ratios", text(specimen.lateral_extent) + ", " + text(specimen.lateral_extent) + ", 1"},
      {"DEM/Sample/Sweeps", std::to_string(sweeps)},
      {"DEM/Boundary particles/Clump force rate [N/s]", text(scene.dem.boundary.clump_force_rate * area / scene_area)}};
    if (scene.campaign.has_friction_tests())
    {
      const double friction_height = specimen.friction_thickness_in_grains * diameter;
      const std::size_t friction_count = friction_specimen_particle_count(specimen);
      const std::string c = text(specimen.friction_lateral_extent);
      changes.emplace_back("Campaign/Friction sample",
                           entry_changes_text({{"Particle count", std::to_string(friction_count)},
                                               {"Box edge [m]", text(friction_height)},
                                               {"Box aspect ratios", c + ", " + c + ", 1"},
                                               {"Sweeps", std::to_string(sweeps_for(friction_count))}}));
      changes.emplace_back("Campaign/Friction shear velocity [m/s]",
                           text(scene.campaign.friction_shear_velocity * friction_height / scene_height));
    }
    if (scene.campaign.compaction_final_strain > 0)
      changes.emplace_back("Campaign/Compaction final strain",
                           text(compaction_final_strain(specimen, scene, diameter, where)));
    return changes;
  }

  nlohmann::ordered_json specimen_record(const ProfileWeakLayer &layer, const ProfileSpecimen &specimen)
  {
    return {{"profile", layer.profile_file},
            {"layer", layer.layer},
            {"grain_form", layer.grain_form},
            {"thickness_m", layer.thickness},
            {"grain_size_m", layer.grain_size},
            {"density_kg_m3", layer.density},
            {"density_source", layer.density_source},
            {"thickness_in_grains", layer.thickness / layer.grain_size},
            {"specimen", {{"class", specimen.name()},
                          {"density_kg_m3", specimen.density},
                          {"solid_fraction", specimen.solid_fraction},
                          {"thickness_in_grains", specimen.thickness_in_grains},
                          {"lateral_extent_in_thicknesses", specimen.lateral_extent},
                          {"particle_count", specimen_particle_count(specimen)},
                          {"friction_specimen",
                           {{"thickness_in_grains", specimen.friction_thickness_in_grains},
                            {"lateral_extent_in_thicknesses", specimen.friction_lateral_extent},
                            {"particle_count", friction_specimen_particle_count(specimen)}}}}}};
  }
} // namespace anticrack::coupling
