#include "coupling/material_handoff.h"

#include <filesystem>

namespace anticrack::coupling
{
  namespace
  {
    /// The t-interval over the realizations; none (NaN; an empty entry in the file) from one realization,
    /// which gives no spread.
    fem::MaterialInterval interval(const params::SampleStatistics &s)
    {
      return s.n >= 2 ? fem::MaterialInterval{s.mean_ci.lower, s.mean_ci.upper} : fem::MaterialInterval{};
    }

    /// How every value was measured, for the reader of the file (not read by the solver).
    std::vector<std::string> comment(const params::Calibration &calibration, const params::MicrostructureCalibration &c,
                                     const std::string &tool_version)
    {
      using fem::material_file_number;
      const params::CampaignData &campaign = calibration.campaign;
      const params::EnvelopeFit &surface = c.material_plane().cam_clay();
      const double k = c.path.lateral_stress_ratio();
      const params::ElasticConstants &e = c.elastic;
      std::vector<std::string> lines = {
        "anticrack material file, written by `anticrack calibrate` (params/, anticrack " + tool_version + ").",
        "Source campaign: " + campaign.file,
        "  sha256 " + campaign.sha256,
        "  scene " + campaign.scene_file + " (sha256 " + campaign.scene_file_sha256 + ")",
        "Microstructure " + std::to_string(c.index) + " (" + c.material.label +
          "): phi = " + material_file_number(c.solid_fraction) + ", z = " + material_file_number(c.coordination) +
          ", nu_c = z phi = " + material_file_number(c.contact_density) + ", " +
          std::to_string(c.realizations.size()) + " realization(s), " + std::to_string(c.tests.size()) +
          " failure points.",
        "Yield surface: cohesive Cam-Clay (1 + 2 beta) q^2 + M^2 (p + beta p0)(p - p0) = 0, fitted to the"};
      lines.push_back("failure points as the FE material point sees them on each DEM test's path: the base stresses");
      lines.push_back("(sigma, tau) are the layer-plane traction, the lateral stresses those of this file's elasticity");
      lines.push_back(c.path.laterally_confined ?
                        "under the test's periodic sides (no lateral strain: sigma_xx = sigma_yy = k sigma_zz, k = nu/(1 - nu) = " +
                          material_file_number(k) + "),"
                                                : std::string("under the test's open sides (sigma_xx = sigma_yy = 0, k = 0),"));
      lines.push_back("so p = (1 + 2k) sigma/3, q = sqrt((1 - k)^2 sigma^2 + 3 tau^2); the DEM's Love-Weber lateral ratio at");
      lines.push_back("failure was " +
                      (c.lateral_stress_ratio_at_failure.n > 0 ?
                         material_file_number(c.lateral_stress_ratio_at_failure.mean) + " (mean of " +
                           std::to_string(c.lateral_stress_ratio_at_failure.n) + " tests)." :
                         std::string("not measured.")) +
                      " Fitted so, the FE point fails at the DEM's (sigma, tau) along every test's ray, by");
      lines.push_back("least squares of the relative radial residuals ln(r/R): R^2 = " +
                      material_file_number(surface.r_squared) + ", RMSE = " + material_file_number(100 * surface.rmse) +
                      " %.");
      lines.push_back("Intervals: " + material_file_number(100 * calibration.options.confidence) +
                      " % from the covariance of the fit (surface) and over the");
      lines.push_back("realizations (elasticity, softening); bootstrap intervals are in calibration.h5 and summary.json.");
      lines.push_back("Elasticity: axial secant modulus " + material_file_number(e.axial_modulus.mean) +
                      " Pa at psi = 0 (" +
                      (e.laterally_confined ? "laterally confined: constrained modulus" : "open sides: Young's modulus") +
                      "), shear secant modulus " + material_file_number(e.shear_modulus.mean) + " Pa at psi = 90 deg" +
                      (e.poisson_ratio_given ? " (not used: Poisson's ratio given)" : "") + "; bulk modulus K = " +
                      material_file_number(e.continuum_bulk_modulus) + " Pa (E, nu, K of the mean moduli, so that the FE layer has both).");
      lines.push_back("Softening: p0 = K sinh(xi max(-alpha, 0)), collapse law (every plastic volume change softens);");
      lines.push_back("xi from the drop to R p0 over a plastic volumetric strain of " +
                      material_file_number(c.softening.plastic_volumetric_strain.mean) + " at psi = 0, read from the " +
                      c.softening.source + ".");
      if (c.compaction_tests.empty())
        lines.push_back("(A load-controlled post-peak is an inertial run-away: add Campaign/Compaction strain rate [1/s].)");
      else
        lines.push_back("Collapse (subsection Collapse): the compaction tests' lock-up strain " +
                        material_file_number(c.softening.lock_up_strain.mean) + " (collapse height = it x the layer's "
                        "thickness), lock-up modulus, fracture and collapse energies (dem/lab/compaction_curve.h).");
      return lines;
    }
  } // namespace

