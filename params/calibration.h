// The calibration: a DEM campaign (campaign.h5) in, everything a continuum model needs out, with
// uncertainties. For every microstructure of the campaign:
//   - the cohesive Cam-Clay surface fitted in both stress planes — the base stresses (σ, τ) of
//     Ritter et al. (2020) and the invariants (p, q) of the Love–Weber stress — with the two alternative envelopes
//     (Mohr–Coulomb with a cap, Mede et al. 2018; the quadratic polynomial of Bobillier et al. 2020, Eq. 9) and their
//     information criteria;
//   - Ritter et al.'s (2020) flow-rule analysis in the normalised (σ*, τ*) plane;
//   - elastic constants and the collapse-softening factor ξ (params/elastic_calibration.h).
// Across microstructures: the power laws of σ0/σ̄_c and βσ0/σ̄_c with the contact density ν_c = zφ
// (Ritter et al. 2020, Eqs. 2–3), M's mean and spread, and the linear micro-to-macro laws of Bobillier et al. 2020 (Eqs. 5–8)
// when the campaign varies the particle modulus or the bond strength.
//
// Which surface the FE solver gets: the invariant-plane (p, q) fit of the failure points as the FE
// material point sees them on each test's own path (params/stress_path.h): the base stresses (σ, τ)
// are the layer-plane traction, the lateral stresses those of the FE elasticity under the test's
// lateral condition (periodic sides: no lateral strain; open sides: none). Fitted so, the FE point
// driven along every DEM test's path fails where the DEM failed, in the fit's own residual measure.
// Two other fits are kept for comparison and never written as FE parameters: the (σ, τ) fit of
// Ritter et al. (2020) (its σ0, β, M, scaling laws and flow rule are in that plane) and the (p, q)
// fit of the specimen's Love–Weber stress (its lateral stresses are the DEM's, which the FE point
// does not have; laterally confined tests reach only a narrow fan of q/p there, so its tips are
// often undetermined). The material surface is refused, with the reason, when no convex isotropic
// surface can pass through the (σ, τ) fit's compressive, shear and tensile strengths on the paths
// (the chord test of params/stress_path.h), when it misses the DEM's failure points by more than the
// (σ, τ) fit does, or when its tips are extrapolated far beyond the data or its covariance is singular.
#pragma once

