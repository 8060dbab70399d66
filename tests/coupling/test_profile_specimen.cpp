// The weak layer's DEM specimen from a pit (coupling/profile_specimen.h): the class of a pit's layer,
// the sphere count of a box, the entries that make the weak-layer scene sample it, and a material's
// lengths for the pit's grains (coupling/snow_units.h). Expected values are the conversion's
// arithmetic written out by hand.
#include "coupling/profile_specimen.h"
#include "coupling/snow_units.h"
#include "dem/scene/parameters.h"
#include "dem/scene/sample_types.h"
#include "util/input_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace
{
  using namespace anticrack;

  coupling::ProfileWeakLayer layer(double density, double thickness, double grain_size)
  {
    coupling::ProfileWeakLayer w;
    w.density = density;
    w.thickness = thickness;
    w.grain_size = grain_size;
    return w;
  }

  coupling::SpecimenRules rules()
  {
    coupling::SpecimenRules r;
    r.density_class_width = 25;
    r.thickness_classes = {5, 10};
    r.lateral_extent = 2.8;
    r.friction_thickness = 15;
    r.friction_lateral_extent = 1;
    return r;
  }

  /// The default weak layer's scene: 2048 spheres at phi = 0.3 in a 1 cm cube (spheres of 0.654 mm),
  /// 20 000 sweeps, the clump at 400 N/s, the friction test at 45 kPa and 0.05 m/s.
  dem::SceneParameters weak_layer_scene()
  {
    dem::SceneParameters scene;
    for (const dem::SampleType &t : dem::sample_types())
      if (std::string(t.name) == "sticky hard spheres")
        scene.dem.sample.type = &t;
    scene.dem.sample.particle_count = 2048;
    scene.dem.sample.volume_fraction = 0.3;
    scene.dem.sample.box_edge = 0.01;
    scene.dem.sample.sweeps = 20000;
    scene.dem.boundary.clump_force_rate = 400;
    scene.campaign.friction_normal_stress = 4.5e4;
    scene.campaign.friction_shear_velocity = 0.05;
    scene.campaign.compaction_final_strain = 0.35;
    scene.dem.boundary.base_thickness = 3;
    scene.dem.boundary.actuator_thickness = 3;
    return scene;
  }
} // namespace

// Density classes of 25 kg/m^3 (158 -> 150, 163 -> 175, 460 -> 450); thickness classes 5 and 10: a
// layer of 80 grains takes 10, one of 7 takes 5, one of 2.5 (thinner than any class) takes 5.
TEST(ProfileSpecimen, ClassOfAPitsLayer)
{
  const coupling::ProfileSpecimen a = coupling::profile_specimen(layer(158, 0.16, 2e-3), rules(), 917);
  EXPECT_EQ(a.density, 150);
  EXPECT_DOUBLE_EQ(a.solid_fraction, 150.0 / 917);
  EXPECT_EQ(a.thickness_in_grains, 10);
  EXPECT_EQ(a.lateral_extent, 2.8);
  EXPECT_EQ(a.name(), "150 kg/m^3, 10 grains");
  EXPECT_EQ(a.directory(), "weak_layer_150kgm3_10grains");
  // The friction tests' specimen: max(n, n_f) grains thick (15 over a 10-grain class; a 10-grain
  // class under n_f = 8 keeps its 10), c_f = 1 wide.
  EXPECT_EQ(a.friction_thickness_in_grains, 15);
  EXPECT_EQ(a.friction_lateral_extent, 1);
  coupling::SpecimenRules thin_friction = rules();
  thin_friction.friction_thickness = 8;
  EXPECT_EQ(coupling::profile_specimen(layer(158, 0.16, 2e-3), thin_friction, 917).friction_thickness_in_grains, 10);
  // Measured at phi_f = 0.218: the 150 kg/m^3 class (phi = 0.1636) gets 15 x 0.218 / 0.1636 = 19.99
  // grains, as much ice per area as 15 grains at 0.218; the 200 and 250 kg/m^3 classes (phi 0.218
  // and 0.273, not looser) keep 15.
  coupling::SpecimenRules measured = rules();
  measured.friction_solid_fraction = 0.218;
  EXPECT_DOUBLE_EQ(coupling::profile_specimen(layer(158, 0.16, 2e-3), measured, 917).friction_thickness_in_grains,
                   15 * 0.218 / (150.0 / 917));
  EXPECT_EQ(coupling::profile_specimen(layer(205, 0.16, 2e-3), measured, 917).friction_thickness_in_grains, 15);
  EXPECT_EQ(coupling::profile_specimen(layer(250, 0.16, 2e-3), measured, 917).friction_thickness_in_grains, 15);
  EXPECT_EQ(coupling::profile_specimen(layer(162.7, 0.02, 1e-3), rules(), 917).density, 175);
  EXPECT_EQ(coupling::profile_specimen(layer(460, 0.05, 1e-3), rules(), 917).density, 450);
  EXPECT_EQ(coupling::profile_specimen(layer(200, 0.01, 1.5e-3), rules(), 917).thickness_in_grains, 5);
  EXPECT_EQ(coupling::profile_specimen(layer(200, 0.01, 4e-3), rules(), 917).thickness_in_grains, 5);
  // Pits of one class share it; another grain size alone does not make another class.
  EXPECT_TRUE(coupling::profile_specimen(layer(158, 0.16, 2e-3), rules(), 917) ==
              coupling::profile_specimen(layer(140, 0.5, 4e-3), rules(), 917));
  EXPECT_FALSE(coupling::profile_specimen(layer(158, 0.16, 2e-3), rules(), 917) ==
               coupling::profile_specimen(layer(158, 0.008, 1e-3), rules(), 917));
}

