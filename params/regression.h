// Small-sample regression for the calibration: straight lines, power laws and sample statistics,
// each with its t-based confidence interval, and the thickness scaling of micro-to-macro laws.
//
// The calibration fits few points (three realisations per microstructure, nine or ten particle
// properties per micro-macro relation), so every estimate is reported with its interval from
// Student's t distribution rather than the normal one:
//
//  * lines y = intercept + slope x: the micro-to-macro relations of Bobillier et al. (2020), Eqs. (5)-(8)
//    (E_macro = beta_0 + beta_1 E_particle, sigma_macro = gamma_0 + gamma_1 sigma_bond);
//  * power laws y = prefactor x^exponent: the scaling of the Cam-Clay tips with contact density,
//    Ritter et al. 2020, Eqs. (2)-(3) (sigma_0/sigma_bond = h nu_c^kappa, beta sigma_0/sigma_bond = k nu_c^lambda),
//    fitted as lines in log-log space;
//  * mean and spread of a parameter without a trend, e.g. M (Ritter et al. 2020: "M varies between 0.6 and 1
//    with an average of ~0.8").
//
// Goodness of fit is R^2 = 1 - SSR/SST (Bobillier et al. 2020, reply to referee 2, comment 31, on its Eq. 9): SSR the residual
// and SST the total sum of squares about the mean.
#pragma once

#include <string>
#include <vector>

namespace anticrack::params
{
  /// Quantile of Student's t distribution: the t with P(T <= t) = `probability` for
  /// `degrees_of_freedom` degrees of freedom (Boost.Math). Two-sided intervals of confidence c use
  /// probability (1 + c)/2. Throws CalibrationError for a probability outside (0, 1) or
  /// non-positive degrees of freedom.
  double student_t_quantile(double probability, double degrees_of_freedom);

  /// A closed interval [lower, upper].
  struct Interval
  {
    double lower = 0;
    double upper = 0;

    /// True if lower <= value <= upper.
    [[nodiscard]] bool contains(double value) const { return lower <= value && value <= upper; }
  };

  /// Ordinary least-squares line y = intercept + slope x with its uncertainty.
  struct LinearFit
  {
    double intercept = 0;
    double slope = 0;
    double intercept_standard_error = 0;
    double slope_standard_error = 0;
    /// Covariance of the two estimates; with the standard errors it gives the variance of a
    /// prediction, var(a + b x) = se_a^2 + 2 x cov_ab + x^2 se_b^2.
    double intercept_slope_covariance = 0;
    Interval intercept_ci;  ///< t-interval of `confidence`, n - 2 degrees of freedom
    Interval slope_ci;      ///< t-interval of `confidence`, n - 2 degrees of freedom
    /// 1 - SSR/SST; NaN if y does not vary (SST = 0), where R^2 is undefined.
    double r_squared = 0;
    double residual_standard_deviation = 0;  ///< sqrt(SSR/(n - 2)), in units of y
    double confidence = 0.95;                ///< of the intervals
    int n = 0;                               ///< number of points

    /// The fitted line at x.
    [[nodiscard]] double operator()(double x) const { return intercept + slope * x; }
  };

  /// Fits y = intercept + slope x by ordinary least squares (in centred form, which keeps the
  /// estimates exact to round-off even when x is far from zero, e.g. E_particle ~ 1e8 Pa).
  /// Throws CalibrationError, naming `what`, for fewer than 3 points (two parameters and one degree
  /// of freedom for the standard errors), sizes that differ, non-finite values, all x equal, or a
  /// confidence outside (0, 1).
  LinearFit fit_line(const std::vector<double> &x,
                     const std::vector<double> &y,
                     double confidence = 0.95,
                     const std::string &what = "");

