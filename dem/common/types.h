// Basic types shared by the DEM library. SI units everywhere (m, kg, s, N, Pa, J).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace anticrack::dem
{
  using Vec3 = Eigen::Vector3d;
  using Mat3 = Eigen::Matrix3d;
  using Quat = Eigen::Quaterniond;
  using Index = std::int64_t;

  /// Raised when the simulation state becomes numerically unusable (NaN, energy blow-up,
  /// a time step above the critical one). The message says where and when.
  class NumericalError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// Raised for inconsistent set-up (bad parameters, geometry that does not fit the domain).
  class SetupError : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /// x with six significant digits, for the values that SetupError messages quote.
  std::string format_for_message(double x);
} // namespace anticrack::dem
