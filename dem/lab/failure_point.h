// Failure-point analysis of a virtual-laboratory test history (docs/physics.md §1.5): the failure point by
// the kinetic-energy window of Ritter et al. (2020) or by the peak of a stress measure (Bobillier et al. 2020), the secant
// modulus to 70 % of the peak and the softening ratio (Bobillier et al. 2020), and the plastic flow angle after
// failure (Ritter et al. 2020, docs/physics.md §1.5). Pure functions on recorded time series: no I/O, no deal.II.
//
// Sign conventions (docs/physics.md §0): stress tensors tension positive; p compression positive; the base
// normal stress sigma compression positive, the base shear stress tau along +x; displacements in the
// global frame with z up, so a clump moving down (compaction) has du_z < 0.
//
// Every function validates its input and throws std::invalid_argument with a message naming the
// offending argument (empty history, mismatched lengths, zero kinetic energy, out-of-range indices).
#pragma once

#include "dem/lab/compaction_curve.h"
#include "dem/lab/stress_invariants.h"
#include "dem/common/types.h"

#include <optional>
#include <vector>

namespace anticrack::dem
{
  /// Time series of one load- or displacement-controlled test; sample i of every non-empty series
  /// belongs to time[i]. Only time and stress are mandatory; each other series is either empty or has
  /// exactly time.size() entries.
  struct TestHistory
  {
    std::vector<double> time;              ///< [s], strictly increasing
    std::vector<Mat3> stress;              ///< Love-Weber stress, tension positive [Pa]
    std::vector<Vec3> clump_velocity;      ///< actuator velocity [m/s]; empty for wall-driven tests
    std::vector<Vec3> clump_displacement;  ///< actuator displacement [m] (flow angle)
    std::vector<double> strain;            ///< scalar loading strain [-] (secant modulus)
    std::vector<double> base_normal_stress; ///< sigma at the base, compression positive [Pa]
    std::vector<double> base_shear_stress;  ///< tau at the base [Pa]
  };

  /// Throws std::invalid_argument unless the history is non-empty, time is strictly increasing and
  /// every optional series is empty or as long as time.
  void validate(const TestHistory &history);

  // p and q of the stress samples: dem/lab/stress_invariants.h (Ritter et al. 2020, Eqs. 9-11).

  /// q of every sample of the history.
  std::vector<double> von_mises_series(const TestHistory &history);

  /// The state of the test at the failure point.
  struct FailurePoint
  {
    Index index = -1;
    double time = 0;
    Mat3 stress = Mat3::Zero();     ///< full Love-Weber tensor at the index (tension positive)
    double p = 0;                   ///< -tr(stress)/3
    double q = 0;                   ///< sqrt(3/2 s:s)
    std::optional<double> sigma;    ///< base normal stress at the index, when recorded
    std::optional<double> tau;      ///< base shear stress at the index, when recorded
    Index window_begin = 0;         ///< first sample of the searched range
    Index window_end = 0;           ///< last sample of the searched range (inclusive)
  };

  /// Failure point by Ritter et al.'s (2020) two-step criterion ("Failure identification", Eq. 8).
  ///   E_k*(i) = |v_c(i)|^2 / max_j |v_c(j)|^2.
  /// Window (our precise reading of "the strain range where E_k* < zeta"): let m be the first sample
  /// of the global maximum of |v_c|^2 (E_k*(m) = 1, the run-away after failure). The window is
  /// [0, e] with e the last sample before m with E_k*(e) < zeta, i.e. it ends with the last quiet
  /// stretch before the run-away; e + 1 is the first time E_k* reaches zeta after that stretch.
  /// Earlier, transient excursions (E_k* >= zeta before the last quiet stretch, e.g. the initial
  /// seating of the clump) do not end the window, but their own samples are excluded from the search.
  /// The failure point is the sample of maximum q among the samples of [0, e] with E_k* < zeta (first
  /// one on ties). Requires clump_velocity; throws std::invalid_argument if it is empty, if the clump
  /// never moves (max |v_c| = 0), if zeta is not in (0, 1] or if no sample before the maximum is quiet.
  FailurePoint failure_by_kinetic_energy_window(const TestHistory &history, double zeta = 0.3);

  /// How a test's actuator is driven, which decides how its failure point is found
  /// (dem/scene/failure_analysis.h): a load-controlled actuator runs away at failure (Ritter et al.'s
  /// (2020) kinetic-energy window); a displacement-controlled one cannot, its failure is the peak of
  /// the base stress it drives.
  enum class ActuatorControl
  {
    force,               ///< clump force ramp, tilted gravity
    shear_displacement,  ///< simple shear: the peak of the base shear stress, strain u_x / h
    normal_displacement  ///< compaction: the first peak of the base normal stress, strain -u_z / h
  };

  /// Stress measure whose peak defines failure.
  enum class Measure
  {
    von_mises,   ///< q of the Love-Weber stress (Ritter et al. 2020)
    base_shear,  ///< |tau| at the base (Bobillier et al. 2020, shear-dominated loading)
    base_normal  ///< sigma at the base, compression positive; its peak is the largest |sigma| (compression or tension)
  };

