// The stress-strain curve of a displacement-controlled compaction test (dem/lab/compaction_test.h)
// read as the continuum reads it: the piecewise-linear response of the FE weak layer under uniaxial
// strain (docs/physics.md §2), fitted to the DEM curve past its peak,
//
//   σ(ε) = σ_p − (σ_p − σ_r)(ε − ε_p)/(ε_s − ε_p)   ε_p ≤ ε < ε_s   strength drop (collapse softening)
//        = σ_r                                      ε_s ≤ ε < ε_d   collapse plateau (residual strength)
//        = σ_r + K_d (ε − ε_d)                      ε ≥ ε_d         densification of the broken grains
//
// with (ε_p, σ_p) the first peak, σ_r the residual stress, ε_s the end of the drop, ε_d the onset of
// the densification and K_d its modulus: the FE's residual strength ratio, the end of its softening,
// its densification (lock-up) strain and modulus.
//
// What the DEM curves look like, and why the reading is so: a bonded snow layer's stress falls
// within a few tenths of a percent of strain to 0.1–0.25 of its peak, stays there for a few
// percent (the broken grains rearrange into the pores), then rises again, convex, as the grains
// densify: it regains the peak at 15–20 % and triples it a few percent later (the SHS layer of
// scenes/shs_weak_layer.prm, docs/calibration.md). A slab loads its collapsed layer with 0.1–0.5 of
// the layer's strength, so what decides whether a slab crushes the layer and how far it falls is
// the level right after the drop and how the densification rises from it: σ_r is that level, not
// the mean of the plateau and the densification (which a flat residual up to a steep lock-up
// would read: 0.53 σ_p for the SHS layer, where the curve sits at about 0.2).
//   * the first peak: the running maximum of the stress at the first sample where the stress has
//     fallen below compaction_collapse_fraction (1/2) of it, the collapse. A layer whose stress never
//     halves does not collapse and is refused (it hardens);
//   * the regain ε_x: where the densified layer carries σ_p again for good (the last upward
//     crossing of σ_p before the stress exceeds compaction_lock_up_stress_ratio (3) × σ_p, where
//     the test stops: CompactionStages);
//   * ε_s, ε_d and σ_r: least squares of the three pieces on (ε_p, ε_x], the densification a line
//     from (ε_d, σ_r) through (ε_x, σ_p) (so K_d = (σ_p − σ_r)/(ε_x − ε_d)), weighted by the strain
//     each sample stands for (a fit to the curve, not to the output interval); ε_s on a logarithmic
//     and ε_d on a linear grid, refined, σ_r linear for each pair (0 <= σ_r <= σ_p). The convex
//     densification is read as the secant to the regain: between σ_r and σ_p (where every slab
//     load lies) it errs by the curvature, which the fit's RMS misfit reports;
//   * the steeper branch beyond the regain (σ_p to 3σ_p, reported as cap_modulus) is not the FE's:
//     a slab that loaded its weak layer past σ_p would have collapsed it before any saw cut.
// Both ratios are detection thresholds; docs/calibration.md shows what changing them does.
//
// Energies per unit volume of the layer:
//   fracture energy   w_f = (σ_p − σ_r) Δε_p / 2 with Δε_p = ε_s − ε_p + (σ_p − σ_r)/M the drop's
//                     plastic strain: what the fitted drop dissipates beyond the residual, which is
//                     what the FE point with these parameters dissipates (its p0 falls linearly in
//                     the plastic strain for p0 ≪ K). Read from the fit, not from the samples: on a
//                     hardening plateau the area between the curve and its mean has either sign;
//   collapse energy   w_c = ∫_0^{ε_d} σ dε − σ_r²/(2M): everything the DEM layer dissipates up to
//                     the lock-up (trapezoidal rule in strain, M the secant modulus of the elastic
//                     branch to 70 % of the peak).
// Times the layer thickness they are energies per unit layer area [J/m²].
//
// Strains are those of the deformable layer (u/h), compression positive; stresses compression
// positive.
#pragma once