#include "params/campaign_data.h"
#include "params/collapse_calibration.h"
#include "params/friction_calibration.h"
#include "params/elastic_calibration.h"
#include "params/envelope_fit.h"
#include "params/flow_rule.h"
#include "params/regression.h"
#include "params/stress_path.h"
#include "params/yield_envelopes.h"

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace anticrack::params
{
  enum class StressPlane
  {
    base_stresses,  ///< (σ, τ) at the fixed base (Ritter et al. 2020), for comparison
    invariants,     ///< (p, q) of the specimen's Love–Weber stress, for comparison
    path_invariants ///< (p, q) of the FE material point on each test's path — the FE solver's surface
  };

  /// "sigma_tau", "p_q" or "p_q_path" (group names in calibration.h5).
  std::string plane_id(StressPlane plane);

  struct CalibrationOptions
  {
    double confidence = 0.95;
    int bootstrap_samples = 1000; ///< resamples of the realizations (needs >= 3 realizations)
    std::uint64_t seed = 1;       ///< of the bootstrap: the calibration is reproducible
    std::optional<double> poisson_ratio; ///< given ν for specimens that are not isotropic
    /// Per test id, the FE material point's peak load on the test's path over its first yield
    /// (coupling/material_point_replay.h). The path plane's points are the DEM's failures divided
    /// by it, so that the fitted surface's first yield times it, the FE point's peak, is the DEM's
    /// failure. Tests not named: 1 (the peak is the first yield).
    std::map<std::string, double> path_peak_factors;
  };

  /// The fits of all envelope models to one microstructure's failure points in one plane.
  struct PlaneCalibration
  {
    StressPlane plane = StressPlane::invariants;
    std::vector<StressPoint> points;       ///< one per completed test
    std::vector<int> realizations;         ///< the bootstrap's groups, one per point
    std::vector<EnvelopeKind> models;      ///< all_envelope_kinds()
    std::vector<EnvelopeFit> fits;         ///< one per model
    std::vector<EnvelopeBand> bands;       ///< one per model, for plots
    std::size_t best_by_aicc = 0;          ///< index into models
    /// Why the Cam-Clay fit does not determine the surface (empty: it does): a tip extrapolated far
    /// beyond the data, or a singular covariance.
    std::string cam_clay_not_determined;

    [[nodiscard]] const EnvelopeFit &cam_clay() const;  ///< the cohesive Cam-Clay fit
    [[nodiscard]] CamClaySurface cam_clay_surface() const;      ///< of the Cam-Clay fit
    [[nodiscard]] CamClaySurfaceInterval cam_clay_interval() const; ///< its covariance interval
  };

  /// Ritter et al.'s (2020) flow-rule analysis for one microstructure, in the (σ, τ) plane of its Cam-Clay fit.
  struct FlowRuleAnalysis
  {
    std::vector<double> loading_angle, flow_angle;   ///< ψ and θ per test [rad]
    std::vector<double> sigma_star, tau_star;        ///< normalised failure points (Eqs. 5–6)
    std::vector<double> psi_star, theta_star;        ///< normalised loading and flow angles [rad]
    AssociativityMeasure associativity;
    double transition_predicted = 0;                 ///< ψ± of Eq. 7 [rad]
    std::optional<double> transition_observed;       ///< where the measured θ changes sign [rad]
    std::string transition_observed_note;            ///< why it is absent
    /// Tests left out because their flow angle is not finite (the clump did not move after the
    /// failure: no displacement increment to take the direction of), and why the associativity is
    /// not measured (fewer than 3 tests left), "" when it is.
    std::vector<std::string> excluded;
    std::string associativity_note;
  };

  struct MicrostructureCalibration
  {
    int index = 0;
    MicrostructureMaterial material;
    std::vector<CampaignTest> tests;  ///< the completed tests used
    /// The failure-point tests of this microstructure that are not used, each "id: why" (its status
    /// when it did not complete, or the failure point it lacks): named in summary.json and on the
    /// console, never dropped silently.
    std::vector<std::string> tests_left_out;
    std::vector<int> realizations;    ///< distinct realization ids
    double solid_fraction = 0, coordination = 0, contact_density = 0; ///< means over the tests
    double layer_thickness = 0;       ///< h of the deformable layer [m], the reference thickness
    /// Mean diameter of the spheres over the tests [m]: the grain size the snow units scale lengths
    /// by; NaN for a campaign older than format 4.
    double grain_diameter = std::numeric_limits<double>::quiet_NaN();
    double density = 0;               ///< φ ρ_particle [kg/m³]
    TestPath path;                    ///< the tests' path for the FE point (the FE elasticity's ν)
    /// The DEM's lateral stress ratio at failure, (σ_xx + σ_yy)/(2 σ_zz) of the Love–Weber stress,
    /// over the tests with |σ| >= half the largest (beside path.lateral_stress_ratio()).
    SampleStatistics lateral_stress_ratio_at_failure;
    PlaneCalibration base_plane, invariant_plane, path_plane;
    FlowRuleAnalysis flow_rule;
    ElasticConstants elastic;
    SofteningEstimate softening;
    /// The compaction tests the softening was read from, and their rate checks (collapse_calibration.h);
    /// empty when the campaign has none (softening.source says so).
    std::vector<CompactionReading> compaction_tests;
    std::vector<CompactionRateCheck> compaction_rate_checks;
    /// The failed layer's friction from the friction tests (friction_calibration.h); not measured
    /// (n = 0) when the campaign has none.
    FrictionEstimate friction;

    /// Why this microstructure gets no material file ("" when it gets one): its FE surface is not
    /// determined, or no isotropic invariant-plane surface fails where the DEM failed. A campaign of
    /// one microstructure is refused instead; in one of several (a scaling study) its DEM-side
    /// results, the (σ, τ) fit among them, still enter the laws across microstructures, and
    /// `softening` is not estimated (it is the FE surface's).
    std::string material_refused;

    [[nodiscard]] const PlaneCalibration &plane(StressPlane which) const;
    /// The FE solver's surface: path_plane.
    [[nodiscard]] const PlaneCalibration &material_plane() const { return path_plane; }
  };

  /// Eqs. 2–3 of Ritter et al. (2020) across microstructures (in the (σ, τ) plane, as published).
  struct ScalingLaws
  {
    std::vector<double> contact_density, compressive_over_bond, tensile_over_bond, M; ///< one per microstructure
    PowerLawFit compressive;          ///< σ0/σ̄_c = h ν_c^κ
    PowerLawFit tensile;              ///< βσ0/σ̄_c = k ν_c^λ
    SampleStatistics M_statistics;    ///< M's mean and spread
  };

  /// Eqs. 5–8 of Bobillier et al. (2020) across microstructures, with its thickness scaling (reference = the layers' h).
  struct MicroMacroRelations
  {
    std::vector<double> particle_modulus, macro_modulus;   ///< Young's modulus of the continuum
    std::vector<double> bond_strength, macro_strength;     ///< base σ at failure at ψ = 0
    std::optional<MicroMacroLaw> modulus, strength;        ///< when >= 3 distinct micro values
  };

  struct Calibration
  {
    CampaignData campaign;
    CalibrationOptions options;
    std::vector<MicrostructureCalibration> microstructures;
    std::optional<ScalingLaws> scaling;       ///< with >= 3 microstructures of distinct ν_c
    MicroMacroRelations micro_macro;
    /// The fit through the FE point's peaks (coupling/calibrate.h): how many refits it took and the
    /// largest change of a test's peak factor in the last one [ln]; 0 and 0 without it.
    int peak_factor_refits = 0;
    double peak_factor_last_change = 0;
  };

  /// How far beyond the data a tip of the Cam-Clay surface may lie and still count as determined:
  /// p0 and β p0 at most this many times the largest failure-point radius of the plane.
  constexpr double tip_extrapolation_limit = 5.0;

  /// How much worse than the (σ, τ) fit the surface on the tests' paths may fit the same failure
  /// points: RMSE_path <= path_misfit_factor RMSE_(σ,τ) + path_misfit_margin. The two are fits of
  /// the same points along the same rays with 3-parameter families of ellipses symmetric about the
  /// normal axis (the FE surface's image in the (σ, τ) plane is one, by Eq. (P1) of stress_path.h), so
  /// where one family reaches the other's shape their minima coincide (the SHS campaign: equal to
  /// four digits, docs/calibration.md); a clearly larger RMSE means the isotropic surface cannot
  /// follow the DEM. The margin (1 % relative error) keeps near-perfect fits from tripping it: the
  /// FE point's peak factors (CalibrationOptions::path_peak_factors) bend the path family away from
  /// an ellipse through the DEM's points, by 0.9 % for exact synthetic surfaces of M = 0.8 under
  /// periodic sides (app.calibrate_scaling_laws), far below the DEM's scatter (~8 %).
  constexpr double path_misfit_factor = 1.25;
  constexpr double path_misfit_margin = 0.01;

  /// Calibrates every microstructure of `campaign`. Throws CalibrationError for degenerate data (a
  /// microstructure with fewer completed tests than 4, fewer than 3 distinct loading angles, or no
  /// tensile point) before anything is computed, and when the Cam-Clay fit on the tests' paths does
  /// not determine the surface or misses the failure points (see above), naming the file, the
  /// microstructure, the reason and what would help.
  Calibration calibrate(const CampaignData &campaign, const CalibrationOptions &options);
} // namespace anticrack::params