  fem::MaterialFile material_handoff(const params::Calibration &calibration, std::size_t m,
                                     const std::string &tool_version)
  {
    const params::MicrostructureCalibration &c = calibration.microstructures.at(m);
    const params::CampaignData &campaign = calibration.campaign;
    const params::PlaneCalibration &plane = c.material_plane();
    const params::CamClaySurface surface = plane.cam_clay_surface();
    const params::CamClaySurfaceInterval surface_interval = plane.cam_clay_interval();
    const params::ElasticConstants &e = c.elastic;
    const params::SofteningEstimate &soft = c.softening;

    fem::MaterialFile file;
    file.comment = comment(calibration, c, tool_version);
    fem::ContinuumMaterial &material = file.material;
    material.yield_surface_plane = "invariants";
    material.name = std::filesystem::path(campaign.scene_file).stem().string() + " m" + std::to_string(c.index);
    material.density = c.density;
    material.youngs_modulus = e.continuum_youngs_modulus;
    material.poisson_ratio = e.continuum_poisson_ratio;
    material.p0 = surface.p0;
    material.beta = surface.beta;
    material.M = surface.M;
    material.hardening_law = "collapse"; // the law the softening was measured for (elastic_calibration.h)
    material.hardening_factor = soft.hardening_factor.mean;
    material.residual_strength_ratio = soft.residual_ratio.mean;
    material.reference_thickness = c.layer_thickness;

    fem::MaterialUncertainty &u = file.uncertainty;
    u.confidence = calibration.options.confidence;
    u.p0 = {surface_interval.lower.p0, surface_interval.upper.p0};
    u.beta = {surface_interval.lower.beta, surface_interval.upper.beta};
    u.M = {surface_interval.lower.M, surface_interval.upper.M};
    u.youngs_modulus = interval(e.youngs_modulus);
    u.poisson_ratio = interval(e.poisson_ratio);
    u.hardening_factor = interval(soft.hardening_factor);

    fem::MaterialProvenance &p = file.provenance;
    p.campaign_file = campaign.file;
    p.campaign_sha256 = campaign.sha256;
    p.scene_file = campaign.scene_file;
    p.scene_sha256 = campaign.scene_file_sha256;
    p.microstructure = c.index;
    p.fit_plane = std::string(fem::path_fit_plane) + ", lateral stress ratio " +
                  fem::material_file_number(c.path.lateral_stress_ratio()) +
                  (c.path.laterally_confined ? " (periodic sides)" : " (open sides)");
    p.r_squared = plane.cam_clay().r_squared;

    if (!c.compaction_tests.empty())
    {
      fem::MaterialCollapse &collapse = file.collapse;
      collapse.lock_up_strain = soft.lock_up_strain.mean;
      collapse.lock_up_strain_interval = interval(soft.lock_up_strain);
      collapse.lock_up_modulus = soft.lock_up_modulus.mean;
      collapse.fracture_energy_density = soft.fracture_energy_density.mean;
      collapse.fracture_energy_density_interval = interval(soft.fracture_energy_density);
      collapse.collapse_energy_density = soft.collapse_energy_density.mean;
    }
    // The failed layer's friction (its campaign's friction tests): a ratio of stresses, unchanged by
    // the snow units.
    if (c.friction.measured())
    {
      file.collapse.friction_coefficient = c.friction.friction_coefficient.mean;
      file.collapse.friction_coefficient_interval = interval(c.friction.friction_coefficient);
    }
    return file;
  }
} // namespace anticrack::coupling
