// The conversion of a DEM weak layer to snow (coupling/snow_units.h): the stress factor S, the
// length factor L, the check that the DEM ran at the snow's bond modulus over strength, and the
// entries that make it run so.
#include "coupling/snow_units.h"
#include "dem/scene/parameters.h"
#include "util/input_error.h"

#include <gtest/gtest.h>

#include <map>

namespace
{
  using namespace anticrack;

  /// A DEM campaign's microstructure: bonds of 1 MPa and 1 GPa, spheres of 0.654 mm, phi = 0.3.
  params::MicrostructureCalibration dem_microstructure()
  {
    params::MicrostructureCalibration c;
    c.index = 0;
    c.material.bond_tensile_strength = 1e6;
    c.material.particle_modulus = 1e9;
    c.solid_fraction = 0.3;
    c.grain_diameter = 6.54e-4;
    return c;
  }

  /// A material file in the DEM's units.
  fem::MaterialFile dem_material()
  {
    fem::MaterialFile file;
    file.material = {"weak layer", "invariants", 3000, 9e6, 0.2, 11e3, 0.4, 1.1, "signed", 40, 0.18, 0.008};
    file.uncertainty.youngs_modulus = {8e6, 10e6};
    file.uncertainty.p0 = {10e3, 12e3};
    file.collapse.lock_up_strain = 0.027;
    file.collapse.lock_up_modulus = 57e3;
    file.collapse.fracture_energy_density = 6.0;
    file.collapse.fracture_energy_density_interval = {5.0, 7.0};
    file.collapse.collapse_energy_density = 90;
    return file;
  }

  coupling::SnowUnits snow(double strength, double modulus, double diameter)
  {
    return coupling::SnowUnits{strength, modulus, diameter, 917};
  }

  std::map<std::string, std::string> as_map(const std::vector<std::pair<std::string, std::string>> &changes)
  {
    return {changes.begin(), changes.end()};
  }
} // namespace

// Stresses by S = 300 kPa / 1 MPa, lengths by L = 1 mm / 0.654 mm, strains and ratios unchanged,
// density phi rho_ice: each number by hand.
TEST(SnowUnits, StressesScaleByTheBondStrengthAndLengthsByTheGrainSize)
{
  const fem::MaterialFile file = coupling::in_snow_units(dem_material(), dem_microstructure(), snow(3e5, 3e8, 1e-3));
  const double S = 0.3, L = 1e-3 / 6.54e-4;
  const fem::ContinuumMaterial &m = file.material;
  EXPECT_DOUBLE_EQ(m.youngs_modulus, 9e6 * S);
  EXPECT_DOUBLE_EQ(m.p0, 11e3 * S);
  EXPECT_DOUBLE_EQ(m.reference_thickness, 0.008 * L);
  EXPECT_DOUBLE_EQ(m.density, 0.3 * 917);
  EXPECT_EQ(m.poisson_ratio, 0.2);
  EXPECT_EQ(m.beta, 0.4);
  EXPECT_EQ(m.M, 1.1);
  EXPECT_EQ(m.hardening_factor, 40);
  EXPECT_EQ(m.residual_strength_ratio, 0.18);
  EXPECT_DOUBLE_EQ(file.uncertainty.p0.lower, 10e3 * S);
  EXPECT_DOUBLE_EQ(file.uncertainty.youngs_modulus.upper, 10e6 * S);
  EXPECT_EQ(file.collapse.lock_up_strain, 0.027);
  EXPECT_DOUBLE_EQ(file.collapse.lock_up_modulus, 57e3 * S);
  EXPECT_DOUBLE_EQ(file.collapse.fracture_energy_density, 6.0 * S);
  // The energy dissipated per unit area of the layer, w_f h_ref, scales by S L.
  EXPECT_NEAR(file.collapse.fracture_energy_density * m.reference_thickness / (6.0 * 0.008), S * L, 1e-12);
}

// A campaign run at another bond modulus over strength than the snow's is not the snow's layer.
TEST(SnowUnits, ACampaignAtAnotherRatioIsRefused)
{
  try
  {
    coupling::in_snow_units(dem_material(), dem_microstructure(), snow(3e5, 1.8e7, 1e-3));
    FAIL() << "no error";
  }
  catch (const InputError &e)
  {
    const std::string what = e.what();
    EXPECT_NE(what.find("Snow units/Bond modulus [Pa]"), std::string::npos) << what;
    EXPECT_NE(what.find("1000"), std::string::npos) << what;
    EXPECT_NE(what.find("60"), std::string::npos) << what;
  }
}

// A campaign of format 3 records no grain size: its lengths cannot be converted.
TEST(SnowUnits, ACampaignWithoutGrainSizeIsRefused)
{
  params::MicrostructureCalibration c = dem_microstructure();
  c.grain_diameter = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(coupling::length_scale(c, snow(3e5, 3e8, 1e-3)), InputError);
  EXPECT_THROW(coupling::length_scale(dem_microstructure(), snow(3e5, 3e8, 0)), InputError);
}

// At the DEM's own ratio nothing changes; at Bobillier et al.'s (2020) 30 MPa / 500 kPa (60) the
// bond and contact moduli and the density are multiplied by k = 60 / 1000, the stop strain divided.
TEST(SnowUnits, TheDemRunsAtTheSnowsRatio)
{
  dem::SceneParameters scene;
  scene.dem.bond.bond.enabled = true;
  scene.dem.bond.bond.modulus = 1e9;
  scene.dem.bond.bond.tensile_strength = 1e6;
  scene.dem.material.contact.contact_modulus = 1e9;
  scene.dem.material.density = 1e4;
  scene.dem.loading.stop_strain = 0.02;
  EXPECT_TRUE(coupling::snow_ratio_changes(scene, snow(3e5, 3e8, 1e-3), "test").empty());

  const auto changes = as_map(coupling::snow_ratio_changes(scene, snow(5e5, 3e7, 1e-3), "test"));
  ASSERT_EQ(changes.size(), 4u);
  const double k = 60.0 / 1000.0;
  EXPECT_NEAR(std::stod(changes.at("DEM/Bond/Modulus [Pa]")), 1e9 * k, 1e-6);
  EXPECT_NEAR(std::stod(changes.at("DEM/Material/Contact modulus [Pa]")), 1e9 * k, 1e-6);
  EXPECT_NEAR(std::stod(changes.at("DEM/Material/Density [kg/m^3]")), 1e4 * k, 1e-9);
  EXPECT_NEAR(std::stod(changes.at("DEM/Loading/Stop strain")), 0.02 / k, 1e-12);

  dem::SceneParameters hertz = scene;
  hertz.dem.material.contact.law = dem::ContactLaw::hertz_mindlin;
  EXPECT_THROW(coupling::snow_ratio_changes(hertz, snow(5e5, 3e7, 1e-3), "test"), InputError);
  dem::SceneParameters unbonded = scene;
  unbonded.dem.bond.bond.enabled = false;
  EXPECT_THROW(coupling::snow_ratio_changes(unbonded, snow(3e5, 3e8, 1e-3), "test"), InputError);
}