#include "dem/common/types.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace anticrack::dem
{
  struct CompactionCurveFit
  {
    Index peak_index = 0;          ///< sample of the first peak
    double peak_strain = 0;        ///< ε_p
    double peak_stress = 0;        ///< σ_p [Pa]
    double axial_modulus = 0;      ///< M [Pa]: given, or the secant to 70 % of the peak
    double residual_stress = 0;    ///< σ_r [Pa]
    double softening_end_strain = 0; ///< ε_s
    double lock_up_strain = 0;     ///< ε_d (the last strain when not locked up)
    double lock_up_modulus = 0;    ///< K_d [Pa]: of the densification, from (ε_d, σ_r) to the regain of σ_p
    double cap_modulus = 0;        ///< secant of the locked-up branch from σ_p to 3σ_p [Pa] (reported, not the FE's)
    double regain_strain = 0;      ///< where the locked-up layer carries σ_p again (last upward crossing)
    double fracture_energy_density = 0; ///< w_f [J/m³]
    double collapse_energy_density = 0; ///< w_c [J/m³]
    double rms_misfit = 0;         ///< strain-weighted RMS of data − model over the fit, over σ_p

    /// σ_r / σ_p.
    [[nodiscard]] double residual_ratio() const { return residual_stress / peak_stress; }
    /// ε_s − ε_p: total strain of the drop.
    [[nodiscard]] double softening_strain() const { return softening_end_strain - peak_strain; }
    /// Plastic strain of the drop: the total strain plus the elastic strain the falling stress
    /// gives back, ε_s − ε_p + (σ_p − σ_r)/M.
    [[nodiscard]] double plastic_softening_strain() const
    {
      return softening_strain() + (peak_stress - residual_stress) / axial_modulus;
    }
    /// The model above at strain `e`.
    [[nodiscard]] double model_stress(double e) const;
  };

  /// Samples of increasing strain a curve needs at the least to be read.
  inline constexpr std::size_t compaction_minimum_samples = 20;
  /// The stress falls below this fraction of its running maximum: the collapse after the first peak.
  inline constexpr double compaction_collapse_fraction = 0.5;
  /// Samples the rise to the peak needs at the least: a coarser history misses the peak (on the SHS
  /// layer of scenes/shs_weak_layer.prm at 5 /s, rows every 800 steps (8.8e-4 strain) give a peak
  /// 21 % low). docs/work_precision.md measures what the curve's strain interval does to the fit.
  inline constexpr std::size_t compaction_elastic_samples = 5;
  /// The fit ends where the stress exceeds this multiple of the first peak after the collapse.
  inline constexpr double compaction_lock_up_stress_ratio = 3;

  /// Fits the curve (strain[i], stress[i]), strain increasing; least squares weighted by the strain
  /// each sample stands for. Throws std::invalid_argument with the reason when the curve cannot be
  /// read this way: fewer than compaction_minimum_samples samples, strains not increasing, no positive stress, no collapse,
  /// fewer than 10 samples in the fit.
  /// The stages of a compaction curve as they come, sample by sample: the first peak (the running
  /// maximum until the collapse), the collapse (the stress below compaction_collapse_fraction of
  /// it, once the peak has been reached by compaction_elastic_samples new maxima since the stress
  /// last fell below that fraction) and the
  /// lock-up (above compaction_lock_up_stress_ratio times the peak after the collapse). One
  /// definition, on the same samples (the history's rows), for the fit below and for the test that
  /// stops once it has locked up (dem/lab/compaction_test.h).
  /// A real peak is the end of a resolved rise, as many samples as the fit needs anyway. The
  /// arriving stress wave's first readings are not: 4e-9 Pa, then -0.05 Pa, then 45 Pa at N = 4096
  /// (a "peak", its "collapse" and a "lock-up" that stopped the test at 800 steps), and 6.6e-8 Pa
  /// and a dip at phi = 0.22 (after five positive readings, which an earlier count of compressive
  /// samples let pass). A fall below the fraction before a resolved rise is such a reading: the
  /// running maximum starts again from it.
  struct CompactionStages
  {
    double lock_up_ratio = compaction_lock_up_stress_ratio; ///< of the stress over the peak at lock-up
    double peak = 0;        ///< the running maximum, frozen at the collapse [Pa]
    std::size_t rising_samples = 0; ///< new maxima since the last fall below the fraction
    bool collapsed = false;
    bool locked_up = false;

    /// Takes the next stress; returns true if this sample is the new running maximum.
    bool add(double stress)
    {
      if (!collapsed)
      {
        if (stress > peak)
        {
          peak = stress;
          ++rising_samples;
          return true;
        }
        if (stress < compaction_collapse_fraction * peak)
        {
          collapsed = rising_samples >= compaction_elastic_samples;
          if (!collapsed)
            peak = std::max(stress, 0.0), rising_samples = 0;
        }
      }
      else if (stress > lock_up_ratio * peak)
        locked_up = true;
      return false;
    }
  };

  /// `axial_modulus`: M for the plastic strain and the energies (the calibration's, which the FE
  /// layer has); NaN: the curve's own secant to 70 % of its peak.
  CompactionCurveFit fit_compaction_curve(const std::vector<double> &strain, const std::vector<double> &stress,
                                          double axial_modulus = std::numeric_limits<double>::quiet_NaN());

  /// A fit as a run's summary.json (dem.failure_analysis.compaction_curve) and calibration.json
  /// (softening.compaction_tests) record it: every field, the derived ratio and plastic strain.
  nlohmann::json compaction_curve_json(const CompactionCurveFit &fit);
} // namespace anticrack::dem
