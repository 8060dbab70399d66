// The material hand-off (coupling/material_handoff.h) and the FE solver's material-file table
// (fem/material/material_file.h): what the writer writes, the solver's reader reads back.
#include "coupling/material_handoff.h"
#include "fem/material/material_file.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{
  using namespace anticrack;

  /// A calibration of one microstructure with the surface (p0, beta, M) in both planes; every
  /// number has at most 6 significant digits, so the file holds it exactly.
  params::Calibration one_microstructure(double p0, double beta, double M)
  {
    params::Calibration c;
    c.campaign.file = "campaign.h5";
    c.campaign.sha256 = std::string(64, 'a');
    c.campaign.scene_file = "scenes/weak_layer.prm";
    c.campaign.scene_file_sha256 = std::string(64, 'b');
    c.options.confidence = 0.9;
    params::MicrostructureCalibration m;
    m.index = 0;
    m.material.label = "scene sample";
    m.solid_fraction = 0.3, m.coordination = 2.8, m.contact_density = 0.84;
    m.layer_thickness = 0.008, m.density = 275.1;
    m.path = params::TestPath{true, 0.2};
    for (params::PlaneCalibration *plane : {&m.base_plane, &m.invariant_plane, &m.path_plane})
    {
      plane->models = {params::EnvelopeKind::cohesive_cam_clay};
      params::EnvelopeFit fit;
      fit.model = "cohesive_cam_clay";
      fit.parameters = Eigen::Vector3d(p0, beta, M);
      fit.ci_lower = Eigen::Vector3d(0.9 * p0, 0.5 * beta, 0.75 * M);
      fit.ci_upper = Eigen::Vector3d(1.1 * p0, 1.5 * beta, 1.25 * M);
      fit.r_squared = 0.987;
      fit.rmse = 0.031;
      plane->fits = {fit};
    }
    m.elastic.continuum_youngs_modulus = 1.2345e6;
    m.elastic.continuum_poisson_ratio = 0.21;
    m.elastic.youngs_modulus.mean_ci = {1.1e6, 1.3e6};
    m.elastic.youngs_modulus.n = 3;
    m.elastic.poisson_ratio.mean = 0.21;
    m.elastic.poisson_ratio.mean_ci = {0.19, 0.23};
    m.softening.hardening_factor.mean = 42.5;
    m.softening.hardening_factor.mean_ci = {40, 45};
    m.softening.residual_ratio.mean = 0.35;
    c.microstructures.push_back(m);
    return c;
  }
} // namespace

TEST(MaterialFile, WhatTheWriterWritesTheReaderReads)
{
  fem::MaterialFile file;
  file.comment = {"a comment", "  indented"};
  file.material = {"weak layer", "invariants", 275.1, 1.2345e6, 0.21, 3456.7, 0.45, 1.05, "signed", 42.5, 0.35, 0.008};
  file.uncertainty.confidence = 0.9;
  file.uncertainty.p0 = {3000, 4000};
  file.uncertainty.youngs_modulus = {1.1e6, 1.3e6};
  const std::string fit_plane = std::string(fem::path_fit_plane) + ", lateral stress ratio 0.25 (periodic sides)";
  file.provenance = {"campaign.h5", "abc", "scene.prm", "def", 3, fit_plane, 0.987};
  const std::string text = fem::material_file_text(file);
  EXPECT_EQ(text.rfind("# a comment\n#   indented\nsubsection Material\n", 0), 0u) << text;

  const fem::MaterialFile back = fem::read_material_file_text(text, "round trip");
  const fem::ContinuumMaterial &a = file.material, &b = back.material;
  EXPECT_EQ(b.name, a.name);
  EXPECT_EQ(b.hardening_law, a.hardening_law);
  for (const fem::MaterialEntry &e : fem::material_entries())
  {
    if (e.number)
    {
      EXPECT_EQ(b.*e.number, a.*e.number) << e.name();
    }
  }
  EXPECT_EQ(back.uncertainty.confidence, 0.9);
  EXPECT_EQ(back.uncertainty.p0.lower, 3000);
  EXPECT_EQ(back.uncertainty.p0.upper, 4000);
  EXPECT_EQ(back.uncertainty.youngs_modulus.upper, 1.3e6);
  EXPECT_TRUE(std::isnan(back.uncertainty.beta.lower)); // written as "nan, nan", read back as NaN
  EXPECT_EQ(back.provenance.microstructure, 3);
  EXPECT_EQ(back.provenance.fit_plane, fit_plane);
  EXPECT_EQ(back.provenance.r_squared, 0.987);
  EXPECT_EQ(fem::read_material_text(text, "round trip").p0, a.p0);
}

