// Elastic constants and the collapse-softening law of the continuum from the DEM campaign's
// compression (ψ = 0) and shear (ψ = 90°) tests, one estimate per realization, then their mean with a
// t-interval over the realizations.
//
// Elasticity. The compression test gives the secant modulus of the base normal stress against the
// normal strain of the deformable layer to 70 % of the peak (Bobillier et al. 2020; strains u/h, campaign_data.h). With periodic sides (Ritter et al. 2020) the specimen is
// laterally confined, so that modulus is the constrained (P-wave) modulus M = K + 4G/3; with open
// sides (Bobillier et al. 2020) it is Young's modulus E. The shear test gives G as the secant modulus of τ against
// γ = u_x/h to 70 % of its peak (the clump moves along x over a fixed base: simple shear). Then
//   confined:   K = M − 4G/3,  E = 9KG/(3K + G),  ν = (3K − 2G)/(2(3K + G));
//   unconfined: ν = E/(2G) − 1,  K = E/(3(1 − 2ν)).
// Confined specimens also give ν from the lateral stress ratio K0 = σ_xx/σ_zz of the Love stress in
// the elastic range, ν = K0/(1 + K0) (uniaxial strain), reported as a cross-check.
//
// Softening (docs/physics.md §2), read here from the post-peak of the load-controlled ψ = 0 tests: a
// fallback for campaigns without compaction tests, whose post-peak is an inertial run-away that
// depends on the loading rate. params/collapse_calibration.h reads it from the displacement-
// controlled compaction tests instead, with the same formula for ξ. p0 = K sinh(ξ max(−α, 0)) with α the accumulated volumetric plastic
// strain, starting at α0 = −asinh(p0_init/K)/ξ; under "collapse softening" every plastic volume
// change, either sign, moves α towards 0, so p0 falls from p0_init to R p0_init after a plastic
// volumetric strain Δε_p when ξ = [asinh(p0/K) − asinh(R p0/K)] / Δε_p. The compression test gives
// R (softening ratio, Bobillier et al. 2020: residual over peak base stress, the residual being the mean over the
// last half of the post-peak samples) and Δε_p: the normal strain from the peak to the first sample
// at the residual stress, plus the elastic strain the falling stress gives back, (σ_peak − σ_res)/M_axial. Under
// uniaxial strain (confined) the volumetric strain is the normal strain; with open sides the collapse
// is still a compaction band of zero lateral strain (Ritter et al. 2020, Fig. 1), so the same holds for its
// plastic part.
//
// The run's own summary (dem/scene/failure_analysis.h: summary.json secant_modulus_70_percent_Pa,
// softening_ratio, and campaign.h5's columns of the same names) uses the same definitions
// (dem::secant_modulus on the layer strain u/h, dem::softening_ratio) on its loading measure.
#pragma once

#include "params/campaign_data.h"
#include "params/regression.h"

#include <optional>

namespace anticrack::params
{
  struct ElasticConstants
  {
    bool laterally_confined = false;
    bool poisson_ratio_given = false; ///< ν from the user, E from the axial modulus alone
    SampleStatistics axial_modulus;   ///< M (confined) or E (open sides), secant to 70 % [Pa]
    SampleStatistics shear_modulus;   ///< G [Pa], measured
    SampleStatistics youngs_modulus;  ///< E [Pa]
    SampleStatistics poisson_ratio;   ///< ν
    SampleStatistics bulk_modulus;    ///< K [Pa]
    SampleStatistics k0_poisson_ratio; ///< ν from K0 (confined only; n = 0 otherwise)
    /// The continuum's constants: those of the MEAN axial and shear moduli, so that the FE layer
    /// reproduces both mean stiffnesses (the means of E and ν over the realizations above do not:
    /// the relations are nonlinear; on the SHS yield-surface campaign by 2.8 % in the normal one).
    double continuum_youngs_modulus = 0, continuum_poisson_ratio = 0, continuum_bulk_modulus = 0;
  };

  /// From the ψ = 0 and ψ = 90° tests of microstructure `m` (every completed realization having both).
  /// With `given_poisson_ratio`, E comes from the axial modulus and that ν alone (the shear modulus
  /// is still measured and reported): for specimens that are not isotropic. Throws CalibrationError
  /// if either angle is missing or the constants are not admissible (K <= 0, ν outside (−1, 0.5)),
  /// naming the tests.
  ElasticConstants elastic_constants(const CampaignData &campaign, int m, double confidence,
                                     std::optional<double> given_poisson_ratio = std::nullopt);

  struct SofteningEstimate
  {
    /// "compaction tests" (params/collapse_calibration.h) or "load-controlled post-peak" (below:
    /// rate-dependent, what a campaign without compaction tests has).
    std::string source;
    SampleStatistics residual_ratio;            ///< R = σ_residual/σ_peak
    SampleStatistics plastic_volumetric_strain; ///< Δε_p from the peak to the residual stress
    SampleStatistics hardening_factor;          ///< ξ of p0 = K sinh(ξ max(−α, 0))
    // From compaction tests only (n = 0 otherwise):
    SampleStatistics fracture_energy_density;   ///< w_f [J/m³] (dem/lab/compaction_curve.h)
    SampleStatistics collapse_energy_density;   ///< w_c [J/m³]
    SampleStatistics lock_up_strain;            ///< ε_d, the collapse height over the layer thickness
    SampleStatistics lock_up_modulus;           ///< K_d [Pa]
    SampleStatistics peak_stress;               ///< σ_p of the compaction tests [Pa]
    std::vector<std::string> excluded;          ///< ψ = 0 tests that did not soften, with the reason
  };

  /// ξ and R from the ψ = 0 tests of microstructure `m`, for the compressive tip p0 and bulk modulus K
  /// of the calibrated continuum and the axial modulus of the tests. Throws CalibrationError if no
  /// ψ = 0 test softens (no sample after the peak at the residual stress, or Δε_p <= 0).
  SofteningEstimate collapse_softening(const CampaignData &campaign, int m, double p0, double bulk_modulus,
                                       double axial_modulus, double confidence);

  /// Statistics of per-realization values; with one realization the interval is the value itself
  /// (no spread can be estimated, and the caller reports n = 1).
  SampleStatistics realization_statistics(const std::vector<double> &values, double confidence,
                                          const std::string &what);

  /// ξ of the relation above (the one formula, shared with tests).
  double hardening_factor(double p0, double bulk_modulus, double residual_ratio, double plastic_volumetric_strain);
} // namespace anticrack::params
