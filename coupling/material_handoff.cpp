#include "coupling/material_handoff.h"

#include <filesystem>

namespace anticrack::coupling
{
  namespace
  {
    fem::MaterialInterval interval(const params::SampleStatistics &s) { return {s.mean_ci.lower, s.mean_ci.upper}; }

    /// How every value was measured, for the reader of the file (not read by the solver).
    std::vector<std::string> comment(const params::Calibration &calibration, const params::MicrostructureCalibration &c,
                                     const std::string &tool_version)
    {
      using fem::material_file_number;
      const params::CampaignData &campaign = calibration.campaign;
      const params::StressPlane plane = calibration.options.fe_plane;
      const params::EnvelopeFit &surface = c.plane(plane).cam_clay();
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
      if (plane == params::StressPlane::invariants)
        lines.push_back("failure points in the (p, q) plane of the Love-Weber stress (the invariants the FE solver "
                        "uses) by");
      else
      {
        lines.push_back("failure points in the (sigma, tau) plane of the base stresses (chosen with --fe-plane "
                        "sigma-tau;");
        lines.push_back("p0, beta, M of Ritter et al.'s (2020) plane, used as the FE's invariant-plane parameters) by");
      }
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
                      material_file_number(e.bulk_modulus.mean) + " Pa.");
      lines.push_back("Softening: p0 = K sinh(xi max(-alpha, 0)), collapse law (every plastic volume change softens);");
      lines.push_back("xi from the drop to R p0 over a plastic volumetric strain of " +
                      material_file_number(c.softening.plastic_volumetric_strain.mean) + " at psi = 0.");
      return lines;
    }
  } // namespace

  fem::MaterialFile material_handoff(const params::Calibration &calibration, std::size_t m,
                                     const std::string &tool_version)
  {
    const params::MicrostructureCalibration &c = calibration.microstructures.at(m);
    const params::CampaignData &campaign = calibration.campaign;
    const params::StressPlane plane = calibration.options.fe_plane;
    const params::CamClaySurface surface = c.plane(plane).cam_clay_surface();
    const params::CamClaySurfaceInterval surface_interval = c.plane(plane).cam_clay_interval();
    const params::ElasticConstants &e = c.elastic;
    const params::SofteningEstimate &soft = c.softening;

    fem::MaterialFile file;
    file.comment = comment(calibration, c, tool_version);
    fem::ContinuumMaterial &material = file.material;
    material.name = std::filesystem::path(campaign.scene_file).stem().string() + " m" + std::to_string(c.index);
    material.density = c.density;
    material.youngs_modulus = e.youngs_modulus.mean;
    material.poisson_ratio = e.poisson_ratio.mean;
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
    p.fit_plane = plane == params::StressPlane::invariants ? "p-q" : "sigma-tau";
    p.r_squared = c.plane(plane).cam_clay().r_squared;
    return file;
  }
} // namespace anticrack::coupling
