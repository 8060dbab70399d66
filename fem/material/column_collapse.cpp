// The 1D column collapse with small-strain and finite-strain (Hencky) kinematics; see the header.
#include "fem/material/column_collapse.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace anticrack::fem
{
  namespace
  {
    /// σ_nn (compression positive) along the column's closure x_k = k h_c / (H steps), k = 0..steps,
    /// of the material point driven by strain(x) n⊗n, the stress divided by stress_divisor(x).
    template <typename Strain, typename Divisor>
    std::vector<double> normal_stress_path(const CamClayParameters &parameters, double closure_ratio,
                                           unsigned int steps, Strain strain, Divisor stress_divisor)
    {
      std::vector<double> stress(steps + 1, 0.);
      CamClayState state = CamClayState::initial(parameters);
      for (unsigned int k = 1; k <= steps; ++k)
      {
        const double x = closure_ratio * k / steps;
        dealii::SymmetricTensor<2, 3> e;
        e[1][1] = strain(x);
        const CamClayUpdate update = update_stress(parameters, state, e);
        state = update.state;
        stress[k] = -update.stress[1][1] / stress_divisor(x);
      }
      return stress;
    }
  } // namespace

  double ColumnCollapseComparison::peak_error() const
  {
    return std::abs(peak_small_strain - peak_finite_strain) / peak_finite_strain;
  }

  double ColumnCollapseComparison::work_error() const
  {
    return std::abs(work_small_strain - work_finite_strain) / work_finite_strain;
  }

  ColumnCollapseComparison compare_column_collapse(const CamClayParameters &parameters, unsigned int steps)
  {
    if (!(parameters.densification_strain > 0))
      throw std::invalid_argument("compare_column_collapse: the layer has no lock-up (densification_strain = 0)");
    ColumnCollapseComparison c;
    c.closure_ratio = parameters.densification_strain;
    const double x_c = c.closure_ratio;
    // The small-strain model, as the solver uses it.
    const std::vector<double> small =
      normal_stress_path(parameters, x_c, steps, [](double x) { return -x; }, [](double) { return 1.; });
    // The finite-strain reference: Hencky strain, Kirchhoff stress, σ = τ / J; its lock-up at the same closure.
    CamClayParameters hencky = parameters;
    hencky.densification_strain = -std::log1p(-x_c);
    const std::vector<double> finite = normal_stress_path(
      hencky, x_c, steps, [](double x) { return std::log1p(-x); }, [](double x) { return 1 - x; });
    const double dx = x_c / steps;
    for (unsigned int k = 1; k <= steps; ++k)
    {
      c.work_small_strain += 0.5 * (small[k - 1] + small[k]) * dx;
      c.work_finite_strain += 0.5 * (finite[k - 1] + finite[k]) * dx;
    }
    c.peak_small_strain = *std::max_element(small.begin(), small.end());
    c.peak_finite_strain = *std::max_element(finite.begin(), finite.end());
    return c;
  }
} // namespace anticrack::fem