  /// Power law y = prefactor x^exponent, fitted as ln y = ln(prefactor) + exponent ln x.
  struct PowerLawFit
  {
    double prefactor = 0;
    double exponent = 0;
    double exponent_standard_error = 0;
    /// Standard error of ln(prefactor), the intercept in log space.
    double log_prefactor_standard_error = 0;
    Interval exponent_ci;   ///< t-interval, n - 2 degrees of freedom
    /// exp of the t-interval of ln(prefactor): asymmetric about the prefactor.
    Interval prefactor_ci;
    double r_squared_log = 0;  ///< R^2 of ln y (the fitted, linear model)
    /// R^2 of y itself, 1 - sum (y - prefactor x^exponent)^2 / sum (y - mean y)^2; it can be
    /// negative because the fit minimises the log residuals, not these.
    double r_squared = 0;
    LinearFit log_fit;         ///< the line in (ln x, ln y)
    double confidence = 0.95;
    int n = 0;

    /// The fitted power law at x (x > 0).
    [[nodiscard]] double operator()(double x) const;
  };

  /// Fits y = prefactor x^exponent by least squares of ln y on ln x (Ritter et al. 2020, Eqs. 2-3). Multiplicative
  /// scatter, which is what a power law over a decade of nu_c shows, becomes additive in log space.
  /// Throws CalibrationError, naming `what` and the offending value, for x <= 0 or y <= 0, and as
  /// fit_line for fewer than 3 points, sizes that differ, non-finite values or fewer than 2 distinct x.
  PowerLawFit fit_power_law(const std::vector<double> &x,
                            const std::vector<double> &y,
                            double confidence = 0.95,
                            const std::string &what = "");

  /// Mean and spread of a sample.
  struct SampleStatistics
  {
    double mean = 0;
    double standard_deviation = 0;  ///< sample standard deviation (divides by n - 1)
    double minimum = 0;
    double maximum = 0;
    Interval mean_ci;               ///< t-interval of the mean, n - 1 degrees of freedom
    double confidence = 0.95;
    int n = 0;
    /// The values described, in their order (e.g. one per realization): estimates taken from the
    /// same curves (ξ, R and the lock-up strain of one compaction test) keep their pairing, so
    /// the covariance of their means can be estimated (covariance_of_means).
    std::vector<double> values;
  };

  /// The covariance of the means of two paired samples, Σ(a − ā)(b − b̄)/((n − 1) n): the sample
  /// covariance over n, the off-diagonal term beside the squared standard errors sd²/n. Throws
  /// CalibrationError for samples of different sizes or fewer than 2 pairs.
  double covariance_of_means(const std::vector<double> &a, const std::vector<double> &b);

  /// Mean, sample standard deviation, range and t-interval of the mean of `values` (e.g. the M of
  /// every fitted microstructure). Throws CalibrationError, naming `what`, for fewer than 2 values,
  /// non-finite values or a confidence outside (0, 1).
  SampleStatistics describe(const std::vector<double> &values,
                            double confidence = 0.95,
                            const std::string &what = "");

  /// Thickness scaling of a macroscopic property of a homothetically scaled layer (Bobillier et al. 2020, reply
  /// to referee 1 comment 3 and its supplement): a sample of thickness h whose particles and
  /// positions are scaled by h/h_ref from the calibrated sample of thickness h_ref has, for the same
  /// particle properties, value(h) = value(h_ref) / (h_ref/h). Throws CalibrationError for a
  /// non-positive or non-finite thickness.
  double scale_to_thickness(double value_at_reference,
                            double thickness,
                            double reference_thickness);

  /// A micro-to-macro relation fitted at one layer thickness, usable at another: Bobillier et al. (2020)
  /// E_wl,macro = (beta_0 + beta_1 E_particle)/(h_ref/h) and
  /// sigma_wl,macro = (gamma_0 + gamma_1 sigma_bond)/(h_ref/h), with `fit` the line (beta_0, beta_1)
  /// or (gamma_0, gamma_1) of the calibrated sample and `reference_thickness` its thickness h_ref
  /// (Bobillier et al. 2020: 3 cm) [m].
  struct MicroMacroLaw
  {
    LinearFit fit;
    double reference_thickness = 0;  ///< h_ref [m]

    /// Macroscopic property of a layer of `thickness` [m] made of particles with property `micro`.
    [[nodiscard]] double predict(double micro, double thickness) const;
  };
} // namespace anticrack::params