// N = 6 phi c^2 n^3 / pi: at phi = 0.3, c = 1, n = 15.28 (the default cube of 1 cm in 0.654 mm
// spheres) it is the default's 2048; at 150 kg/m^3, c = 2.8, n = 10 it is 6 (150/917) 7.84 1000 / pi.
TEST(ProfileSpecimen, ParticleCountFillsTheBoxAtItsSolidFraction)
{
  coupling::ProfileSpecimen cube;
  cube.solid_fraction = 0.3;
  cube.lateral_extent = 1;
  cube.thickness_in_grains = 0.01 / 6.5404e-4;
  EXPECT_NEAR(static_cast<double>(coupling::specimen_particle_count(cube)), 2048, 1);
  const coupling::ProfileSpecimen s = coupling::profile_specimen(layer(158, 0.16, 2e-3), rules(), 917);
  EXPECT_EQ(coupling::specimen_particle_count(s), std::size_t(std::llround(6 * (150.0 / 917) * 7.84 * 1000 / M_PI)));
}

// The 150 kg/m^3, 10-grain class under the default scene: its box 10 sphere diameters thick and 28
// wide, the clump's force rate times the cross-sections' ratio (same stress rate), the friction
// test's velocity times the thicknesses' ratio (same strain rate), the sweeps times N over 2048.
TEST(ProfileSpecimen, ChangesMakeTheScenesSampleThatBox)
{
  const coupling::ProfileSpecimen s = coupling::profile_specimen(layer(158, 0.16, 2e-3), rules(), 917);
  std::map<std::string, std::string> changes;
  for (const auto &[path, value] : coupling::specimen_changes(s, weak_layer_scene(), "test"))
    changes[path] = value;
  const double d = 2 * std::cbrt(0.3 * 1e-6 / (2048 * 4.0 / 3.0 * M_PI));
  const double h = 10 * d, count = static_cast<double>(coupling::specimen_particle_count(s));
  EXPECT_NEAR(std::stod(changes.at("DEM/Sample/Volume fraction")), 150.0 / 917, 1e-15);
  EXPECT_EQ(changes.at("DEM/Sample/Particle count"), std::to_string(coupling::specimen_particle_count(s)));
  EXPECT_NEAR(std::stod(changes.at("DEM/Sample/Box edge [m]")), h, 1e-15);
  const std::string ratios = changes.at("DEM/Sample/Box aspect ratios");
  EXPECT_EQ(std::stod(ratios), 2.8) << ratios;
  EXPECT_EQ(std::stod(ratios.substr(ratios.find(',') + 1)), 2.8) << ratios;
  EXPECT_EQ(ratios.substr(ratios.rfind(',') + 1), " 1") << ratios;
  EXPECT_EQ(changes.at("DEM/Sample/Sweeps"), std::to_string(static_cast<long long>(std::ceil(20000 * count / 2048))));
  EXPECT_NEAR(std::stod(changes.at("DEM/Boundary particles/Clump force rate [N/s]")),
              400 * (2.8 * h) * (2.8 * h) / 1e-4, 1e-9);
  // The friction tests' own sample: a cube 15 d thick of 6 phi 15^3 / pi spheres, the scene's sweeps
  // (fewer spheres than its 2048), sheared at the scene's strain rate: 0.05 m/s x 15 d / 1 cm.
  const double hf = 15 * d;
  const long long friction_count = std::llround(6 * (150.0 / 917) * 3375 / M_PI);
  EXPECT_EQ(static_cast<long long>(coupling::friction_specimen_particle_count(s)), friction_count);
  const std::string friction_sample = changes.at("Campaign/Friction sample");
  EXPECT_EQ(friction_sample.substr(0, friction_sample.find(',')), "Particle count = " + std::to_string(friction_count));
  const auto edge_at = friction_sample.find("Box edge [m] = ") + std::string("Box edge [m] = ").size();
  EXPECT_NEAR(std::stod(friction_sample.substr(edge_at)), hf, 1e-15);
  EXPECT_NE(friction_sample.find("Box aspect ratios = 1, 1, 1, Sweeps = 20000"), std::string::npos) << friction_sample;
  EXPECT_NEAR(std::stod(changes.at("Campaign/Friction shear velocity [m/s]")), 0.05 * hf / 0.01, 1e-15);
  // The compaction test: the layer between base and actuator (3 + 3 radii = 3 d) compacted to the
  // scene's final solid fraction, 0.3 / (1 - 0.35 x 0.01 / (0.01 - 3 d)), under uniaxial strain; the
  // entry is over the whole box, 10 d, of which 7 d compact.
  const double scene_final_fraction = 0.3 / (1 - 0.35 * 0.01 / (0.01 - 3 * d));
  const double layer_strain = 1 - (150.0 / 917) / scene_final_fraction;
  EXPECT_NEAR(std::stod(changes.at("Campaign/Compaction final strain")), layer_strain * 0.7, 1e-12);
  // The sphere count N at this phi and box gives back the scene's diameter (radius from Box edge).
  const double phi = 150.0 / 917, volume = (2.8 * h) * (2.8 * h) * h;
  EXPECT_NEAR(2 * std::cbrt(phi * volume / (count * 4.0 / 3.0 * M_PI)), d, 1e-3 * d);
  // A smaller box than the scene's keeps the scene's sweeps.
  coupling::ProfileSpecimen thin = s;
  thin.thickness_in_grains = 5;
  thin.lateral_extent = 1;
  for (const auto &[path, value] : coupling::specimen_changes(thin, weak_layer_scene(), "test"))
    if (path == "DEM/Sample/Sweeps")
      EXPECT_EQ(value, "20000");
}

