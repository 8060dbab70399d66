// Helpers shared by the material-point tests (test_cohesive_cam_clay.cpp, test_densification.cpp,
// test_point_simple_shear.cpp).
#pragma once

#include "fem/material/cohesive_cam_clay.h"

#include <deal.II/base/symmetric_tensor.h>

#include <cmath>

#include <functional>
#include <random>
#include <stdexcept>
#include <string>

namespace anticrack::fem::test_support
{
  /// A weak layer that collapses at once under hydrostatic compaction (collapse law, ξ = 5:
  /// ξ cosh(ξ α) > 1, see CamClayHardening.CollapseCompactionLowersP0): K = 0.5 MPa, G = 0.3 MPa,
  /// p0 = 1 kPa, floor 0.2 p0, lock-up at ε_d = 0.2 with K_d = 1 MPa.
  inline CamClayParameters weak_layer(bool lock_up = true)
  {
    CamClayParameters m;
    m.bulk_modulus = 0.5e6;
    m.shear_modulus = 0.3e6;
    m.M = 0.8;
    m.beta = 0.3;
    m.p0_initial = 1e3;
    m.hardening_factor = 5;
    m.p0_floor = residual_p0_floor(m.p0_initial, 0.2);
    m.law = HardeningLaw::collapse;
    if (lock_up)
      {
        m.densification_strain = 0.2;
        m.densification_modulus = 1e6;
      }
    return m;
  }

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

  /// ‖C_fd − C‖ / ‖C‖ over the 6×6 components of `tangent`, C_fd by central differences of
  /// update_stress from `previous` at `strain` with step h (direction [k][l] also sets [l][k]: the
  /// column compared is C : direction).
  inline double central_difference_error(const CamClayParameters &m, const CamClayState &previous,
                                         const dealii::SymmetricTensor<2, 3> &strain,
                                         const dealii::SymmetricTensor<4, 3> &tangent, double h)
  {
    double difference = 0, reference = 0;
    for (unsigned int k = 0; k < 3; ++k)
      for (unsigned int l = k; l < 3; ++l)
      {
        dealii::SymmetricTensor<2, 3> direction;
        direction[k][l] = 1;
        const dealii::SymmetricTensor<2, 3> fd =
          (update_stress(m, previous, strain + h * direction).stress -
           update_stress(m, previous, strain - h * direction).stress) /
          (2 * h);
        const dealii::SymmetricTensor<2, 3> analytic = tangent * direction;
        difference += std::pow((fd - analytic).norm(), 2);
        reference += std::pow(analytic.norm(), 2);
      }
    return std::sqrt(difference / reference);
  }
} // namespace anticrack::fem::test_support
