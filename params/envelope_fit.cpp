// Least-squares fits of failure envelopes with their uncertainty; see envelope_fit.h for the
// residuals, the goodness-of-fit measures and the two kinds of interval.
#include "params/envelope_fit.h"

#include "params/calibration_error.h"
#include "params/regression.h"

#include <Eigen/Eigenvalues>
#include <unsupported/Eigen/NonLinearOptimization>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>

namespace anticrack::params
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    constexpr double infinity = std::numeric_limits<double>::infinity();

    /// Smallest spread of polar angles that defines a shape rather than a single ray [rad].
    constexpr double minimum_angle_spread = 5 * pi / 180;

    /// Failure points in polar form: the controlled angle and the measured radius (and its logarithm,
    /// the coordinate the residuals are taken in).
    struct RadialData
    {
      std::vector<double> angle;
      Eigen::VectorXd radius;
      Eigen::VectorXd log_radius;
    };

    RadialData radial_data(const std::vector<StressPoint> &points)
    {
      RadialData data;
      data.radius.resize(points.size());
      for (std::size_t i = 0; i < points.size(); ++i)
      {
        data.angle.push_back(polar_angle(points[i]));
        data.radius[i] = polar_radius(points[i]);
      }
      data.log_radius = data.radius.array().log();
      return data;
    }

    Eigen::VectorXd envelope_radii(const YieldEnvelope &model, const std::vector<double> &angles,
                                   const Eigen::VectorXd &physical)
    {
      Eigen::VectorXd radii(angles.size());
      for (std::size_t i = 0; i < angles.size(); ++i)
        radii[i] = model.radius(angles[i], physical);
      return radii;
    }

    /// ln R(a_i) of the envelope: the fitted coordinate (relative residuals, see envelope_fit.h).
    Eigen::VectorXd envelope_log_radii(const YieldEnvelope &model, const std::vector<double> &angles,
                                       const Eigen::VectorXd &physical)
    {
      return envelope_radii(model, angles, physical).array().log();
    }

    /// dR(a_i)/dtheta_j in internal coordinates by central differences. The step h = 1e-5 max(1,
    /// |theta_j|) balances truncation (h^2 ~ 1e-10) against round-off (1e-16 / h ~ 1e-11), both relative
    /// to R; the internal coordinates are logarithms, logits or slopes of order one.
    Eigen::MatrixXd radius_jacobian(const YieldEnvelope &model, const std::vector<double> &angles,
                                    const Eigen::VectorXd &internal)
    {
      Eigen::MatrixXd jacobian(angles.size(), internal.size());
      for (Eigen::Index j = 0; j < internal.size(); ++j)
      {
        const double step = 1e-5 * std::max(1.0, std::abs(internal[j]));
        Eigen::VectorXd forward = internal, backward = internal;
        forward[j] += step;
        backward[j] -= step;
        jacobian.col(j) = (envelope_radii(model, angles, model.to_physical(forward)) -
                           envelope_radii(model, angles, model.to_physical(backward))) /
                          (2 * step);
      }
      return jacobian;
    }

    /// d ln R(a_i)/dtheta_j = (dR/dtheta_j) / R, the Jacobian of the relative residuals.
    Eigen::MatrixXd log_radius_jacobian(const YieldEnvelope &model, const std::vector<double> &angles,
                                        const Eigen::VectorXd &internal)
    {
      const Eigen::VectorXd radii = envelope_radii(model, angles, model.to_physical(internal));
      return radii.cwiseInverse().asDiagonal() * radius_jacobian(model, angles, internal);
    }

    /// The residuals ln R(a_i; theta) - ln r_i in the form Eigen's Levenberg-Marquardt expects (MINPACK's
    /// lmder: function values and Jacobian). Non-finite radii of a trial step (overflowing
    /// exponentials) make its norm non-finite, and lmder rejects such a step and shrinks its trust
    /// region, so they need no special treatment.
    struct RadialResiduals
    {
      const YieldEnvelope &model;
      const RadialData &data;

      int values() const { return static_cast<int>(data.angle.size()); }

      int operator()(const Eigen::VectorXd &internal, Eigen::VectorXd &residual) const
      {
        residual = envelope_log_radii(model, data.angle, model.to_physical(internal)) - data.log_radius;
        return 0;
      }

      int df(const Eigen::VectorXd &internal, Eigen::MatrixXd &jacobian) const
      {
        jacobian = log_radius_jacobian(model, data.angle, internal);
        return 0;
      }
    };

    struct LocalFit
    {
      Eigen::VectorXd internal;
      double ssr = 0;
    };

    /// One Levenberg-Marquardt run; a fit only if lmder stopped on one of its convergence tests (not on
    /// the evaluation limit or bad input) at a finite, admissible envelope.
    std::optional<LocalFit> minimise_from(const YieldEnvelope &model, const RadialData &data,
                                          const Eigen::VectorXd &internal_start, int max_evaluations)
    {
      RadialResiduals residuals{model, data};
      Eigen::LevenbergMarquardt<RadialResiduals> solver(residuals);
      solver.parameters.maxfev = max_evaluations;
      Eigen::VectorXd internal = internal_start;
      const Eigen::LevenbergMarquardtSpace::Status status = solver.minimize(internal);

      using namespace Eigen::LevenbergMarquardtSpace;
      const bool converged = status == RelativeReductionTooSmall || status == RelativeErrorTooSmall ||
                             status == RelativeErrorAndReductionTooSmall || status == CosinusTooSmall ||
                             status == FtolTooSmall || status == XtolTooSmall || status == GtolTooSmall;
      if (!converged || !internal.allFinite())
        return std::nullopt;
      const Eigen::VectorXd physical = model.to_physical(internal);
      if (!model.admissible(physical).admissible)
        return std::nullopt;
      const double ssr = (envelope_log_radii(model, data.angle, physical) - data.log_radius).squaredNorm();
      if (!std::isfinite(ssr))
        return std::nullopt;
      return LocalFit{internal, ssr};
    }

    /// Linearly interpolated percentile (Hyndman & Fan type 7) of a non-empty sample, probability in [0, 1].
    double percentile(std::vector<double> values, double probability)
    {
      std::sort(values.begin(), values.end());
      const double position = probability * static_cast<double>(values.size() - 1);
      const std::size_t below = static_cast<std::size_t>(std::floor(position));
      const std::size_t above = std::min(below + 1, values.size() - 1);
      return values[below] + (position - static_cast<double>(below)) * (values[above] - values[below]);
    }

    /// sum_kl a_k C_kl b_l over a_k != 0 and b_l != 0: a coordinate a quantity does not depend on at
    /// all (an exact zero, see YieldEnvelope::physical_jacobian) contributes nothing, even when its
    /// variance is infinite.
    double quadratic_form_skipping_zeros(const Eigen::VectorXd &a, const Eigen::MatrixXd &C, const Eigen::VectorXd &b)
    {
      double sum = 0;
      for (Eigen::Index k = 0; k < a.size(); ++k)
        for (Eigen::Index l = 0; l < b.size(); ++l)
          if (a[k] != 0 && b[l] != 0)
            sum += a[k] * C(k, l) * b[l];
      return sum;
    }

    /// True if physical parameter j is a function of internal coordinate j alone.
    bool depends_on_own_coordinate_only(const Eigen::MatrixXd &map_jacobian, Eigen::Index j)
    {
      for (Eigen::Index k = 0; k < map_jacobian.cols(); ++k)
        if (k != j && map_jacobian(j, k) != 0)
          return false;
      return true;
    }

    /// Covariance, delta-method covariance and Student-t intervals of the physical parameters.
    void add_covariance_intervals(const YieldEnvelope &model, const RadialData &data, EnvelopeFit &fit)
    {
      const Eigen::Index p = fit.internal_parameters.size();
      const Eigen::MatrixXd jacobian = log_radius_jacobian(model, data.angle, fit.internal_parameters);
      if (!jacobian.allFinite())
        throw CalibrationError(model.name() + ": the Jacobian of the residuals at the best fit is not finite");
      const LeastSquaresCovariance internal = least_squares_covariance(jacobian, fit.ssr);
      fit.internal_covariance = internal.covariance;
      fit.identifiable =
        std::find(internal.identifiable.begin(), internal.identifiable.end(), false) == internal.identifiable.end();

      const Eigen::MatrixXd map_jacobian = model.physical_jacobian(fit.internal_parameters);
      fit.covariance.resize(p, p);
      for (Eigen::Index i = 0; i < p; ++i)
        for (Eigen::Index j = 0; j < p; ++j)
          fit.covariance(i, j) = quadratic_form_skipping_zeros(map_jacobian.row(i).transpose(), internal.covariance,
                                                               map_jacobian.row(j).transpose());

      const double t = student_t_quantile((1 + fit.confidence) / 2, internal.degrees_of_freedom);
      fit.ci_lower.resize(p);
      fit.ci_upper.resize(p);
      for (Eigen::Index j = 0; j < p; ++j)
      {
        fit.ci_lower[j] = -infinity;
        fit.ci_upper[j] = infinity;
        if (depends_on_own_coordinate_only(map_jacobian, j))
        {
          if (!internal.identifiable[j])
            continue;
          // A monotone map of one coordinate: the interval's endpoints map to the endpoints.
          const double half_width = t * std::sqrt(internal.covariance(j, j));
          Eigen::VectorXd lower_end = fit.internal_parameters, upper_end = fit.internal_parameters;
          lower_end[j] -= half_width;
          upper_end[j] += half_width;
          const double a = model.to_physical(lower_end)[j], b = model.to_physical(upper_end)[j];
          fit.ci_lower[j] = std::min(a, b);
          fit.ci_upper[j] = std::max(a, b);
        }
        else
        {
          const double standard_deviation = std::sqrt(fit.covariance(j, j));
          if (!std::isfinite(standard_deviation))
            continue;
          fit.ci_lower[j] = fit.parameters[j] - t * standard_deviation;
          fit.ci_upper[j] = fit.parameters[j] + t * standard_deviation;
        }
      }
    }

    /// Resamples the groups with replacement and refits each resample from the best fit.
    void add_bootstrap(const YieldEnvelope &model, const std::vector<StressPoint> &points,
                       const std::vector<int> &groups, const EnvelopeFitOptions &options, EnvelopeFit &fit)
    {
      std::vector<int> ids = groups;
      std::sort(ids.begin(), ids.end());
      ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
      if (options.bootstrap_samples == 0 || ids.size() < 3)
        return;

      std::vector<std::vector<std::size_t>> members(ids.size());
      for (std::size_t i = 0; i < points.size(); ++i)
        members[std::lower_bound(ids.begin(), ids.end(), groups[i]) - ids.begin()].push_back(i);

      std::mt19937_64 generator(options.seed);
      std::uniform_int_distribution<std::size_t> pick(0, ids.size() - 1);
      const std::size_t p = model.n_parameters();
      std::vector<Eigen::VectorXd> samples;
      for (int b = 0; b < options.bootstrap_samples; ++b)
      {
        // Every draw is made before anything can fail, so resample b is the same whatever happened to
        // the earlier ones.
        std::vector<StressPoint> resample;
        for (std::size_t g = 0; g < ids.size(); ++g)
          for (const std::size_t i : members[pick(generator)])
            resample.push_back(points[i]);
        try
        {
          check_envelope_data(resample, p, options.data_set + ", bootstrap resample");
        }
        catch (const CalibrationError &)
        {
          ++fit.bootstrap_failures;
          continue;
        }
        const std::optional<LocalFit> refit =
          minimise_from(model, radial_data(resample), fit.internal_parameters, options.max_iterations);
        if (!refit)
        {
          ++fit.bootstrap_failures;
          continue;
        }
        samples.push_back(model.to_physical(refit->internal));
      }
      if (samples.size() < 2)
        return;

      fit.has_bootstrap = true;
      fit.bootstrap_samples.resize(samples.size(), p);
      for (std::size_t s = 0; s < samples.size(); ++s)
        fit.bootstrap_samples.row(s) = samples[s].transpose();
      fit.bootstrap_lower.resize(p);
      fit.bootstrap_upper.resize(p);
      for (std::size_t j = 0; j < p; ++j)
      {
        const Eigen::VectorXd column = fit.bootstrap_samples.col(j);
        const std::vector<double> values(column.data(), column.data() + column.size());
        fit.bootstrap_lower[j] = percentile(values, (1 - fit.confidence) / 2);
        fit.bootstrap_upper[j] = percentile(values, (1 + fit.confidence) / 2);
      }
    }

    void check_options(const YieldEnvelope &model, const std::vector<StressPoint> &points,
                       const std::vector<int> &groups, const EnvelopeFitOptions &options)
    {
      if (!groups.empty() && groups.size() != points.size())
        throw std::invalid_argument("fit_envelope: " + std::to_string(groups.size()) + " group ids for " +
                                    std::to_string(points.size()) + " points (give one per point or none)");
      if (!(options.confidence > 0 && options.confidence < 1))
        throw std::invalid_argument("fit_envelope: confidence = " + std::to_string(options.confidence) +
                                    " must be in (0, 1)");
      if (options.bootstrap_samples < 0 || options.max_iterations <= 0)
        throw std::invalid_argument("fit_envelope: bootstrap_samples must be >= 0 and max_iterations > 0");
      if (!options.use_model_guesses && options.extra_initial_guesses.empty())
        throw std::invalid_argument("fit_envelope: no starting point (use_model_guesses is false and "
                                    "extra_initial_guesses is empty)");
      for (const Eigen::VectorXd &guess : options.extra_initial_guesses)
      {
        if (guess.size() != static_cast<Eigen::Index>(model.n_parameters()))
          throw std::invalid_argument("fit_envelope: an extra initial guess has " + std::to_string(guess.size()) +
                                      " entries, " + model.name() + " has " +
                                      std::to_string(model.n_parameters()) + " parameters");
        if (const Admissibility check = model.admissible(guess); !check.admissible)
          throw CalibrationError(options.data_set + ": extra initial guess for " + model.name() +
                                 " is not admissible: " + check.reason);
      }
    }
  } // namespace

  void check_envelope_data(const std::vector<StressPoint> &points, std::size_t n_parameters, const std::string &what)
  {
    std::ostringstream msg;
    msg << what << ": ";
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!std::isfinite(points[i].normal) || !std::isfinite(points[i].shear))
      {
        msg << "failure point " << i << " is not finite (normal = " << points[i].normal
            << " Pa, shear = " << points[i].shear << " Pa); every point must be a finite stress";
        throw CalibrationError(msg.str());
      }
    if (points.size() < n_parameters + 1)
    {
      msg << points.size() << " failure points for an envelope with " << n_parameters << " parameters; at least "
          << n_parameters + 1 << " are needed (one more than the parameters, for the residual variance)";
      throw CalibrationError(msg.str());
    }
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      if (points[i].shear < 0)
      {
        msg << "failure point " << i << " has negative shear " << points[i].shear
            << " Pa; the shear coordinate must be >= 0 (|tau| or q)";
        throw CalibrationError(msg.str());
      }
      if (polar_radius(points[i]) == 0)
      {
        msg << "failure point " << i << " is at the origin (zero stress), which has no loading angle";
        throw CalibrationError(msg.str());
      }
    }
    const RadialData data = radial_data(points);
    const auto [smallest, largest] = std::minmax_element(data.angle.begin(), data.angle.end());
    if (*largest - *smallest < minimum_angle_spread)
    {
      msg << "the " << points.size() << " failure points span polar angles from " << *smallest * 180 / pi
          << " to " << *largest * 180 / pi << " degrees, all on one ray; loading angles spread over at least "
          << minimum_angle_spread * 180 / pi << " degrees are needed to fit an envelope";
      throw CalibrationError(msg.str());
    }
    if (std::none_of(points.begin(), points.end(), [](const StressPoint &point) { return point.normal < 0; }))
    {
      msg << "none of the " << points.size() << " failure points has a tensile normal stress (normal < 0); "
          << "the tensile tip of the envelope would be an extrapolation: add tests loaded in tension";
      throw CalibrationError(msg.str());
    }
  }

  InformationCriteria information_criteria(double ssr, std::size_t n_points, std::size_t n_parameters)
  {
    const double n = static_cast<double>(n_points);
    const double k = static_cast<double>(n_parameters + 1);
    const double log_likelihood_term = n * std::log(ssr / n);
    InformationCriteria criteria;
    criteria.aic = log_likelihood_term + 2 * k;
    criteria.aicc = n - k - 1 > 0 ? criteria.aic + 2 * k * (k + 1) / (n - k - 1) : infinity;
    criteria.bic = log_likelihood_term + k * std::log(n);
    return criteria;
  }

  LeastSquaresCovariance least_squares_covariance(const Eigen::MatrixXd &jacobian, double ssr)
  {
    const Eigen::Index m = jacobian.rows(), p = jacobian.cols();
    if (m <= p || p == 0)
      throw std::invalid_argument("least_squares_covariance: a Jacobian of " + std::to_string(m) + " x " +
                                  std::to_string(p) + " (more residuals than parameters are needed)");
    if (!jacobian.allFinite() || !(ssr >= 0))
      throw std::invalid_argument("least_squares_covariance: non-finite Jacobian or negative SSR");

    LeastSquaresCovariance result;
    result.degrees_of_freedom = static_cast<int>(m - p);
    result.residual_variance = ssr / static_cast<double>(m - p);
    result.identifiable.assign(p, true);

    // Rank on the column-scaled normal matrix, so that the units of the coordinates do not matter. A
    // column of zeros (a coordinate no residual depends on) gets scale 0 and is unidentifiable.
    const Eigen::MatrixXd normal_matrix = jacobian.transpose() * jacobian;
    Eigen::VectorXd inverse_scale(p);
    for (Eigen::Index j = 0; j < p; ++j)
    {
      const double scale = std::sqrt(normal_matrix(j, j));
      inverse_scale[j] = scale > 0 ? 1 / scale : 0;
      if (!(scale > 0))
        result.identifiable[j] = false;
    }
    const Eigen::MatrixXd scaled = inverse_scale.asDiagonal() * normal_matrix * inverse_scale.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled);
    const double largest = eigen.eigenvalues().maxCoeff();
    Eigen::MatrixXd scaled_inverse = Eigen::MatrixXd::Zero(p, p);
    for (Eigen::Index k = 0; k < p; ++k)
    {
      const Eigen::VectorXd direction = eigen.eigenvectors().col(k);
      if (eigen.eigenvalues()[k] > 1e-10 * largest)
        scaled_inverse += direction * direction.transpose() / eigen.eigenvalues()[k];
      else
        for (Eigen::Index j = 0; j < p; ++j)
          if (std::abs(direction[j]) > 1e-5)
            result.identifiable[j] = false;
    }

    result.covariance =
      result.residual_variance * inverse_scale.asDiagonal() * scaled_inverse * inverse_scale.asDiagonal();
    for (Eigen::Index j = 0; j < p; ++j)
      if (!result.identifiable[j])
      {
        result.covariance.row(j).setConstant(std::numeric_limits<double>::quiet_NaN());
        result.covariance.col(j).setConstant(std::numeric_limits<double>::quiet_NaN());
        result.covariance(j, j) = infinity;
      }
    return result;
  }

  EnvelopeFit fit_envelope(const YieldEnvelope &model, const std::vector<StressPoint> &points,
                           const std::vector<int> &groups, const EnvelopeFitOptions &options)
  {
    check_options(model, points, groups, options);
    check_envelope_data(points, model.n_parameters(), options.data_set);
    const RadialData data = radial_data(points);

    std::vector<Eigen::VectorXd> starts;
    if (options.use_model_guesses)
      starts = model.initial_guesses(points);
    starts.insert(starts.end(), options.extra_initial_guesses.begin(), options.extra_initial_guesses.end());

    std::vector<LocalFit> converged;
    for (const Eigen::VectorXd &start : starts)
      if (std::optional<LocalFit> local = minimise_from(model, data, model.to_internal(start), options.max_iterations))
        converged.push_back(*local);
    if (converged.empty())
    {
      std::ostringstream msg;
      msg << options.data_set << ": none of the " << starts.size() << " starting points of the " << model.name()
          << " fit converged to a finite, admissible envelope (limit " << options.max_iterations
          << " evaluations per start)";
      throw CalibrationError(msg.str());
    }
    const LocalFit &best = *std::min_element(converged.begin(), converged.end(),
                                             [](const LocalFit &a, const LocalFit &b) { return a.ssr < b.ssr; });

    EnvelopeFit fit;
    fit.model = model.name();
    fit.parameter_names = model.parameter_names();
    fit.parameter_units = model.parameter_units();
    fit.internal_parameters = best.internal;
    fit.parameters = model.to_physical(best.internal);
    fit.confidence = options.confidence;
    fit.n_points = points.size();
    fit.starts = static_cast<int>(starts.size());
    // "Within 1e-8 relative" of the lowest SSR; for data on the envelope (SSR at round-off level) the
    // scale is machine precision times the squared radii.
    const double tolerance =
      1e-8 * (best.ssr + std::numeric_limits<double>::epsilon() * data.log_radius.squaredNorm());
    fit.starts_at_best = static_cast<int>(std::count_if(
      converged.begin(), converged.end(), [&](const LocalFit &local) { return local.ssr - best.ssr <= tolerance; }));

    fit.residuals = data.log_radius - envelope_log_radii(model, data.angle, fit.parameters);
    fit.ssr = fit.residuals.squaredNorm();
    fit.sst = (data.log_radius.array() - data.log_radius.mean()).square().sum();
    fit.r_squared = fit.sst > 0 ? 1 - fit.ssr / fit.sst : std::numeric_limits<double>::quiet_NaN();
    fit.rmse = std::sqrt(fit.ssr / static_cast<double>(fit.n_points));
    const InformationCriteria criteria = information_criteria(fit.ssr, fit.n_points, model.n_parameters());
    fit.aic = criteria.aic;
    fit.aicc = criteria.aicc;
    fit.bic = criteria.bic;

    add_covariance_intervals(model, data, fit);
    add_bootstrap(model, points, groups, options, fit);
    return fit;
  }

  EnvelopeBand envelope_band(const YieldEnvelope &model, const EnvelopeFit &fit, int n_angles, bool from_bootstrap)
  {
    if (fit.model != model.name())
      throw std::invalid_argument("envelope_band: a fit of " + fit.model + " with the model " + model.name());
    if (n_angles < 2)
      throw std::invalid_argument("envelope_band: n_angles = " + std::to_string(n_angles) + " must be >= 2");

    EnvelopeBand band;
    band.from_bootstrap = from_bootstrap && fit.has_bootstrap;
    for (int i = 0; i < n_angles; ++i)
      band.angle.push_back(pi * i / (n_angles - 1));
    const Eigen::VectorXd radius = envelope_radii(model, band.angle, fit.parameters);
    band.radius.assign(radius.data(), radius.data() + radius.size());

    if (band.from_bootstrap)
    {
      std::vector<Eigen::VectorXd> sample_radii;
      for (Eigen::Index s = 0; s < fit.bootstrap_samples.rows(); ++s)
        sample_radii.push_back(envelope_radii(model, band.angle, fit.bootstrap_samples.row(s).transpose()));
      for (int i = 0; i < n_angles; ++i)
      {
        std::vector<double> values;
        for (const Eigen::VectorXd &radii : sample_radii)
          values.push_back(radii[i]);
        band.lower.push_back(percentile(values, (1 - fit.confidence) / 2));
        band.upper.push_back(percentile(values, (1 + fit.confidence) / 2));
      }
      return band;
    }

    const Eigen::MatrixXd gradient = radius_jacobian(model, band.angle, fit.internal_parameters);
    const double t = student_t_quantile((1 + fit.confidence) / 2,
                                        static_cast<double>(fit.n_points - model.n_parameters()));
    for (int i = 0; i < n_angles; ++i)
    {
      const Eigen::VectorXd g = gradient.row(i).transpose();
      const double standard_deviation = std::sqrt(quadratic_form_skipping_zeros(g, fit.internal_covariance, g));
      if (!std::isfinite(standard_deviation))
      {
        band.lower.push_back(0);
        band.upper.push_back(infinity);
        continue;
      }
      band.lower.push_back(std::max(0.0, band.radius[i] - t * standard_deviation));
      band.upper.push_back(band.radius[i] + t * standard_deviation);
    }
    return band;
  }
} // namespace anticrack::params