  /// Failure as the maximum of the measure over the whole history (Bobillier et al. 2020: "the maximum stress
  /// before catastrophic failure"; first sample on ties). The window is the whole history. Throws
  /// std::invalid_argument if the chosen base series is not recorded.
  FailurePoint failure_by_peak(const TestHistory &history, Measure measure);

  /// The series of a measure, one value per sample (q, |tau| or sigma).
  std::vector<double> measure_series(const TestHistory &history, Measure measure);

  /// Secant modulus (Bobillier et al. 2020, response to reviewer: "secant modulus up to 70 % of the peak stress"):
  ///   E = sigma_f / eps_f,
  /// the slope of the line from the origin (eps, sigma) = (0, 0) to the first point where the stress
  /// reaches fraction * stress[peak_index]. That point is interpolated linearly between the samples
  /// i-1 and i that bracket the target (the first i <= peak_index with s_i >= target, s = stress
  /// measured in the direction of the peak's sign, so negative peaks work too). A history recorded
  /// with a preload must be shifted to its own origin by the caller. Throws std::invalid_argument on
  /// mismatched lengths, a zero peak, fraction outside (0, 1], or a zero strain at the target point.
  double secant_modulus(const std::vector<double> &strain, const std::vector<double> &stress_measure,
                        Index peak_index, double fraction = 0.7);

  /// Softening ratio R = sigma_residual / sigma_peak (Bobillier et al. 2020, "softening ratio";
  /// docs/physics.md §1.5), with sigma_peak = stress[peak_index] and sigma_residual the arithmetic
  /// mean of the last half of the post-peak samples (ceil(m/2) of the m samples after the peak):
  /// the end of the test stands for the brittle-crushing phase, and a load-controlled test
  /// collapses within a few samples of its peak, so a share of the whole history could reach back
  /// to the peak. The one definition of the project: the run summary, campaign.h5 and the
  /// calibration (params/elastic_calibration.cpp) all use it. Throws std::invalid_argument if fewer
  /// than min_post_peak_samples samples follow the peak or if the peak is zero.
  double softening_ratio(const std::vector<double> &stress_measure, Index peak_index);

  /// Samples after the peak that softening_ratio() needs.
  inline constexpr Index min_post_peak_samples = 2;

  /// Plastic flow angle (Ritter et al. 2020, Eq. 18 / docs/physics.md §1.5) from the clump displacement increment
  /// du = u(failure_index + window) - u(failure_index) just after failure:
  ///   theta = atan2(du_z, du_x)  in radians, in (-pi, pi].
  /// With z up: du_z < 0 (compaction, "anticrack") gives theta < 0, du_z > 0 (dilation) theta > 0;
  /// pure compression gives -pi/2, pure shear along +x gives 0. Throws std::invalid_argument if the
  /// displacement series is empty, window < 1, failure_index + window is past the end, or du has no
  /// component in the x-z plane.
  double flow_angle(const TestHistory &history, Index failure_index, Index window);

  struct FailureAnalysisOptions
  {
    double zeta = 0.3;                      ///< kinetic-energy threshold
    Measure loading_measure = Measure::base_normal; ///< curve for secant modulus and softening ratio
    double secant_fraction = 0.7;
    Index flow_window = 10;                 ///< samples after failure for the flow angle
    /// Failure at the peak of the loading measure instead of the kinetic-energy window (tests whose
    /// actuator is displacement-controlled, e.g. simple shear with base_shear: its velocity is
    /// prescribed, so its kinetic energy says nothing about failure).
    bool failure_at_loading_peak = false;
    /// With the loading measure base_normal: the peak is sought only up to the lock-up of a
    /// compaction test (compaction_lock_up_index), whose densified layer may carry more than the
    /// peak that broke it.
    bool peak_before_lock_up = false;
  };

  /// Everything for one test. Quantities whose input series is missing stay empty.
  struct FailureAnalysis
  {
    /// By the kinetic-energy window if clump_velocity is recorded, else by the peak of q.
    FailurePoint failure;
    FailurePoint peak_q;                            ///< failure_by_peak(von_mises)
    std::optional<FailurePoint> peak_loading;       ///< failure_by_peak(loading_measure)
    std::optional<double> secant_modulus;           ///< needs strain and the loading measure
    std::optional<double> softening_ratio;          ///< of the loading measure, about its peak
    std::optional<double> flow_angle;               ///< after `failure`, needs displacement and enough samples
    /// With peak_before_lock_up: the whole curve read by fit_compaction_curve (its own secant as the
    /// axial modulus; a calibration reads it again with the campaign's).
    std::optional<CompactionCurveFit> compaction_curve;
  };

  /// Runs the analysis; throws like the functions above for invalid histories. If the loading measure
  /// is not recorded, peak_loading, secant_modulus and softening_ratio stay empty (base_normal falls
  /// back to nothing, not to q, to keep the meaning of the numbers unambiguous).
  FailureAnalysis analyse_failure(const TestHistory &history, const FailureAnalysisOptions &options = {});
} // namespace anticrack::dem