namespace
{
  /// The text of a complete, valid material file with `from` replaced by `to` (exactly once).
  std::string edited_material_file(const std::string &from, const std::string &to)
  {
    fem::MaterialFile file;
    file.material = {"layer", "invariants", 275.1, 1.2345e6, 0.21, 3456.7, 0.45, 1.05, "collapse", 42.5, 0.35, 0.008};
    file.provenance.fit_plane = std::string(fem::path_fit_plane) + ", lateral stress ratio 0 (open sides)";
    std::string text = fem::material_file_text(file);
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
  }

  /// The message read_material_text() throws for `text`, or "" if it reads it.
  std::string refusal(const std::string &text)
  {
    try
    {
      fem::read_material_text(text, "edited.prm");
    }
    catch (const std::exception &e)
    {
      return e.what();
    }
    return "";
  }
} // namespace

TEST(MaterialFile, AFileStatesItsPhysicsAndNoEntryHasADefault)
{
  EXPECT_EQ(refusal(edited_material_file("", "")), "");
  for (const fem::MaterialEntry &e : fem::material_entries())
  {
    if (e.text == &fem::ContinuumMaterial::name)
      continue; // a label, not physics
    const std::string without = edited_material_file("  set " + e.name() + " = ", "  # set " + e.name() + " = ");
    const std::string message = refusal(without);
    EXPECT_NE(message.find("edited.prm"), std::string::npos) << message;
    EXPECT_NE(message.find(e.name()), std::string::npos) << e.name() << ": " << message;
    EXPECT_NE(message.find("no defaults"), std::string::npos) << message;
  }
}

TEST(MaterialFile, ParametersOfAnotherPlaneAreRefusedNamingTheEntry)
{
  const std::string sigma_tau = refusal(edited_material_file("Yield surface plane = invariants",
                                                             "Yield surface plane = sigma-tau"));
  EXPECT_NE(sigma_tau.find("Yield surface plane"), std::string::npos) << sigma_tau;
  EXPECT_NE(sigma_tau.find("invariants"), std::string::npos) << sigma_tau;
  // Older calibrations: the (sigma, tau) fit, and the (p, q) fit of the Love-Weber stress.
  for (const char *older : {"sigma-tau", "p-q"})
  {
    const std::string message =
      refusal(edited_material_file(std::string("Fit plane = ") + fem::path_fit_plane, std::string("Fit plane = ") + older +
                                                                                          " was"));
    EXPECT_NE(message.find("Provenance/Fit plane"), std::string::npos) << message;
    EXPECT_NE(message.find(fem::path_fit_plane), std::string::npos) << message;
    EXPECT_NE(message.find("edited.prm"), std::string::npos) << message;
  }
}

TEST(MaterialFile, EveryEntryOfTheTableIsWrittenUnderItsNameAndUnit)
{
  const std::string text = fem::material_file_text(fem::MaterialFile{});
  for (const fem::MaterialEntry &e : fem::material_entries())
    EXPECT_NE(text.find("  set " + e.name() + " = "), std::string::npos) << e.name();
  for (const fem::MaterialEntry *e : fem::material_interval_entries())
    EXPECT_NE(text.find("    set " + e->interval_name() + " = "), std::string::npos) << e->interval_name();
  EXPECT_NE(text.find("set Compressive strength p0 interval [Pa] = "), std::string::npos);
  EXPECT_NE(text.find("set Tensile strength ratio beta interval = "), std::string::npos);
}

