// Fitting a failure envelope (yield_envelopes.h) to DEM failure points, with its uncertainty.
//
// Residuals. The DEM loads along rays from the origin, so the failure point i is a radius r_i measured
// at a controlled polar angle a_i. DEM strengths scatter in proportion to their size (a coefficient of
// variation: the same few per cent at the compressive tip as in tension), so the residuals are
// relative, e_i = ln r_i - ln R(a_i; theta), and the fit minimises SSR = sum_i e_i^2 over the internal
// (unconstrained) parameters theta with Levenberg-Marquardt (MINPACK's lmder, Eigen unsupported
// module), from every starting point the model derives from the data, keeping the lowest SSR. All
// families are compared on the same residuals. (With absolute residuals r_i - R(a_i) and 3 % relative
// scatter the covariance intervals below were too narrow: the nominal 95 % interval of p0 covered the
// truth in 77 % of synthetic data sets with Ritter et al.'s (2020) design; the relative residuals restore 93-96 %,
// tests/params/test_envelope_fit.cpp.)
//
// Goodness of fit. R^2 = 1 - SSR/SST with SST = sum_i (ln r_i - mean ln r)^2, in the coordinate of the
// fit (Bobillier et al. 2020, reply to referee 2, comment 31: "R^2 = 1 - SSR/SST, SSR the residual sum of squares, SST the total
// sum of squares"); RMSE = sqrt(SSR/n), a relative error; information criteria with k = p + 1
// parameters (the noise variance is estimated too): AIC = n ln(SSR/n) + 2k, AICc = AIC +
// 2k(k+1)/(n-k-1), BIC = n ln(SSR/n) + k ln n.
//
// Uncertainty, two ways.
//  - Asymptotic covariance in internal coordinates, Cov = s^2 (J^T J)^-1 with s^2 = SSR/(n-p) and J the
//    Jacobian of the residuals; Student-t intervals theta_j +- t_{(1+c)/2, n-p} sqrt(Cov_jj), mapped to
//    physical parameters endpoint by endpoint where the map is monotone in one coordinate (so a positive
//    parameter keeps a positive, asymmetric interval), by the delta method otherwise.
//  - Bootstrap over groups (DEM realizations of one microstructure): the groups are resampled with
//    replacement and the fit repeated; percentile intervals. It accounts for the scatter between
//    realizations, which the residual variance of one pooled fit treats as independent noise; with
//    three realizations, however, there are only ten distinct resamples, and its percentile intervals
//    are too narrow: they covered the truth in 73-75 % of synthetic data sets where the covariance
//    intervals covered 94.9-95.4 % (9 angles x 3 realizations, 3 % scatter). The calibration therefore
//    reports the covariance intervals first and the bootstrap beside them.
#pragma once

#include "params/yield_envelopes.h"

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

namespace anticrack::params
{
  /// Throws CalibrationError, before any fit, for data that cannot determine an envelope: non-finite
  /// values; fewer points than n_parameters + 1 (the residual variance needs a degree of freedom);
  /// negative shear (the plane's shear coordinate is >= 0) or a point at the origin (no polar angle);
  /// all points within 5 degrees of polar angle (one ray says nothing about the shape); no tensile
  /// point, normal < 0 (the tensile tip would be an extrapolation). `what` names the data set in the
  /// message, e.g. "microstructure 0, (p, q) plane".
  void check_envelope_data(const std::vector<StressPoint> &points, std::size_t n_parameters,
                           const std::string &what);

  struct EnvelopeFitOptions
  {
    double confidence = 0.95;      ///< level of every interval and band, in (0, 1)
    int bootstrap_samples = 1000;  ///< resamples of the groups; 0 switches the bootstrap off
    std::uint64_t seed = 1;        ///< of the bootstrap's std::mt19937_64: same seed, same resamples
    int max_iterations = 2000;     ///< per Levenberg-Marquardt run, counted in residual evaluations
    std::string data_set = "failure points"; ///< named in error messages
    bool use_model_guesses = true; ///< start from YieldEnvelope::initial_guesses()
    /// Further starting points (physical, admissible), tried after the model's own; with
    /// use_model_guesses = false they are the only ones (to test robustness to a poor guess).
    std::vector<Eigen::VectorXd> extra_initial_guesses;
  };

  /// Information criteria of a least-squares fit with Gaussian errors, k = n_parameters + 1.
  struct InformationCriteria
  {
    double aic = 0;  ///< n ln(SSR/n) + 2k
    double aicc = 0; ///< AIC + 2k(k+1)/(n-k-1); +infinity if n - k - 1 <= 0
    double bic = 0;  ///< n ln(SSR/n) + k ln n
  };

  InformationCriteria information_criteria(double ssr, std::size_t n_points, std::size_t n_parameters);

