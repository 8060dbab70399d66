// Helpers shared by the material-point tests (test_cohesive_cam_clay.cpp, test_densification.cpp).
#pragma once

#include <deal.II/base/symmetric_tensor.h>

#include <functional>
#include <random>
#include <stdexcept>
#include <string>

namespace anticrack::fem::test_support
{
  /// The strain of a hydrostatic state with tr ε = volumetric_strain.
  inline dealii::SymmetricTensor<2, 3> hydrostatic(double volumetric_strain)
  {
    return (volumetric_strain / 3) * dealii::unit_symmetric_tensor<3>();
  }

  /// A random symmetric tensor with N(0, scale²) components, reproducible from the engine.
  inline dealii::SymmetricTensor<2, 3> random_tensor(std::mt19937_64 &engine, double scale)
  {
    std::normal_distribution<double> normal(0, scale);
    dealii::SymmetricTensor<2, 3> t;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        t[i][j] = normal(engine);
    return t;
  }

  /// The message of the std::invalid_argument that `f` throws ("" if none).
  inline std::string invalid_argument_message(const std::function<void()> &f)
  {
    try
    {
      f();
    }
    catch (const std::invalid_argument &e)
    {
      return e.what();
    }
    return "";
  }
} // namespace anticrack::fem::test_support
