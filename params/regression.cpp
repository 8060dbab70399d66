// Least-squares lines, power laws and sample statistics with t-intervals (see regression.h).
#include "params/regression.h"

#include "params/calibration_error.h"

#include <Eigen/Core>
#include <boost/math/distributions/students_t.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace anticrack::params
{
  namespace
  {
    /// Name of the data set in messages.
    std::string label(const std::string &what)
    {
      return what.empty() ? std::string("data") : what;
    }

    /// One y per x, or a CalibrationError naming the data set and the model.
    void check_same_length(const std::vector<double> &x, const std::vector<double> &y, const std::string &what,
                           const std::string &model)
    {
      if (x.size() == y.size())
        return;
      std::ostringstream message;
      message << label(what) << ": " << x.size() << " x values but " << y.size() << " y values; " << model
              << " needs one y per x";
      throw CalibrationError(message.str());
    }

    void check_confidence(double confidence, const std::string &what)
    {
      if (!(confidence > 0 && confidence < 1))
        {
          std::ostringstream message;
          message << label(what) << ": confidence level " << confidence
                  << " is not in (0, 1); use e.g. 0.95 for a 95 % interval";
          throw CalibrationError(message.str());
        }
    }

    void check_finite(const std::vector<double> &values, const char *name, const std::string &what)
    {
      for (std::size_t i = 0; i < values.size(); ++i)
        if (!std::isfinite(values[i]))
          {
            std::ostringstream message;
            message << label(what) << ": " << name << "[" << i << "] = " << values[i]
                    << " is not finite; every value must be a finite number";
            throw CalibrationError(message.str());
          }
    }

    /// Two-sided t multiplier: the half-width of an interval of `confidence` is this times the
    /// standard error.
    double two_sided_t(double confidence, double degrees_of_freedom)
    {
      return student_t_quantile(0.5 * (1 + confidence), degrees_of_freedom);
    }

    Interval symmetric_interval(double centre, double half_width)
    {
      return Interval{centre - half_width, centre + half_width};
    }

    /// 1 - SSR/SST, NaN when SST = 0 (no variation to explain).
    double coefficient_of_determination(double residual_sum_of_squares, double total_sum_of_squares)
    {
      if (!(total_sum_of_squares > 0))
        return std::numeric_limits<double>::quiet_NaN();
      return 1 - residual_sum_of_squares / total_sum_of_squares;
    }

    Eigen::Map<const Eigen::ArrayXd> as_array(const std::vector<double> &values)
    {
      return Eigen::Map<const Eigen::ArrayXd>(values.data(), static_cast<Eigen::Index>(values.size()));
    }
  } // namespace

  double student_t_quantile(double probability, double degrees_of_freedom)
  {
    if (!(probability > 0 && probability < 1))
      {
        std::ostringstream message;
        message << "Student t quantile: probability " << probability << " is not in (0, 1)";
        throw CalibrationError(message.str());
      }
    if (!(degrees_of_freedom > 0) || !std::isfinite(degrees_of_freedom))
      {
        std::ostringstream message;
        message << "Student t quantile: " << degrees_of_freedom
                << " degrees of freedom; need a positive finite number (more points than parameters)";
        throw CalibrationError(message.str());
      }
    const boost::math::students_t distribution(degrees_of_freedom);
    return boost::math::quantile(distribution, probability);
  }

  // Ordinary least squares in centred form: with x_c = x - mean(x),
  //   slope = sum x_c y / Sxx, Sxx = sum x_c^2,   intercept = mean(y) - slope mean(x),
  // residual variance s^2 = SSR/(n - 2), var(slope) = s^2/Sxx,
  // var(intercept) = s^2 (1/n + mean(x)^2/Sxx), cov = -mean(x) s^2/Sxx.
  // Centring avoids the cancellation of the raw normal equations when x is large (E_particle ~ 1e8).
  LinearFit fit_line(const std::vector<double> &x,
                     const std::vector<double> &y,
                     double confidence,
                     const std::string &what)
  {
    check_same_length(x, y, what, "a line");
    if (x.size() < 3)
      {
        std::ostringstream message;
        message << label(what) << ": " << x.size()
                << " points for a straight-line fit; need at least 3 (two parameters and one degree "
                   "of freedom for the standard errors)";
        throw CalibrationError(message.str());
      }
    check_finite(x, "x", what);
    check_finite(y, "y", what);
    check_confidence(confidence, what);
    if (std::all_of(x.begin(), x.end(), [&](double value) { return value == x.front(); }))
      {
        std::ostringstream message;
        message << label(what) << ": all " << x.size() << " x values equal " << x.front()
                << "; the slope needs at least 2 distinct x";
        throw CalibrationError(message.str());
      }

    const auto x_values = as_array(x);
    const auto y_values = as_array(y);
    const double n = static_cast<double>(x.size());

    const double x_mean = x_values.mean();
    const double y_mean = y_values.mean();
    const Eigen::ArrayXd x_centred = x_values - x_mean;
    const Eigen::ArrayXd y_centred = y_values - y_mean;
    const double sxx = x_centred.square().sum();

    LinearFit fit;
    fit.n = static_cast<int>(x.size());
    fit.confidence = confidence;
    fit.slope = (x_centred * y_centred).sum() / sxx;
    fit.intercept = y_mean - fit.slope * x_mean;

    // Residuals from the centred form, so that SSR is not a difference of large sums.
    const Eigen::ArrayXd residuals = y_centred - fit.slope * x_centred;
    const double ssr = residuals.square().sum();
    const double sst = y_centred.square().sum();
    const double degrees_of_freedom = n - 2;
    const double residual_variance = ssr / degrees_of_freedom;

    fit.residual_standard_deviation = std::sqrt(residual_variance);
    fit.slope_standard_error = std::sqrt(residual_variance / sxx);
    fit.intercept_standard_error = std::sqrt(residual_variance * (1 / n + x_mean * x_mean / sxx));
    fit.intercept_slope_covariance = -x_mean * residual_variance / sxx;
    fit.r_squared = coefficient_of_determination(ssr, sst);

    const double t = two_sided_t(confidence, degrees_of_freedom);
    fit.slope_ci = symmetric_interval(fit.slope, t * fit.slope_standard_error);
    fit.intercept_ci = symmetric_interval(fit.intercept, t * fit.intercept_standard_error);
    return fit;
  }

  double PowerLawFit::operator()(double x) const
  {
    return prefactor * std::pow(x, exponent);
  }

  // Eqs. (2)-(3) of Ritter et al. (2020): y = prefactor x^exponent  <=>  ln y = ln(prefactor) + exponent ln x.
  // The exponent's interval is the slope's t-interval; the prefactor's is exp of the intercept's,
  // which is asymmetric (a symmetric error in ln(prefactor) is a factor, not a difference).
  PowerLawFit fit_power_law(const std::vector<double> &x,
                            const std::vector<double> &y,
                            double confidence,
                            const std::string &what)
  {
    check_same_length(x, y, what, "a power law");
    check_finite(x, "x", what);
    check_finite(y, "y", what);
    for (std::size_t i = 0; i < x.size(); ++i)
      {
        if (!(x[i] > 0) || !(y[i] > 0))
          {
            std::ostringstream message;
            message << label(what) << ": point " << i << " has x = " << x[i] << ", y = " << y[i]
                    << "; a power-law fit (in log space) needs x > 0 and y > 0";
            throw CalibrationError(message.str());
          }
      }

    std::vector<double> log_x(x.size());
    std::vector<double> log_y(y.size());
    std::transform(x.begin(), x.end(), log_x.begin(), [](double value) { return std::log(value); });
    std::transform(y.begin(), y.end(), log_y.begin(), [](double value) { return std::log(value); });

    PowerLawFit fit;
    fit.log_fit = fit_line(log_x, log_y, confidence, label(what) + " (log-log)");
    fit.n = fit.log_fit.n;
    fit.confidence = confidence;
    fit.exponent = fit.log_fit.slope;
    fit.prefactor = std::exp(fit.log_fit.intercept);
    fit.exponent_standard_error = fit.log_fit.slope_standard_error;
    fit.log_prefactor_standard_error = fit.log_fit.intercept_standard_error;
    fit.exponent_ci = fit.log_fit.slope_ci;
    fit.prefactor_ci = Interval{std::exp(fit.log_fit.intercept_ci.lower),
                                std::exp(fit.log_fit.intercept_ci.upper)};
    fit.r_squared_log = fit.log_fit.r_squared;

    const auto y_values = as_array(y);
    double ssr = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
      {
        const double residual = y[i] - fit(x[i]);
        ssr += residual * residual;
      }
    const double sst = (y_values - y_values.mean()).square().sum();
    fit.r_squared = coefficient_of_determination(ssr, sst);
    return fit;
  }

  SampleStatistics describe(const std::vector<double> &values,
                            double confidence,
                            const std::string &what)
  {
    if (values.size() < 2)
      {
        std::ostringstream message;
        message << label(what) << ": " << values.size()
                << " values; a standard deviation and an interval of the mean need at least 2";
        throw CalibrationError(message.str());
      }
    check_finite(values, "value", what);
    check_confidence(confidence, what);

    const auto sample = as_array(values);
    const double n = static_cast<double>(values.size());

    SampleStatistics statistics;
    statistics.n = static_cast<int>(values.size());
    statistics.confidence = confidence;
    statistics.mean = sample.mean();
    statistics.minimum = sample.minCoeff();
    statistics.maximum = sample.maxCoeff();
    statistics.standard_deviation =
      std::sqrt((sample - statistics.mean).square().sum() / (n - 1));
    const double standard_error = statistics.standard_deviation / std::sqrt(n);
    statistics.mean_ci =
      symmetric_interval(statistics.mean, two_sided_t(confidence, n - 1) * standard_error);
    statistics.values = values;
    return statistics;
  }

  double covariance_of_means(const std::vector<double> &a, const std::vector<double> &b)
  {
    if (a.size() != b.size() || a.size() < 2)
      throw CalibrationError("covariance of two means: samples of " + std::to_string(a.size()) + " and " +
                             std::to_string(b.size()) + " values; it needs at least 2 pairs");
    const auto x = as_array(a), y = as_array(b);
    const double n = static_cast<double>(a.size());
    return ((x - x.mean()) * (y - y.mean())).sum() / ((n - 1) * n);
  }

  // Bobillier et al. 2020 (reply to referee 1, comment 3): X_macro(h) = X_macro(h_ref) / (h_ref/h).
  double scale_to_thickness(double value_at_reference,
                            double thickness,
                            double reference_thickness)
  {
    if (!(thickness > 0) || !std::isfinite(thickness))
      {
        std::ostringstream message;
        message << "thickness scaling: layer thickness " << thickness
                << " m; need a positive finite thickness";
        throw CalibrationError(message.str());
      }
    if (!(reference_thickness > 0) || !std::isfinite(reference_thickness))
      {
        std::ostringstream message;
        message << "thickness scaling: reference thickness " << reference_thickness
                << " m; need the positive thickness of the calibrated sample";
        throw CalibrationError(message.str());
      }
    return value_at_reference / (reference_thickness / thickness);
  }

  double MicroMacroLaw::predict(double micro, double thickness) const
  {
    return scale_to_thickness(fit(micro), thickness, reference_thickness);
  }
} // namespace anticrack::params
