// The collapse of the weak layer as the continuum needs it, from the campaign's displacement-
// controlled compaction tests (dem/lab/compaction_test.h, Campaign/Compaction strain rate [1/s]), one
// per realization: each curve is read by dem::fit_compaction_curve (dem/lab/compaction_curve.h) as
// the FE layer's response under uniaxial strain, and the calibration takes, per realization,
//   R     = σ_r / σ_p                          residual strength ratio
//   Δε_p  = ε_s − ε_p + (σ_p − σ_r)/M          plastic volumetric strain of the strength drop, M the
//                                              axial modulus of the load-controlled ψ = 0 tests (the
//                                              FE layer's, elastic_calibration.h)
//   ξ     = [asinh(p0/K) − asinh(R p0/K)]/Δε_p hardening factor of p0 = K sinh(ξ max(−α, 0)), the
//                                              collapse law's drop from p0 to R p0 over Δε_p
//                                              (elastic_calibration.h, hardening_factor)
//   w_f, w_c                                   fracture and collapse energy per unit volume
//   ε_d, K_d                                   lock-up strain and modulus (the FE's densification
//                                              strain and modulus; collapse height = ε_d h)
// then their means with t-intervals over the realizations. Under periodic sides the test is one of
// uniaxial strain, so the normal strain is the volumetric strain; with open sides the collapse is
// still a compaction band of zero lateral strain (Ritter et al. 2020, Fig. 1).
//
// The tests' quasi-static references (Campaign/Quasi-static check, the same test at the rate divided
// by the slowdown) give the rate check: every measure of a test against its reference's.
#pragma once

#include "dem/lab/compaction_curve.h"
#include "params/campaign_data.h"
#include "params/elastic_calibration.h"

#include <string>
#include <vector>

namespace anticrack::params
{
  /// One compaction test as the calibration read it.
  struct CompactionReading
  {
    std::string test;
    int realization = 0;
    double layer_thickness = 0;  ///< h [m]
    dem::CompactionCurveFit fit;
  };

  /// A compaction test against its slower quasi-static reference: relative differences
  /// (reference − test)/reference of each measure (absolute for the strains ε_d, Δε_p: over the
  /// reference's value as well).
  struct CompactionRateCheck
  {
    std::string test, reference;
    double peak_stress = 0, residual_ratio = 0, plastic_strain = 0, fracture_energy = 0, lock_up_strain = 0;
    [[nodiscard]] double largest() const;
  };

  /// The readings of microstructure `m`'s compaction tests and their statistics. Throws
  /// CalibrationError naming the test when a curve cannot be read (dem::fit_compaction_curve's
  /// reasons), when it ends before the lock-up, or when fewer than two realizations remain.
  SofteningEstimate compaction_softening(const CampaignData &campaign, int m, double p0, double bulk_modulus,
                                         double axial_modulus, double confidence,
                                         std::vector<CompactionReading> &readings,
                                         std::vector<CompactionRateCheck> &rate_checks);

  /// The reading of one test's curve (a compaction test of `campaign`), with the calibration's axial
  /// modulus M (elastic_calibration.h) for the plastic strain and the energies.
  CompactionReading read_compaction_test(const CampaignData &campaign, const CampaignTest &test, double axial_modulus);
} // namespace anticrack::params
