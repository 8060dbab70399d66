// Failure envelopes in a stress plane; see yield_envelopes.h for the plane, the polar radius and the
// sources of the three families.
#include "params/yield_envelopes.h"

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace anticrack::params
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;
    constexpr double radians_per_degree = pi / 180;

    void check_size(const Eigen::VectorXd &parameters, Eigen::Index expected, const std::string &model)
    {
      if (parameters.size() != expected)
      {
        std::ostringstream msg;
        msg << model << ": parameter vector of size " << parameters.size() << ", expected " << expected;
        throw std::invalid_argument(msg.str());
      }
    }

    Admissibility refuse(const std::string &reason) { return {false, reason}; }

    /// The first violated condition among "finite" for every entry, as an Admissibility.
    Admissibility finite_entries(const Eigen::VectorXd &physical, const std::vector<std::string> &names)
    {
      for (Eigen::Index i = 0; i < physical.size(); ++i)
        if (!std::isfinite(physical[i]))
          return refuse(names[i] + " is not finite");
      return {};
    }

    double logistic(double x) { return 1 / (1 + std::exp(-x)); }
    double logit(double fraction) { return std::log(fraction / (1 - fraction)); }

    /// Larger root of a x^2 + b x + c = 0, assumed real (a >= 0; if a == 0 then b > 0). The textbook
    /// formula subtracts nearly equal numbers when b > 0 and |4 a c| << b^2; there the larger root is
    /// taken from the product of the roots, c / a, divided by the smaller one (no cancellation in it).
    double larger_quadratic_root(double a, double b, double c)
    {
      const double root_of_discriminant = std::sqrt(std::max(0.0, b * b - 4 * a * c));
      if (b <= 0)
        return (-b + root_of_discriminant) / (2 * a);
      return 2 * c / (-b - root_of_discriminant);
    }

    /// What the starting points of every family are derived from: the extent of the data along the
    /// axes. The tips are only as well known as the loading angles next to 0 and pi, the peak shear as
    /// the angles next to it, so the guesses are rough on purpose; the multi-start makes up for it.
    struct DataExtents
    {
      double tensile = 0;            ///< largest -normal (> 0 for checked data) [Pa]
      double compressive = 0;        ///< largest normal, or the largest radius without compressive points [Pa]
      double largest_shear = 0;      ///< [Pa]
      double shear_near_vertical = 0; ///< shear of the point nearest to a = pi/2, for the shear at n = 0 [Pa]
      double largest_radius = 0;     ///< [Pa]
    };

    DataExtents data_extents(const std::vector<StressPoint> &points)
    {
      if (points.empty())
        throw std::invalid_argument("initial_guesses: no failure points");
      DataExtents extents;
      double largest_normal = -std::numeric_limits<double>::infinity();
      double distance_from_vertical = std::numeric_limits<double>::infinity();
      for (const StressPoint &point : points)
      {
        extents.tensile = std::max(extents.tensile, -point.normal);
        largest_normal = std::max(largest_normal, point.normal);
        extents.largest_shear = std::max(extents.largest_shear, point.shear);
        extents.largest_radius = std::max(extents.largest_radius, polar_radius(point));
        const double distance = std::abs(polar_angle(point) - pi / 2);
        if (distance < distance_from_vertical)
        {
          distance_from_vertical = distance;
          extents.shear_near_vertical = point.shear;
        }
      }
      if (!(extents.tensile > 0))
        throw std::invalid_argument("initial_guesses: the data have no tensile point (normal < 0); "
                                    "check them with check_envelope_data() first");
      extents.compressive = largest_normal > 0 ? largest_normal : extents.largest_radius;
      // A data set without a point near pure shear still needs a positive shear scale.
      if (!(extents.shear_near_vertical > 0))
        extents.shear_near_vertical = extents.largest_shear > 0 ? extents.largest_shear : extents.largest_radius;
      return extents;
    }

    // -------------------------------------------------------------------------------------------------
    /// Cohesive Cam-Clay (docs/physics.md §2, Ritter et al. 2020, Eq. 1), parameters (p0 [Pa], beta [-], M [-]), all
    /// positive; internal coordinates are their logarithms.
    ///
    /// Radius: the point R (cos a, sin a) on y = 0 solves
    ///   R^2 [(1 + 2 beta) sin^2 a + M^2 cos^2 a] + R M^2 p0 (beta - 1) cos a - M^2 beta p0^2 = 0,
    /// whose constant term is negative and leading coefficient positive: exactly one positive root.
    class CohesiveCamClay : public YieldEnvelope
    {
    public:
      std::string name() const override { return "cohesive_cam_clay"; }
      std::vector<std::string> parameter_names() const override { return {"p0", "beta", "M"}; }
      std::vector<std::string> parameter_units() const override { return {"Pa", "-", "-"}; }

      double radius(double angle, const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 3, name());
        return cam_clay_radius(angle, physical[0], physical[1], physical[2]);
      }

      std::optional<double> shear_at(double normal, const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 3, name());
        const double p0 = physical[0], beta = physical[1], M = physical[2];
        // y(n, s) = (1 + 2 beta) s^2 + y(n, 0) = 0 on the ellipse.
        const double yield_without_shear = cam_clay_yield(normal, 0, p0, beta, M);
        if (yield_without_shear > 0)
          return std::nullopt;
        return std::sqrt(-yield_without_shear / (1 + 2 * beta));
      }

      Eigen::VectorXd to_internal(const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 3, name());
        return physical.array().log();
      }

      Eigen::VectorXd to_physical(const Eigen::VectorXd &internal) const override
      {
        check_size(internal, 3, name());
        return internal.array().exp();
      }

      Eigen::MatrixXd physical_jacobian(const Eigen::VectorXd &internal) const override
      {
        return to_physical(internal).asDiagonal();
      }

      Admissibility admissible(const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 3, name());
        if (const Admissibility finite = finite_entries(physical, parameter_names()); !finite.admissible)
          return finite;
        const std::vector<std::string> names = parameter_names();
        for (Eigen::Index i = 0; i < 3; ++i)
          if (!(physical[i] > 0))
            return refuse(names[i] + " = " + std::to_string(physical[i]) + " must be > 0");
        return {};
      }

      /// Tips from the extreme normal stresses, M from the largest shear read as the peak of the
      /// ellipse; variations of beta and M by a factor 2 and of the compressive tip by 1.5, because the
      /// tips and the peak lie between loading angles in general.
      std::vector<Eigen::VectorXd> initial_guesses(const std::vector<StressPoint> &points) const override
      {
        const DataExtents extents = data_extents(points);
        const double p0 = extents.compressive;
        const double beta = extents.tensile / p0;
        // The peak shear is proportional to M: invert it with M = 1.
        const double M = extents.largest_shear / cam_clay_peak_shear(p0, beta, 1);
        std::vector<Eigen::VectorXd> guesses;
        for (const Eigen::Vector3d &factor : {Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1, 1, 0.5),
                                              Eigen::Vector3d(1, 1, 2), Eigen::Vector3d(1, 0.5, 1),
                                              Eigen::Vector3d(1, 2, 1), Eigen::Vector3d(1.5, 1 / 1.5, 1)})
          guesses.push_back(Eigen::Vector3d(p0, beta, M).cwiseProduct(factor));
        return guesses;
      }
    };

    // -------------------------------------------------------------------------------------------------
    /// Mohr-Coulomb line with an elliptical cap, parameters (c [Pa], phi [deg], n_k [Pa], n_c [Pa]):
    ///   shear = c + n tan(phi)                                  for -c/tan(phi) <= n <= n_k,
    ///   shear = tau_k sqrt(1 - ((n - n_k)/(n_c - n_k))^2)       for n_k < n <= n_c,
    /// tau_k = c + n_k tan(phi). The cap leaves the line with a horizontal tangent, so the upper boundary
    /// is concave and the enclosed region convex; it contains the origin when c > 0 and n_c > 0.
    ///
    /// Constraints: c > 0, 0 < phi < 90 deg, n_c > 0, -c/tan(phi) < n_k < n_c. The internal coordinates
    /// keep the ordering: (ln c, logit(phi / 90 deg), logit of the position of n_k in
    /// (-c/tan(phi), n_c), ln n_c). c, phi and n_c are each a function of their own coordinate; n_k
    /// depends on all four.
    class MohrCoulombCap : public YieldEnvelope
    {
    public:
      std::string name() const override { return "mohr_coulomb_cap"; }
      std::vector<std::string> parameter_names() const override
      {
        return {"cohesion", "friction_angle", "cap_start", "compressive_strength"};
      }
      std::vector<std::string> parameter_units() const override { return {"Pa", "deg", "Pa", "Pa"}; }

      double radius(double angle, const Eigen::VectorXd &physical) const override
      {
        const Geometry g = geometry(physical);
        // The envelope is star-shaped about the origin: rays steeper than the one through the knee
        // (n_k, tau_k) meet the line, the others the cap; the same ray never meets both.
        const double c = std::cos(angle), s = std::sin(angle);
        if (angle >= std::atan2(g.knee_shear, g.cap_start))
          return g.cohesion / (s - c * g.tan_friction); // R s = c + R c tan(phi)
        // ((R c - n_k)/w)^2 + (R s / tau_k)^2 = 1, times w^2; the constant n_k^2 - w^2 is written as
        // n_c (2 n_k - n_c). The ray leaves the cap where it leaves the full ellipse: the larger root.
        const double half_width = g.compressive_strength - g.cap_start;
        const double stretched_sine = s * half_width / g.knee_shear;
        return larger_quadratic_root(c * c + stretched_sine * stretched_sine, -2 * c * g.cap_start,
                                     g.compressive_strength * (2 * g.cap_start - g.compressive_strength));
      }

      std::optional<double> shear_at(double normal, const Eigen::VectorXd &physical) const override
      {
        const Geometry g = geometry(physical);
        if (normal < -g.cohesion / g.tan_friction || normal > g.compressive_strength)
          return std::nullopt;
        if (normal <= g.cap_start)
          return std::max(0.0, line_shear(normal, g));
        const double x = (normal - g.cap_start) / (g.compressive_strength - g.cap_start);
        return g.knee_shear * std::sqrt(std::max(0.0, 1 - x * x));
      }

      Eigen::VectorXd to_internal(const Eigen::VectorXd &physical) const override
      {
        const Geometry g = geometry(physical);
        const double tensile_strength = g.cohesion / g.tan_friction;
        return Eigen::Vector4d(std::log(g.cohesion), logit(physical[1] / 90),
                               logit((g.cap_start + tensile_strength) / (g.compressive_strength + tensile_strength)),
                               std::log(g.compressive_strength));
      }

      Eigen::VectorXd to_physical(const Eigen::VectorXd &internal) const override
      {
        check_size(internal, 4, name());
        const double cohesion = std::exp(internal[0]);
        const double friction_angle = 90 * logistic(internal[1]);
        const double compressive_strength = std::exp(internal[3]);
        const double tensile_strength = cohesion / std::tan(friction_angle * radians_per_degree);
        const double cap_start = -tensile_strength + (compressive_strength + tensile_strength) * logistic(internal[2]);
        return Eigen::Vector4d(cohesion, friction_angle, cap_start, compressive_strength);
      }

      /// Derivatives of to_physical; with T = c / tan(phi) and f = logistic(u2),
      /// n_k = -T (1 - f) + n_c f, dT/du0 = T, dT/du1 = -T / (sin(phi) cos(phi)) dphi/du1 (phi in rad).
      Eigen::MatrixXd physical_jacobian(const Eigen::VectorXd &internal) const override
      {
        const Eigen::VectorXd physical = to_physical(internal);
        const double cohesion = physical[0], compressive_strength = physical[3];
        const double phi = physical[1] * radians_per_degree;
        const double tensile_strength = cohesion / std::tan(phi);
        const double f = logistic(internal[2]), g = logistic(internal[1]);
        const double dphi_degrees = 90 * g * (1 - g);
        const double dtensile_du1 =
          -tensile_strength / (std::sin(phi) * std::cos(phi)) * dphi_degrees * radians_per_degree;

        Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(4, 4);
        jacobian(0, 0) = cohesion;
        jacobian(1, 1) = dphi_degrees;
        jacobian(2, 0) = -(1 - f) * tensile_strength;
        jacobian(2, 1) = -(1 - f) * dtensile_du1;
        jacobian(2, 2) = (compressive_strength + tensile_strength) * f * (1 - f);
        jacobian(2, 3) = f * compressive_strength;
        jacobian(3, 3) = compressive_strength;
        return jacobian;
      }

      Admissibility admissible(const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 4, name());
        if (const Admissibility finite = finite_entries(physical, parameter_names()); !finite.admissible)
          return finite;
        const double cohesion = physical[0], friction_angle = physical[1];
        const double cap_start = physical[2], compressive_strength = physical[3];
        std::ostringstream msg;
        if (!(cohesion > 0))
          msg << "cohesion = " << cohesion << " Pa must be > 0";
        else if (!(friction_angle > 0 && friction_angle < 90))
          msg << "friction_angle = " << friction_angle << " deg must be in (0, 90)";
        else if (!(compressive_strength > 0))
          msg << "compressive_strength = " << compressive_strength << " Pa must be > 0 (enclose the origin)";
        else if (!(cap_start > -cohesion / std::tan(friction_angle * radians_per_degree)))
          msg << "cap_start = " << cap_start << " Pa must exceed the tensile tip -c/tan(phi) = "
              << -cohesion / std::tan(friction_angle * radians_per_degree) << " Pa";
        else if (!(cap_start < compressive_strength))
          msg << "cap_start = " << cap_start << " Pa must be below compressive_strength = " << compressive_strength
              << " Pa";
        else
          return {};
        return refuse(msg.str());
      }

      /// The line through the tensile tip and the shear near n = 0, the cap ending at the compressive
      /// extent, the knee at a quarter, half and three quarters of the way between the tips.
      std::vector<Eigen::VectorXd> initial_guesses(const std::vector<StressPoint> &points) const override
      {
        const DataExtents extents = data_extents(points);
        const double cohesion = extents.shear_near_vertical;
        const double friction_angle = std::clamp(std::atan(cohesion / extents.tensile) / radians_per_degree, 1.0, 89.0);
        const double tensile_strength = cohesion / std::tan(friction_angle * radians_per_degree);
        std::vector<Eigen::VectorXd> guesses;
        for (const double fraction : {0.25, 0.5, 0.75})
          guesses.push_back(Eigen::Vector4d(cohesion, friction_angle,
                                            -tensile_strength + fraction * (extents.compressive + tensile_strength),
                                            extents.compressive));
        return guesses;
      }

    private:
      struct Geometry
      {
        double cohesion, tan_friction, cap_start, compressive_strength, knee_shear;
      };

      static double line_shear(double normal, const Geometry &g) { return g.cohesion + normal * g.tan_friction; }

      Geometry geometry(const Eigen::VectorXd &physical) const
      {
        check_size(physical, 4, name());
        Geometry g{physical[0], std::tan(physical[1] * radians_per_degree), physical[2], physical[3], 0};
        g.knee_shear = line_shear(g.cap_start, g);
        return g;
      }
    };

    // -------------------------------------------------------------------------------------------------
    /// Quadratic polynomial of Bobillier et al. (2020), Eq. 9, shear = b0 + b1 n + b2 n^2, parameters (b0 [Pa], b1 [-],
    /// b2 [1/Pa]) with b0 > 0 (shear strength at n = 0, so the origin is inside) and b2 < 0 (concave,
    /// closed by its two roots, the tips). Internal coordinates (ln b0, b1, ln(-b2)).
    ///
    /// Radius: R sin a = b0 + b1 R cos a + b2 R^2 cos^2 a, i.e. (times -1)
    ///   -b2 cos^2 a R^2 + (sin a - b1 cos a) R - b0 = 0,
    /// leading coefficient >= 0, constant < 0: exactly one positive root (R = b0 at a = pi/2).
    class QuadraticPolynomial : public YieldEnvelope
    {
    public:
      std::string name() const override { return "quadratic_polynomial"; }
      std::vector<std::string> parameter_names() const override { return {"b0", "b1", "b2"}; }
      std::vector<std::string> parameter_units() const override { return {"Pa", "-", "1/Pa"}; }

      double radius(double angle, const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 3, name());
        const double c = std::cos(angle), s = std::sin(angle);
        return larger_quadratic_root(-physical[2] * c * c, s - physical[1] * c, -physical[0]);
      }

      std::optional<double> shear_at(double normal, const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 3, name());
        const double shear = physical[0] + normal * (physical[1] + normal * physical[2]);
        if (shear < 0)
          return std::nullopt;
        return shear;
      }

      Eigen::VectorXd to_internal(const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 3, name());
        return Eigen::Vector3d(std::log(physical[0]), physical[1], std::log(-physical[2]));
      }

      Eigen::VectorXd to_physical(const Eigen::VectorXd &internal) const override
      {
        check_size(internal, 3, name());
        return Eigen::Vector3d(std::exp(internal[0]), internal[1], -std::exp(internal[2]));
      }

      Eigen::MatrixXd physical_jacobian(const Eigen::VectorXd &internal) const override
      {
        const Eigen::VectorXd physical = to_physical(internal);
        return Eigen::Vector3d(physical[0], 1, physical[2]).asDiagonal();
      }

      Admissibility admissible(const Eigen::VectorXd &physical) const override
      {
        check_size(physical, 3, name());
        if (const Admissibility finite = finite_entries(physical, parameter_names()); !finite.admissible)
          return finite;
        if (!(physical[0] > 0))
          return refuse("b0 = " + std::to_string(physical[0]) + " Pa must be > 0 (the origin inside)");
        if (!(physical[2] < 0))
          return refuse("b2 = " + std::to_string(physical[2]) + " 1/Pa must be < 0 (a closed, concave envelope)");
        return {};
      }

      /// Bobillier et al.'s (2020) own fit, ordinary least squares of the shear on (1, n, n^2), projected into the
      /// admissible set (b0 and -b2 at least 1 % of the data's scale, which leaves an admissible fit
      /// untouched); and the parabola through the two tips and the shear near n = 0.
      std::vector<Eigen::VectorXd> initial_guesses(const std::vector<StressPoint> &points) const override
      {
        const DataExtents extents = data_extents(points);
        // Regress on n / L: the columns 1, n, n^2 in Pa would differ by eight orders of magnitude.
        const double L = extents.largest_radius;
        Eigen::MatrixXd design(points.size(), 3);
        Eigen::VectorXd shear(points.size());
        for (std::size_t i = 0; i < points.size(); ++i)
        {
          const double x = points[i].normal / L;
          design.row(i) << 1, x, x * x;
          shear[i] = points[i].shear;
        }
        const Eigen::Vector3d scaled = design.colPivHouseholderQr().solve(shear);
        const double floor_b0 = 0.01 * extents.largest_shear;
        const double ceiling_b2 = -0.01 * extents.largest_shear / (L * L);
        const Eigen::Vector3d least_squares(std::max(scaled[0], floor_b0), scaled[1] / L,
                                            std::min(scaled[2] / (L * L), ceiling_b2));

        // s(n) = -s0 (n + T)(n - C) / (T C): tips -T and C, s(0) = s0.
        const double T = extents.tensile, C = extents.compressive, s0 = extents.shear_near_vertical;
        const Eigen::Vector3d through_tips(s0, s0 * (C - T) / (T * C), -s0 / (T * C));
        return {least_squares, through_tips};
      }
    };
  } // namespace

  double polar_angle(const StressPoint &point) { return std::atan2(point.shear, point.normal); }

  double polar_radius(const StressPoint &point) { return std::hypot(point.normal, point.shear); }

  std::vector<EnvelopeKind> all_envelope_kinds()
  {
    return {EnvelopeKind::cohesive_cam_clay, EnvelopeKind::mohr_coulomb_cap, EnvelopeKind::quadratic_polynomial};
  }

  std::unique_ptr<YieldEnvelope> make_envelope(EnvelopeKind kind)
  {
    switch (kind)
    {
      case EnvelopeKind::cohesive_cam_clay:
        return std::make_unique<CohesiveCamClay>();
      case EnvelopeKind::mohr_coulomb_cap:
        return std::make_unique<MohrCoulombCap>();
      case EnvelopeKind::quadratic_polynomial:
        return std::make_unique<QuadraticPolynomial>();
    }
    throw std::invalid_argument("make_envelope: unknown EnvelopeKind");
  }

  double cam_clay_yield(double normal, double shear, double p0, double beta, double M)
  {
    return (1 + 2 * beta) * shear * shear + M * M * (normal + beta * p0) * (normal - p0);
  }

  double cam_clay_radius(double angle, double p0, double beta, double M)
  {
    const double c = std::cos(angle), s = std::sin(angle);
    const double M2 = M * M;
    return larger_quadratic_root((1 + 2 * beta) * s * s + M2 * c * c, M2 * p0 * (beta - 1) * c, -M2 * beta * p0 * p0);
  }

  double cam_clay_peak_shear(double p0, double beta, double M)
  {
    return M * p0 * (1 + beta) / (2 * std::sqrt(1 + 2 * beta));
  }

  CamClaySurface cam_clay_surface(const Eigen::VectorXd &physical)
  {
    check_size(physical, 3, "cohesive_cam_clay");
    return {physical[0], physical[1], physical[2]};
  }

  Eigen::VectorXd scale_polynomial(const Eigen::VectorXd &polynomial_parameters, double strength_ratio)
  {
    check_size(polynomial_parameters, 3, "scale_polynomial");
    if (!(std::isfinite(strength_ratio) && strength_ratio > 0))
      throw std::invalid_argument("scale_polynomial: strength_ratio = " + std::to_string(strength_ratio) +
                                  " must be finite and > 0");
    const double k = strength_ratio;
    return Eigen::Vector3d(k * polynomial_parameters[0], polynomial_parameters[1], polynomial_parameters[2] / k);
  }
} // namespace anticrack::params
