// The calibration's input: a DEM campaign file (campaign.h5, written by `anticrack run` for a scene
// with a Campaign subsection; format in docs/lab.md, the failure-point columns in
// dem/campaign/campaign_file.h). Read once, validated, and kept as plain data:
// the failure-point table, the material of every microstructure, and access to every test's history.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

namespace anticrack::params
{
  /// One row of /failure_points: a test at one loading angle of one realization of one microstructure.
  struct CampaignTest
  {
    std::string id;                 ///< m<k>_r<k>_psi<angle>
    std::string status;             ///< completed, failed, interrupted or missing
    int microstructure = 0;
    int realization = 0;
    double loading_angle_deg = 0;   ///< ψ, clump force along (sin ψ, 0, −cos ψ)
    double sigma = 0, tau = 0;      ///< base stresses at failure, σ compression positive [Pa]
    double p = 0, q = 0;            ///< Love–Weber invariants at failure, p compression positive [Pa]
    std::array<double, 9> love_stress{}; ///< full tensor at failure, tension positive, row-major [Pa]
    double flow_angle_deg = 0;      ///< atan2(Δu_z, Δu_x) of the clump after failure
    double solid_fraction = 0, coordination = 0;
    double specimen_height = 0;     ///< H0 [m], the whole specimen (rigid base and clump included)
    double layer_thickness = 0;     ///< h [m], the deformable layer between base and clump
    /// Mean diameter of the specimen's spheres [m]; NaN in campaigns older than format 4.
    double particle_diameter = std::numeric_limits<double>::quiet_NaN();
    /// Friction tests (format 5): the steady sliding's mean shear and normal stresses [Pa] and their
    /// ratio, the collapsed layer's friction coefficient; NaN for the other tests.
    double steady_shear_stress = std::numeric_limits<double>::quiet_NaN();
    double steady_normal_stress = std::numeric_limits<double>::quiet_NaN();
    double steady_stress_ratio = std::numeric_limits<double>::quiet_NaN();
    std::string reference_for;      ///< a quasi-static reference run: the test it checks

    [[nodiscard]] bool completed() const { return status == "completed"; }
  };

  /// What the campaign's scene says about the material of one microstructure (/microstructures).
  struct MicrostructureMaterial
  {
    std::string label;                ///< the Campaign/Microstructures variant, or "scene sample"
    double particle_modulus = 0;      ///< bond modulus of bonded samples, else contact modulus [Pa]
    double bond_tensile_strength = 0; ///< σ̄_c [Pa] (NaN without bonds)
    double bond_cohesion = 0;         ///< c̄ [Pa]
    double particle_density = 0;      ///< [kg/m³]
    bool laterally_periodic = false;  ///< periodic x and y: uniaxial strain at ψ = 0
  };

  /// The columns of one test's history that the calibration uses. The strains are those of the
  /// deformable layer, u/h: the histories store u/H0 over the whole specimen, whose rigid base and
  /// clump do not deform, so they are rescaled by H0/h on reading (for Bobillier et al.'s (2020) weak layer under
  /// its actuator layer H0/h is about 2.5).
  struct TestHistory
  {
    std::vector<double> normal_strain;  ///< −u_z / h, compression positive
    std::vector<double> shear_strain;   ///< u_x / h
    std::vector<double> sigma, tau;     ///< base stresses [Pa]
    std::vector<double> love_xx, love_yy, love_zz; ///< Love–Weber normal components, tension positive [Pa]
  };

  struct CampaignData
  {
    std::string file;
    std::string sha256;               ///< of the campaign file itself
    std::string scene_file, scene_file_sha256, parameters_sha256, anticrack_version;
    std::vector<MicrostructureMaterial> microstructures;
    std::vector<CampaignTest> tests;  ///< the campaign proper (quasi-static references apart)
    /// The displacement-controlled compaction tests (/compaction_tests; psi = 0), one per realization.
    std::vector<CampaignTest> compaction_tests;
    /// The simple shears of the collapsed layer (/friction_tests, format 5), one per realization.
    std::vector<CampaignTest> friction_tests;
    /// The quasi-static reference runs (/quasi_static_check), of either kind, reference_for set.
    std::vector<CampaignTest> reference_tests;

    /// The history of `test` from /tests/<id>/history, strains per layer thickness; throws
    /// CalibrationError naming the file and test if it is missing or lacks a column.
    [[nodiscard]] TestHistory history(const CampaignTest &test) const;
  };

  /// Reads and validates `file` (format anticrack-campaign, version 2). Throws CalibrationError with
  /// the file, the object and the reason (missing file, other format, old version, inconsistent table).
  CampaignData read_campaign(const std::string &file);
} // namespace anticrack::params
