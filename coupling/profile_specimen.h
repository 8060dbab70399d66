// The weak layer's DEM specimen from the pit's own weak layer (Pipeline/Weak layer specimen =
// profile): the layer's density sets the sample's solid fraction, its thickness over its grain size
// the specimen's thickness in grains, and its grain size the snow units' length, instead of the
// weak-layer scene's fixed specimen under every pit.
//
// The conversion (docs/pipeline.md lists its assumptions with their references):
//   - solid fraction φ = ρ_class / ρ_grain. The layer's density ρ is the profile's, measured or
//     inferred (Geldsetzer & Jamieson 2000, profile/layer_properties.h), put in a class of width Δρ
//     (its centre Δρ round(ρ/Δρ)), so that pits of one density class share one DEM campaign (the
//     material cache, coupling/material_cache.h);
//   - thickness in grains n = h / d with the layer's thickness h and grain size d. The specimen's is
//     the largest of the thickness classes at or below n (the smallest for a thinner layer): the
//     collapse of a thick layer localises in a compaction band (Ritter et al. 2020, Fig. 1B;
//     Barraclough et al. 2017), the strength is the bulk's, and the FE crack band carries the
//     softening from the specimen's thickness to the element rows (fem/scene/crack_band.h);
//   - the specimen is a box periodic in its lateral axes, its lateral edges c times its thickness
//     (the lateral-extent study of docs/work_precision.md: the strengths level off from about 2.8
//     thicknesses), of N = 6 φ c² n³ / π spheres of the weak-layer scene's sphere diameter;
//   - the friction tests shear a specimen of their own (Campaign/Friction sample), at least n_f = 15
//     grains thick and c_f = 1 thickness wide: a collapsed 10-grain layer sticks and slips (τ/σ
//     swinging through zero), a 15-grain one slides at a steady ratio, and a wider box adds slip
//     events at large strain (docs/calibration.md, "Friction of the failed layer": the thickness
//     study);
//   - what is extensive in the scene follows the box: the clump's force rate with the cross-section
//     (the same stress rate), the friction test's shear velocity with its specimen's thickness (the
//     same strain rate), the Monte Carlo sweeps with N over the scene's N (a larger box levels off
//     later, docs/work_precision.md);
//   - the compaction test compacts the class's layer to the scene's final solid fraction: between
//     the rigid base and actuator the layer is in uniaxial strain, so a strain e takes phi to
//     phi / (1 - e); a lighter layer needs more strain to lock up (at phi = 0.218 the scene's 0.35
//     left a 10-grain layer short of its lock-up, measured);
//   - the grain size d is the snow units' length for the pit: the material's only length, its
//     reference thickness, scales by d over Snow units/Grain diameter [m] (coupling/snow_units.h:
//     the grains' size is a unit, so pits that differ only in it share a campaign).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace anticrack::dem
{
  struct SceneParameters;
}

namespace anticrack::coupling
{
  /// What a pit says of the weak layer a snowpack scene puts its saw test in.
  struct ProfileWeakLayer
  {
    std::string scene;        ///< the snowpack scene
    std::string profile_file; ///< the pit
    int layer = 0;            ///< in the profile, from 1 at the surface
    std::string grain_form;
    double thickness = 0;       ///< h [m]
    double grain_size = 0;      ///< d [m]
    double density = 0;         ///< ρ [kg/m³]
    std::string density_source; ///< measured, or the law that inferred it
  };

  /// The weak layer of the snowpack scene `scene_file` from its profile record
  /// (fem::SnowpackScene::profile_record); throws InputError naming the scene, the profile file and
  /// the layer when the scene has no profile, or the layer gives no grain size or no density.
  ProfileWeakLayer profile_weak_layer(const nlohmann::ordered_json &profile_record, const std::string &scene_file);

  /// How pits' weak layers are put in classes (subsection Pipeline/Profile specimen).
  struct SpecimenRules
  {
    double density_class_width = 0;        ///< Δρ [kg/m³]
    std::vector<double> thickness_classes; ///< in grains, ascending
    double lateral_extent = 0;             ///< c: lateral edges over thickness
    double friction_thickness = 0;         ///< n_f: the friction tests' specimen is at least this thick, in grains
    double friction_lateral_extent = 0;    ///< c_f: its lateral edges over its thickness
    /// φ_f: the solid fraction n_f was measured at; a looser class's friction specimen is
    /// n_f φ_f / φ thick (as much ice per area, as many grain layers once collapsed); 0: n_f at any φ.
    double friction_solid_fraction = 0;
  };

  /// The DEM specimen of one class of weak layers.
  struct ProfileSpecimen
  {
    double density = 0;             ///< the class's ρ [kg/m³]
    double solid_fraction = 0;      ///< φ = ρ / ρ_grain
    double thickness_in_grains = 0; ///< n, a thickness class
    double lateral_extent = 0;      ///< c
    /// The friction tests' own specimen (Campaign/Friction sample): max(n, n_f max(1, φ_f / φ)) grains
    /// thick, c_f wide.
    double friction_thickness_in_grains = 0;
    double friction_lateral_extent = 0;
    [[nodiscard]] std::string name() const;      ///< "150 kg/m^3, 10 grains"
    [[nodiscard]] std::string directory() const; ///< "weak_layer_150kgm3_10grains"
    [[nodiscard]] bool operator==(const ProfileSpecimen &other) const;
  };

  /// The class of `layer` under `rules`, with the snow's grain density `grain_density` [kg/m³].
  ProfileSpecimen profile_specimen(const ProfileWeakLayer &layer, const SpecimenRules &rules, double grain_density);

  /// N = 6 φ c² n³ / π, rounded: the spheres of diameter d that fill a box n d thick, c n d wide, at φ.
  std::size_t specimen_particle_count(const ProfileSpecimen &specimen);
  /// The same for the friction tests' specimen (n_f, c_f).
  std::size_t friction_specimen_particle_count(const ProfileSpecimen &specimen);

  /// The entries that make the weak-layer scene `dem` (a sticky-hard-sphere sample, loaded along z)
  /// sample and test `specimen` with the scene's sphere diameter: volume fraction, particle count,
  /// box edge and aspect ratios, sweeps, the clump's force rate, the friction tests' own sample and
  /// shear velocity, and the compaction test's final strain (the header says why each). Throws InputError (naming `where`) for another sample type.
  std::vector<std::pair<std::string, std::string>> specimen_changes(const ProfileSpecimen &specimen,
                                                                    const dem::SceneParameters &dem,
                                                                    const std::string &where);

  /// Campaign/Compaction final strain of `specimen` (spheres of `diameter`) under the weak-layer scene
  /// `dem`: the strain (over the whole box, as the entry's) that takes its layer between the rigid
  /// base and actuator to the final solid fraction of the scene's compaction test. Throws InputError
  /// (naming `where`) when the class is too dense or too thin for it.
  double compaction_final_strain(const ProfileSpecimen &specimen, const dem::SceneParameters &dem, double diameter,
                                 const std::string &where);

  /// Its record for summary.json: the layer, its class and the specimen.
  nlohmann::ordered_json specimen_record(const ProfileWeakLayer &layer, const ProfileSpecimen &specimen);
} // namespace anticrack::coupling