TEST(ProfileSpecimen, OtherSamplesAndUnsizedBoxesAreRefused)
{
  const coupling::ProfileSpecimen s = coupling::profile_specimen(layer(158, 0.16, 2e-3), rules(), 917);
  dem::SceneParameters lattice = weak_layer_scene();
  lattice.dem.sample.type = &dem::sample_types().front();
  ASSERT_NE(std::string(lattice.dem.sample.type->name), "sticky hard spheres");
  EXPECT_THROW(coupling::specimen_changes(s, lattice, "test"), InputError);
  dem::SceneParameters by_radius = weak_layer_scene();
  by_radius.dem.sample.box_edge = 0;
  EXPECT_THROW(coupling::specimen_changes(s, by_radius, "test"), InputError);
}

// A pit's layer from the snowpack scene's profile record: its grain size and density, or a refusal
// naming the scene, the pit and the layer.
TEST(ProfileSpecimen, PitsLayerFromTheProfileRecord)
{
  nlohmann::ordered_json record = {
    {"file", "pit.xml"},
    {"weak_layer_index", 2},
    {"layers",
     {{{"thickness_m", 0.1}},
      {{"thickness_m", 0.02}, {"grain_form", "FC"}, {"grain_size_m", 0.002},
       {"density_kg_m3", {{"value", 158.0}, {"measured", false}, {"source", "Geldsetzer & Jamieson (2000)"}}}}}}};
  const coupling::ProfileWeakLayer w = coupling::profile_weak_layer(record, "pst.prm");
  EXPECT_EQ(w.layer, 2);
  EXPECT_EQ(w.grain_form, "FC");
  EXPECT_EQ(w.thickness, 0.02);
  EXPECT_EQ(w.grain_size, 0.002);
  EXPECT_EQ(w.density, 158.0);
  nlohmann::ordered_json no_density = record;
  no_density["layers"][1].erase("density_kg_m3");
  no_density["layers"][1]["density_note"] = "grain form SH is not among Geldsetzer & Jamieson's classes";
  try
  {
    coupling::profile_weak_layer(no_density, "pst.prm");
    FAIL() << "a layer without density was accepted";
  }
  catch (const InputError &e)
  {
    const std::string m = e.what();
    for (const char *needle : {"pst.prm", "layer 2 of pit.xml", "has no density", "SH is not among"})
      EXPECT_NE(m.find(needle), std::string::npos) << needle << " in " << m;
  }
  nlohmann::ordered_json no_grain = record;
  no_grain["layers"][1].erase("grain_size_m");
  EXPECT_THROW(coupling::profile_weak_layer(no_grain, "pst.prm"), InputError);
  EXPECT_THROW(coupling::profile_weak_layer(nlohmann::ordered_json(), "pst.prm"), InputError);
}

// A material's only length, its reference thickness, for other grains: times their ratio.
TEST(ProfileSpecimen, MaterialLengthsFollowThePitsGrains)
{
  fem::MaterialFile file;
  file.material.reference_thickness = 0.005;
  file.material.p0 = 5000;
  const fem::MaterialFile pit = coupling::with_grain_diameter(file, 6.54e-4, 2e-3, "test");
  EXPECT_NEAR(pit.material.reference_thickness, 0.005 * 2e-3 / 6.54e-4, 1e-15);
  EXPECT_EQ(pit.material.p0, 5000);
  EXPECT_THROW(coupling::with_grain_diameter(file, 0, 2e-3, "test"), InputError);
}
