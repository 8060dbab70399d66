// Flow-rule analysis in the mixed-mode plane (Ritter et al. 2020, Eqs. 1, 4-7, 12-19; see flow_rule.h).
#include "params/flow_rule.h"

#include "params/calibration_error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

namespace anticrack::params
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    constexpr double degrees_per_radian = 180.0 / pi;

    /// Absolute allowance for round-off when asking whether 1 or -pi/2 lies in an interval of an
    /// O(1) angle or slope: exact associative data give intervals of zero width whose centre is off
    /// by ~1e-15, and no measured interval is narrower than 1e-12.
    constexpr double round_off_allowance = 1e-12;

    /// Loading angles closer than this [rad] are the same nominal angle.
    constexpr double same_loading_angle = 1e-9;

    void check_parameters(const CamClaySurface &parameters)
    {
      std::ostringstream problem;
      if (!(parameters.p0 > 0) || !std::isfinite(parameters.p0))
        problem << "p0 = " << parameters.p0 << " (need a positive finite compressive strength)";
      else if (!(parameters.beta >= 0) || !std::isfinite(parameters.beta))
        problem << "beta = " << parameters.beta << " (need a finite beta >= 0)";
      else if (!(parameters.M > 0) || !std::isfinite(parameters.M))
        problem << "M = " << parameters.M << " (need a positive finite slope M)";
      else
        return;
      throw CalibrationError("Cam-Clay parameters of the flow-rule analysis: " + problem.str());
    }

    void check_loading_angle(double psi)
    {
      if (!(psi >= 0 && psi <= pi))
        {
          std::ostringstream message;
          message << "loading angle psi = " << psi << " rad (" << psi * degrees_per_radian
                  << " deg) is outside [0, pi] (0 compression, pi/2 shear, pi tension)";
          throw CalibrationError(message.str());
        }
    }

    /// sqrt(1 + 2 beta), the factor between the cohesive and the cohesionless critical state
    /// line (Ritter et al. 2020, Discussion: M' = M/sqrt(1 + 2 beta)).
    double cohesion_factor(const CamClaySurface &parameters)
    {
      return std::sqrt(1 + 2 * parameters.beta);
    }

    /// Wraps an angle difference to [-pi, pi]: a deviation between two directions.
    double wrapped_angle(double angle)
    {
      return std::remainder(angle, 2 * pi);
    }

    void check_same_size_and_finite(const std::vector<double> &first,
                                    const char *first_name,
                                    const std::vector<double> &second,
                                    const char *second_name,
                                    const std::string &what)
    {
      if (first.size() != second.size())
        {
          std::ostringstream message;
          message << what << ": " << first.size() << " values of " << first_name << " but "
                  << second.size() << " of " << second_name << "; need one per failure point";
          throw CalibrationError(message.str());
        }
      for (const auto &[values, name] :
           {std::pair{&first, first_name}, std::pair{&second, second_name}})
        for (std::size_t i = 0; i < values->size(); ++i)
          if (!std::isfinite((*values)[i]))
            {
              std::ostringstream message;
              message << what << ": " << name << "[" << i << "] = " << (*values)[i]
                      << " is not finite; every angle must be a finite number";
              throw CalibrationError(message.str());
            }
    }
  } // namespace

  // Eqs. 5-6 of Ritter et al. (2020): the affine map that sends the ellipse of Eq. 1 to the unit circle (Eq. 4):
  // centre (1 - beta) p0/2 -> 0, semi-axis (1 + beta) p0/2 -> 1 along sigma, and the apex height
  // M (1 + beta) p0/(2 sqrt(1 + 2 beta)) -> 1 along tau.
  NormalisedStress normalise(double sigma, double tau, const CamClaySurface &parameters)
  {
    check_parameters(parameters);
    const double p0 = parameters.p0;
    const double beta = parameters.beta;
    NormalisedStress normalised;
    normalised.sigma = (2 * sigma - (1 - beta) * p0) / ((1 + beta) * p0);
    normalised.tau = 2 * tau * cohesion_factor(parameters) / (parameters.M * (1 + beta) * p0);
    return normalised;
  }

  // The ray r (cos psi, sin psi) in Eq. 1 multiplied by 1/M^2:
  //   Q r^2 - 2 B r + C = 0,  Q = cos^2 psi + (1 + 2 beta)/M^2 sin^2 psi,
  //   B = cos psi (1 - beta) p0/2,  C = -beta p0^2 = (sigma_c^2 - a^2) with centre sigma_c and
  //   semi-axis a of the ellipse.
  // C <= 0 (the origin is inside the surface, or on it for beta = 0), so there is exactly one root
  // r >= 0; it is evaluated in the form that avoids cancellation for either sign of B.
  StressPoint surface_point_on_loading_ray(double psi, const CamClaySurface &parameters)
  {
    check_parameters(parameters);
    check_loading_angle(psi);
    // The loading ray (cos psi, sin psi) in (sigma, tau) meets the surface at the envelope's radius.
    const double r = cam_clay_radius(psi, parameters.p0, parameters.beta, parameters.M);
    return StressPoint{r * std::cos(psi), r * std::sin(psi)};
  }

  // psi* = atan2(tau*, sigma*) of the intersection: the quadrant is that of the point itself, so
  // psi* is right beyond the apex (psi* > pi/2), where Eq. 14 of Ritter et al. (2020) would return the mirror image.
  double normalised_loading_angle(double psi, const CamClaySurface &parameters)
  {
    const StressPoint point = surface_point_on_loading_ray(psi, parameters);
    const NormalisedStress normalised = normalise(point.normal, point.shear, parameters);
    return std::atan2(normalised.tau, normalised.sigma);
  }

  // Eq. 19 of Ritter et al. (2020), mu* = k (1 + d sqrt(1 + mu*^2)) with k = (mu/M) sqrt(1 + 2 beta),
  // d = (1 - beta)/(1 + beta): the loading ray is the line tau* = k (sigma* + d) through the
  // image (-d, 0) of the origin, and Eq. 14 puts the point on the circle at sigma* > 0.
  // Squaring gives (1 - k^2 d^2) mu*^2 - 2 k mu* + k^2 (1 - d^2) = 0 with the roots
  //   A = k (1 + d S)/(1 - k^2 d^2) = k (1 - d^2)/(1 - d S),
  //   B = k (1 - d S)/(1 - k^2 d^2) = k (1 - d^2)/(1 + d S),   S = sqrt(1 + k^2 (1 - d^2)).
  // Inserting them in the unsquared equation, sqrt(1 + mu*^2) = (mu* - k)/(k d) is
  // (S - d)/(1 - d S) for A and -(S + d)/(1 + d S) for B, and S >= 1 >= |d|. Hence
  //   mu >= 0: A, valid while 1 - d S > 0, i.e. k d < 1 (below the transition angle; always for
  //            beta >= 1, where d <= 0);
  //   mu < 0 (psi > pi/2): B, valid while 1 + d S < 0, i.e. beta > 1 and k d > 1 (between pi/2
  //            and the obtuse transition angle); the other root is the lower half of the circle.
  // Each root is evaluated in the form without cancellation.
  double normalised_loading_slope_eq19(double mu, const CamClaySurface &parameters)
  {
    check_parameters(parameters);
    if (!std::isfinite(mu))
      {
        std::ostringstream message;
        message << "Eq. 19: loading slope mu = " << mu << " is not finite";
        throw CalibrationError(message.str());
      }
    const double beta = parameters.beta;
    const double k = mu / parameters.M * cohesion_factor(parameters);
    const double d = (1 - beta) / (1 + beta);
    const double one_minus_d_squared = 4 * beta / ((1 + beta) * (1 + beta));
    const double s = std::sqrt(1 + k * k * one_minus_d_squared);

    auto beyond_transition = [&]() {
      std::ostringstream message;
      message << "Eq. 19: the loading ray with slope mu = " << mu << " (psi = "
              << std::atan2(mu >= 0 ? mu : -mu, mu >= 0 ? 1.0 : -1.0) * degrees_per_radian
              << " deg) meets the surface at sigma* <= 0, beyond the transition angle "
              << transition_loading_angle(parameters) * degrees_per_radian
              << " deg; Eq. 19 holds on the branch sigma* > 0 only (use normalised_loading_angle)";
      return CalibrationError(message.str());
    };

    if (mu >= 0)
      {
        if (d > 0)
          {
            if (!(k * d < 1))
              throw beyond_transition();
            return k * (1 + d * s) / ((1 - k * d) * (1 + k * d));
          }
        return k * one_minus_d_squared / (1 - d * s);
      }
    if (!(1 + d * s < 0))
      throw beyond_transition();
    return k * one_minus_d_squared / (1 + d * s);
  }

  // Eq. 18 of Ritter et al. (2020) with the quadrant kept: tan theta* = (sqrt(1 + 2 beta)/M) tan theta is the
  // same direction as (M cos theta, sqrt(1 + 2 beta) sin theta), both components scaled by
  // positive factors.
  double normalised_flow_angle(double theta, const CamClaySurface &parameters)
  {
    check_parameters(parameters);
    return std::atan2(cohesion_factor(parameters) * std::sin(theta),
                      parameters.M * std::cos(theta));
  }

  double flow_angle_from_normalised(double theta_star, const CamClaySurface &parameters)
  {
    check_parameters(parameters);
    return std::atan2(parameters.M * std::sin(theta_star),
                      cohesion_factor(parameters) * std::cos(theta_star));
  }

  // Eq. 16 of Ritter et al. (2020): the outward normal of the unit circle at psi* is (cos psi*, sin psi*) =
  // (-du_z*, du_x*), so theta* = atan2(du_z*, du_x*) = psi* - pi/2.
  double associative_normalised_flow_angle(double psi_star)
  {
    return psi_star - pi / 2;
  }

  double associative_flow_angle(double psi, const CamClaySurface &parameters)
  {
    const double psi_star = normalised_loading_angle(psi, parameters);
    return flow_angle_from_normalised(associative_normalised_flow_angle(psi_star), parameters);
  }

  // Eq. 7 of Ritter et al. (2020): the apex (sigma, tau) = ((1 - beta) p0/2, M (1 + beta) p0/(2 sqrt(1 + 2 beta)))
  // seen from the origin; atan2 gives the obtuse angle when the apex is on the tensile side (beta > 1).
  double transition_loading_angle(const CamClaySurface &parameters)
  {
    check_parameters(parameters);
    const double beta = parameters.beta;
    return std::atan2(parameters.M * (1 + beta), (1 - beta) * cohesion_factor(parameters));
  }

  AssociativityMeasure measure_associativity(const std::vector<double> &psi_star,
                                             const std::vector<double> &theta_star,
                                             double confidence)
  {
    const std::string what = "associativity of the flow (theta* against psi*)";
    check_same_size_and_finite(psi_star, "psi*", theta_star, "theta*", what);
    if (psi_star.size() < 3)
      {
        std::ostringstream message;
        message << what << ": " << psi_star.size()
                << " failure points; need at least 3 (a line and its intervals)";
        throw CalibrationError(message.str());
      }

    AssociativityMeasure measure;
    measure.n = static_cast<int>(psi_star.size());
    measure.confidence = confidence;
    measure.line = fit_line(psi_star, theta_star, confidence, what);

    // Deviations from Ritter et al. (2020), Eq. 16.
    measure.deviation.resize(psi_star.size());
    double sum_of_squares = 0;
    for (std::size_t i = 0; i < psi_star.size(); ++i)
      {
        const double deviation =
          wrapped_angle(theta_star[i] - associative_normalised_flow_angle(psi_star[i]));
        measure.deviation[i] = deviation;
        sum_of_squares += deviation * deviation;
        measure.max_abs_deviation = std::max(measure.max_abs_deviation, std::abs(deviation));
      }
    measure.rms_deviation = std::sqrt(sum_of_squares / measure.n);
    measure.rms_deviation_deg = measure.rms_deviation * degrees_per_radian;
    measure.max_abs_deviation_deg = measure.max_abs_deviation * degrees_per_radian;

    const SampleStatistics deviation_statistics =
      describe(measure.deviation, confidence, what + ", deviation from Eq. 16");
    measure.mean_deviation = deviation_statistics.mean;
    measure.mean_deviation_deg = deviation_statistics.mean * degrees_per_radian;
    measure.mean_deviation_ci = deviation_statistics.mean_ci;

    const Interval &slope_ci = measure.line.slope_ci;
    const Interval &intercept_ci = measure.line.intercept_ci;
    measure.slope_consistent_with_associative =
      Interval{slope_ci.lower - round_off_allowance, slope_ci.upper + round_off_allowance}.contains(1);
    measure.intercept_consistent_with_associative =
      Interval{intercept_ci.lower - round_off_allowance, intercept_ci.upper + round_off_allowance}
        .contains(-pi / 2);

    double theta_mean = 0;
    for (double value : theta_star)
      theta_mean += value;
    theta_mean /= measure.n;
    double total_sum_of_squares = 0;
    for (double value : theta_star)
      total_sum_of_squares += (value - theta_mean) * (value - theta_mean);
    measure.r_squared_associative = total_sum_of_squares > 0
                                      ? 1 - sum_of_squares / total_sum_of_squares
                                      : std::numeric_limits<double>::quiet_NaN();
    return measure;
  }

  double observed_transition_angle(const std::vector<double> &psi, const std::vector<double> &theta)
  {
    const std::string what = "observed compaction-expansion transition";
    check_same_size_and_finite(psi, "psi", theta, "theta", what);

    // Mean flow angle per distinct loading angle, in increasing psi.
    std::vector<std::pair<double, double>> points(psi.size());
    for (std::size_t i = 0; i < psi.size(); ++i)
      points[i] = {psi[i], theta[i]};
    std::sort(points.begin(), points.end());

    struct LoadingAngleMean
    {
      double psi;
      double theta;
    };
    std::vector<LoadingAngleMean> means;
    for (std::size_t first = 0; first < points.size();)
      {
        std::size_t last = first;
        double psi_sum = 0;
        double theta_sum = 0;
        while (last < points.size() && points[last].first - points[first].first <= same_loading_angle)
          {
            psi_sum += points[last].first;
            theta_sum += points[last].second;
            ++last;
          }
        const double count = static_cast<double>(last - first);
        means.push_back({psi_sum / count, theta_sum / count});
        first = last;
      }

    if (means.size() < 2)
      {
        std::ostringstream message;
        message << what << ": " << means.size()
                << " distinct loading angle(s) among " << psi.size()
                << " failure points; need at least 2 to locate a change of sign of theta";
        throw CalibrationError(message.str());
      }

    // First change from compaction to expansion; exact zeros between them are a plateau of the
    // piecewise-linear interpolant, whose middle is returned.
    for (std::size_t j = 0; j + 1 < means.size(); ++j)
      {
        if (!(means[j].theta < 0))
          continue;
        std::size_t k = j + 1;
        while (k < means.size() && means[k].theta == 0)
          ++k;
        if (k == means.size())
          break;
        if (means[k].theta > 0)
          {
            if (k == j + 1)
              return means[j].psi
                     + (0 - means[j].theta) * (means[k].psi - means[j].psi)
                         / (means[k].theta - means[j].theta);
            return 0.5 * (means[j + 1].psi + means[k - 1].psi);
          }
      }

    const bool any_compaction =
      std::any_of(means.begin(), means.end(), [](const LoadingAngleMean &m) { return m.theta < 0; });
    const bool any_expansion =
      std::any_of(means.begin(), means.end(), [](const LoadingAngleMean &m) { return m.theta > 0; });
    std::ostringstream message;
    message << what << ": ";
    if (any_compaction && !any_expansion)
      message << "all compaction (mean theta <= 0)";
    else if (any_expansion && !any_compaction)
      message << "all expansion (mean theta >= 0)";
    else if (any_compaction && any_expansion)
      message << "the mean flow changes only from expansion to compaction with increasing psi";
    else
      message << "every mean flow angle is 0";
    message << " at the " << means.size() << " loading angles psi in [" << means.front().psi << ", "
            << means.back().psi << "] rad ([" << means.front().psi * degrees_per_radian << ", "
            << means.back().psi * degrees_per_radian
            << "] deg); need compaction (theta < 0) below and expansion (theta > 0) above the "
               "transition";
    throw CalibrationError(message.str());
  }
} // namespace anticrack::params