  /// Asymptotic covariance of least-squares parameters.
  struct LeastSquaresCovariance
  {
    /// s^2 (J^T J)^-1 in the coordinates of J's columns. Rows and columns of unidentifiable coordinates
    /// hold +infinity on the diagonal and NaN elsewhere.
    Eigen::MatrixXd covariance;
    /// False for a coordinate with a component in the null space of J (the data do not determine it).
    std::vector<bool> identifiable;
    double residual_variance = 0; ///< s^2 = SSR / (n - p)
    int degrees_of_freedom = 0;   ///< n - p
  };

  /// Cov = s^2 (J^T J)^-1 for the m x p Jacobian J of the residuals (m > p). A singular J^T J does not
  /// throw: the inverse is taken on the identifiable subspace (a pseudo-inverse, which gives the right
  /// variance for every coordinate orthogonal to the null space, whatever generalised inverse is used),
  /// the other coordinates are marked unidentifiable. Rank is judged on the column-scaled J^T J
  /// (eigenvalues below 1e-10 of the largest).
  LeastSquaresCovariance least_squares_covariance(const Eigen::MatrixXd &jacobian, double ssr);

  /// The fitted envelope and its uncertainty. Parameter vectors are physical, in the order of
  /// YieldEnvelope::parameter_names().
  struct EnvelopeFit
  {
    std::string model;                         ///< YieldEnvelope::name()
    std::vector<std::string> parameter_names;
    std::vector<std::string> parameter_units;
    Eigen::VectorXd parameters;                ///< best fit
    Eigen::VectorXd internal_parameters;       ///< best fit, internal coordinates
    Eigen::MatrixXd internal_covariance;       ///< see LeastSquaresCovariance
    Eigen::MatrixXd covariance;                ///< physical, by the delta method: J_map Cov J_map^T
    double confidence = 0.95;                  ///< level of the intervals below

    /// Student-t intervals from the covariance. Unidentifiable parameters: (-inf, +inf).
    Eigen::VectorXd ci_lower, ci_upper;
    bool identifiable = true;                  ///< false if J^T J is singular at the best fit

    bool has_bootstrap = false;                ///< >= 3 groups, bootstrap requested, >= 2 resamples fitted
    Eigen::VectorXd bootstrap_lower, bootstrap_upper; ///< percentile intervals
    Eigen::MatrixXd bootstrap_samples;         ///< fitted resamples x parameters (physical)
    int bootstrap_failures = 0;                ///< resamples skipped: degenerate data or no converged fit

    double ssr = 0;        ///< sum of squared relative residuals (ln r_i - ln R(a_i))^2
    double sst = 0;        ///< sum of squared deviations of ln r_i from their mean
    double r_squared = 0;  ///< 1 - SSR/SST (NaN if SST = 0)
    double rmse = 0;       ///< sqrt(SSR/n), relative (0.03 = 3 %)
    double aic = 0, aicc = 0, bic = 0;
    std::size_t n_points = 0;
    int starts = 0;         ///< starting points tried
    int starts_at_best = 0; ///< starts that converged to the lowest SSR (within 1e-8 relative)
    Eigen::VectorXd residuals; ///< ln r_i - ln R(a_i) at the best fit (relative)
  };

  /// Fits the envelope to the points (see the file comment). `groups` is empty or holds one group id
  /// (realization) per point; with >= 3 distinct ids and options.bootstrap_samples > 0 the groups are
  /// bootstrapped, each resample refitted from the best fit. Throws CalibrationError for degenerate
  /// data (check_envelope_data), an inadmissible extra starting point, or when no start converges to a
  /// finite, admissible envelope; std::invalid_argument for groups of the wrong length or options out of
  /// range.
  EnvelopeFit fit_envelope(const YieldEnvelope &model, const std::vector<StressPoint> &points,
                           const std::vector<int> &groups, const EnvelopeFitOptions &options = {});

  /// Radius of the fitted envelope on a grid of polar angles with a confidence band, for plots.
  struct EnvelopeBand
  {
    std::vector<double> angle;  ///< n_angles values from 0 to pi [rad]
    std::vector<double> radius; ///< best fit [Pa]
    std::vector<double> lower;  ///< lower end of the band [Pa]
    std::vector<double> upper;  ///< upper end of the band [Pa]
    bool from_bootstrap = false;
  };

  /// Pointwise band at fit.confidence: by default the delta method, R -+ t sqrt(g Cov g^T) with
  /// g = dR/dtheta (central differences in internal coordinates), its lower end floored at 0 and
  /// infinite where a parameter is unidentifiable; with `from_bootstrap` (and a bootstrap in the fit)
  /// the percentiles of the radius over the bootstrap samples. The covariance is the default because
  /// it keeps its coverage with few realizations (measured with Ritter et al.'s (2020) design, 9 angles x 3
  /// realizations, 3 % scatter: 95 % intervals covering in 94.9-95.4 % of 2000 data sets, the
  /// percentile bootstrap over the three realizations in only 73-75 %). Throws std::invalid_argument
  /// if the fit is of another model or n_angles < 2.
  EnvelopeBand envelope_band(const YieldEnvelope &model, const EnvelopeFit &fit, int n_angles,
                             bool from_bootstrap = false);
} // namespace anticrack::params
