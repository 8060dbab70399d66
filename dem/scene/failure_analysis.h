// Failure analysis of a finished run (the virtual lab's yield point, docs/physics.md §1.5): the history's
// Love-Weber stress, actuator motion and base stresses become a dem::TestHistory, and
// dem::analyse_failure (dem/lab/failure_point.h) picks the failure point (Ritter et al.'s (2020)
// kinetic-energy window, then max q), the peaks, the secant modulus, the softening ratio and the
// plastic flow angle. The run hands the result to its caller in memory (a campaign tabulates it,
// dem/campaign/campaign_file.h) and writes it into summary.json (dem.failure_analysis), from where a
// resumed campaign reads it back.
#pragma once

#include "dem/common/types.h"
#include "dem/lab/failure_point.h"
#include "util/time_series.h"

#include <nlohmann/json.hpp>

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace anticrack::dem
{
  /// A point of the analysis as the run records it.
  struct RecordedFailurePoint
  {
    double step = 0;                  ///< engine step of the history sample
    double time = 0;                  ///< [s]
    double p = 0;                     ///< mean pressure of the Love-Weber stress, compression positive [Pa]
    double q = 0;                     ///< von Mises stress of the Love-Weber stress [Pa]
    std::optional<double> sigma, tau; ///< base stresses, when recorded [Pa]
    Mat3 love_stress = Mat3::Zero();  ///< tension positive [Pa]
  };

  /// The failure analysis of a clump-driven test: dem::FailureAnalysis (dem/lab/failure_point.h)
  /// with the engine step of every point, the flow angle in degrees and the quasi-static measure of
  /// the approach to failure.
  struct TestFailureAnalysis
  {
    std::string error;             ///< why the history allows no analysis; empty: the rest holds
    ActuatorControl control = ActuatorControl::force; ///< decides the criterion (analyse_test_history)
    RecordedFailurePoint failure;
    RecordedFailurePoint peak_q;
    std::optional<RecordedFailurePoint> peak_loading; ///< of sigma (tau when shear-controlled)
    std::optional<double> secant_modulus;             ///< to 70 % of the loading peak [Pa]
    std::optional<double> softening_ratio;            ///< residual / peak of the loading measure
    std::optional<double> flow_angle_deg;             ///< atan2(du_z, du_x) just after failure
    /// Compaction tests: the curve's fit, with its own secant modulus as M (summary.json's
    /// dem.failure_analysis.compaction_curve; not read back: a calibration fits the history again
    /// with the campaign's M).
    std::optional<CompactionCurveFit> compaction_curve;
    /// Largest inertial number between half the failure q and the failure point
    /// (max_inertial_number_before_failure); NaN without the columns. Not part of summary.json:
    /// a campaign that reads a test back computes it from the test's history.h5.
    double max_inertial_number = std::numeric_limits<double>::quiet_NaN();
  };

  /// Analysis of a clump-driven test (needs the clump and Love-Weber columns); `layer_thickness` [m]
  /// turns the clump's displacement into the loading strain u/h of the deformable layer between
  /// the rigid base and clump, as the calibration does (params/elastic_calibration.h). If the
  /// history does not allow the analysis (no clump, no run-away yet) `error` says why.
  /// `control`: force, Ritter et al.'s criterion; shear_displacement (simple shear), failure at the
  /// peak of the base shear stress, strain u_x / h; normal_displacement (compaction), failure at the
  /// first peak of the base normal stress, before the lock-up (dem/lab/compaction_curve.h).
  TestFailureAnalysis analyse_test_history(const TimeSeries &history, double layer_thickness,
                                           ActuatorControl control = ActuatorControl::force);

  /// Ritter et al. (2020, Methods): a test is quasi-static while its inertial number stays below this.
  inline constexpr double quasi_static_inertial_number = 1e-4;

  /// Was the loading quasi-static as failure approached? The largest inertial number over the
  /// samples up to `failure_step` whose q is at least half the failure q (earlier, I ~ 1/sqrt(p)
  /// measures nothing but the start of the ramp at vanishing stress). The series are the history's
  /// step, von_mises_stress and inertial_number columns.
  double max_inertial_number_before_failure(const std::vector<double> &step, const std::vector<double> &von_mises,
                                            const std::vector<double> &inertial_number, double failure_step,
                                            double failure_q);

  /// summary.json's dem.failure_analysis (keys in alphabetical order, as summary.json has them).
  nlohmann::json failure_analysis_json(const TestFailureAnalysis &analysis);

  /// The analysis read back from summary.json's dem.failure_analysis; numbers that the file lacks
  /// or records as null are NaN, max_inertial_number is NaN.
  TestFailureAnalysis failure_analysis_from_json(const nlohmann::ordered_json &json);
} // namespace anticrack::dem
