// Stress invariants (docs/physics.md §0): mean pressure p = -tr(sigma)/3 (compression positive) and von
// Mises stress q = sqrt(3/2 s:s) with the deviator s = sigma + p I; sigma tension positive.
#pragma once

#include "dem/common/types.h"

#include <cmath>

namespace anticrack::dem
{
  inline double mean_pressure(const Mat3 &stress) { return -stress.trace() / 3; }

  inline double von_mises_stress(const Mat3 &stress)
  {
    const Mat3 deviator = stress + mean_pressure(stress) * Mat3::Identity();
    return std::sqrt(1.5 * deviator.cwiseProduct(deviator).sum());
  }

  struct StressInvariants
  {
    double p = 0; ///< mean pressure, compression positive [Pa]
    double q = 0; ///< von Mises stress [Pa]
  };

  inline StressInvariants stress_invariants(const Mat3 &stress)
  {
    return {mean_pressure(stress), von_mises_stress(stress)};
  }
} // namespace anticrack::dem