TEST(MaterialHandoff, TheFilesSurfaceIsTheFitOnTheTestsPathsNeverAnotherPlanes)
{
  params::Calibration calibration = one_microstructure(3456.7, 0.45, 1.05);
  // The comparison planes carry other surfaces; none of them may reach the file.
  calibration.microstructures[0].base_plane.fits[0].parameters = Eigen::Vector3d(9999, 0.9, 1.9);
  calibration.microstructures[0].invariant_plane.fits[0].parameters = Eigen::Vector3d(8888, 0.8, 1.8);
  const fem::MaterialFile file = coupling::material_handoff(calibration, 0, "test");
  const fem::MaterialFile back = fem::read_material_file_text(fem::material_file_text(file), "hand-off");
  EXPECT_EQ(back.material.yield_surface_plane, "invariants");
  EXPECT_EQ(back.material.p0, 3456.7);
  EXPECT_EQ(back.material.beta, 0.45);
  EXPECT_EQ(back.material.M, 1.05);
  EXPECT_EQ(back.material.youngs_modulus, 1.2345e6);
  EXPECT_EQ(back.material.poisson_ratio, 0.21);
  EXPECT_EQ(back.material.hardening_law, "collapse");
  EXPECT_EQ(back.material.hardening_factor, 42.5);
  EXPECT_EQ(back.material.residual_strength_ratio, 0.35);
  EXPECT_EQ(back.material.reference_thickness, 0.008);
  EXPECT_EQ(back.material.name, "weak_layer m0");
  EXPECT_NEAR(back.uncertainty.p0.lower, 0.9 * 3456.7, 0.01);
  EXPECT_NEAR(back.uncertainty.M.upper, 1.25 * 1.05, 1e-5);
  EXPECT_EQ(back.uncertainty.youngs_modulus.lower, 1.1e6); // over 3 realizations
  // One realization gives no spread: no interval rather than a zero-width one.
  EXPECT_TRUE(std::isnan(back.uncertainty.hardening_factor.lower));
  // nu = 0.2 under periodic sides: k = nu/(1 - nu) = 0.25.
  EXPECT_EQ(back.provenance.fit_plane, std::string(fem::path_fit_plane) + ", lateral stress ratio 0.25 (periodic sides)");
  EXPECT_EQ(back.provenance.campaign_sha256, std::string(64, 'a'));
  EXPECT_EQ(back.provenance.r_squared, 0.987);
}

TEST(MaterialFile, TheCollapseIsWrittenOnlyWhenGivenAndReadBack)
{
  fem::MaterialFile file;
  file.material = {"layer", "invariants", 275.1, 1.2345e6, 0.21, 3456.7, 0.45, 1.05, "collapse", 42.5, 0.35, 0.008};
  file.provenance.fit_plane = std::string(fem::path_fit_plane) + ", lateral stress ratio 0 (open sides)";
  EXPECT_EQ(fem::material_file_text(file).find("subsection Collapse"), std::string::npos);
  EXPECT_FALSE(fem::read_material_file_text(fem::material_file_text(file), "no collapse").collapse.given());

  file.collapse.lock_up_strain = 0.2416;
  file.collapse.lock_up_strain_interval = {0.1565, 0.3267};
  file.collapse.lock_up_modulus = 1.7e5;
  file.collapse.fracture_energy_density = 1.608;
  file.collapse.fracture_energy_density_interval = {0.95, 2.27};
  file.collapse.collapse_energy_density = 651.5;
  const fem::MaterialFile back = fem::read_material_file_text(fem::material_file_text(file), "collapse");
  ASSERT_TRUE(back.collapse.given());
  EXPECT_EQ(back.collapse.lock_up_strain, 0.2416);
  EXPECT_EQ(back.collapse.lock_up_strain_interval.lower, 0.1565);
  EXPECT_EQ(back.collapse.lock_up_strain_interval.upper, 0.3267);
  EXPECT_EQ(back.collapse.lock_up_modulus, 1.7e5);
  EXPECT_EQ(back.collapse.fracture_energy_density, 1.608);
  EXPECT_EQ(back.collapse.fracture_energy_density_interval.lower, 0.95);
  EXPECT_EQ(back.collapse.fracture_energy_density_interval.upper, 2.27);
  EXPECT_EQ(back.collapse.collapse_energy_density, 651.5);
  // No friction tests: the entry stays empty and reads back as not measured (0 would be a value).
  EXPECT_EQ(fem::material_file_text(file).find("set Friction coefficient ="), std::string::npos);
  EXPECT_TRUE(std::isnan(back.collapse.friction_coefficient));

  file.collapse.friction_coefficient = 0.383;
  file.collapse.friction_coefficient_interval = {0.367, 0.399};
  const fem::MaterialFile with_friction = fem::read_material_file_text(fem::material_file_text(file), "friction");
  EXPECT_EQ(with_friction.collapse.friction_coefficient, 0.383);
  EXPECT_EQ(with_friction.collapse.friction_coefficient_interval.lower, 0.367);
  EXPECT_EQ(with_friction.collapse.friction_coefficient_interval.upper, 0.399);
  // Out of [0, 2], or not a number: refused naming the entry.
  for (const char *bad : {"2.5", "-0.1", "0.4x"})
  {
    std::string text = fem::material_file_text(file);
    const std::string entry = "set Friction coefficient = 0.383";
    text.replace(text.find(entry), entry.size(), std::string("set Friction coefficient = ") + bad);
    try
    {
      fem::read_material_file_text(text, "bad friction");
      ADD_FAILURE() << bad << " accepted";
    }
    catch (const std::exception &e)
    {
      EXPECT_NE(std::string(e.what()).find("Collapse/Friction coefficient"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("[0, 2]"), std::string::npos) << e.what();
    }
  }
}
