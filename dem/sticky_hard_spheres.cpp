#include "dem/sticky_hard_spheres.h"

#include "dem/types.h"

#include <cmath>
#include <sstream>
#include <string>

namespace anticrack::dem::shs
{
  namespace
  {
    void require_volume_fraction(double phi)
    {
      if (!(phi > 0 && phi < 1))
        throw SetupError("sticky hard spheres: volume fraction phi = " + std::to_string(phi) +
                         " outside (0, 1)");
    }

    /// Coefficients of the PY quadratic a lambda^2 + b lambda + c = 0.
    struct Quadratic
    {
      double a, b, c;
    };
    Quadratic percus_yevick_quadratic(double phi, double tau)
    {
      return {phi / 12, -(tau + phi / (1 - phi)), (1 + phi / 2) / ((1 - phi) * (1 - phi))};
    }
  } // namespace

  double minimum_stickiness(double phi)
  {
    require_volume_fraction(phi);
    return (14 * phi * phi - 4 * phi - 1) / (12 * (2 * phi * phi - phi - 1));
  }

  double percus_yevick_lambda(double phi, double tau)
  {
    const double tau_min = minimum_stickiness(phi);
    const Quadratic q = percus_yevick_quadratic(phi, tau);
    const double discriminant = q.b * q.b - 4 * q.a * q.c;
    if (!(tau >= tau_min) || discriminant < 0)
    {
      std::ostringstream message;
      message << "sticky hard spheres: stickiness tau = " << tau << " at volume fraction phi = " << phi
              << " is below the admissible minimum tau_min(phi) = " << tau_min
              << " (PHYSICS.md 1.4); use tau >= tau_min or a lower volume fraction";
      throw SetupError(message.str());
    }
    // Smaller root, written to avoid cancellation: lambda = 2c / (-b + sqrt(disc)).
    return 2 * q.c / (-q.b + std::sqrt(discriminant));
  }

  double percus_yevick_coordination(double phi, double tau)
  {
    return 2 * phi * percus_yevick_lambda(phi, tau);
  }

  double stickiness_for_coordination(double phi, double z)
  {
    require_volume_fraction(phi);
    if (!(z > 0))
      throw SetupError("sticky hard spheres: target coordination number z = " + std::to_string(z) +
                       " must be positive");
    const double lambda = z / (2 * phi);
    const Quadratic q = percus_yevick_quadratic(phi, 0.0);
    const double tau = (q.a * lambda * lambda + q.c) / lambda - phi / (1 - phi);
    const double tau_min = minimum_stickiness(phi);
    // lambda must be the smaller root: the vertex of the parabola lies at lambda* = (tau + phi/(1-phi))/(2a).
    const double vertex = (tau + phi / (1 - phi)) / (2 * q.a);
    if (!(tau >= tau_min) || lambda > vertex)
    {
      std::ostringstream message;
      message << "sticky hard spheres: coordination number z = " << z << " at volume fraction phi = " << phi
              << " needs tau = " << tau << ", outside the admissible range tau >= tau_min(phi) = " << tau_min
              << " (the largest reachable z is " << percus_yevick_coordination(phi, tau_min) << ")";
      throw SetupError(message.str());
    }
    return tau;
  }
} // namespace anticrack::dem::shs
