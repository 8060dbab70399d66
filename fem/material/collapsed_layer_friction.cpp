// Coulomb friction of a failed weak layer: the stick–slip update (F2) on the layer plane and its
// tangent. The equations are in the header.
#include "fem/material/collapsed_layer_friction.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace anticrack::fem
{
  using dealii::SymmetricTensor;

  namespace
  {
    void require(bool condition, const char *name, double value, const char *range)
    {
      if (!condition)
      {
        std::ostringstream out;
        out << "collapsed-layer friction parameter '" << name << "' = " << value << " must be " << range;
        throw std::invalid_argument(out.str());
      }
    }

  } // namespace

  CollapsedFrictionParameters CollapsedFrictionParameters::of_layer(double friction_coefficient, double bulk_modulus,
                                                                    double shear_modulus, double lock_up_modulus)
  {
    require(std::isfinite(friction_coefficient) && friction_coefficient >= 0 &&
              friction_coefficient <= max_friction_coefficient,
            "friction coefficient", friction_coefficient, "in [0, 2]");
    require(std::isfinite(bulk_modulus) && bulk_modulus > 0, "bulk modulus", bulk_modulus, "> 0 [Pa]");
    require(std::isfinite(shear_modulus) && shear_modulus > 0, "shear modulus", shear_modulus, "> 0 [Pa]");
    require(std::isfinite(lock_up_modulus) && lock_up_modulus >= 0, "lock-up modulus", lock_up_modulus, ">= 0 [Pa]");
    CollapsedFrictionParameters p;
    p.enabled = true;
    p.friction_coefficient = friction_coefficient;
    p.shear_modulus = shear_modulus * std::max(1., lock_up_modulus / bulk_modulus); // (F2)
    return p;
  }

  CollapsedFrictionUpdate update_collapsed_friction(const CollapsedFrictionParameters &parameters,
                                                    unsigned int normal_axis,
                                                    const SymmetricTensor<2, 3> &previous,
                                                    const SymmetricTensor<2, 3> &strain_increment,
                                                    double normal_traction,
                                                    const SymmetricTensor<2, 3> &normal_traction_gradient,
                                                    bool with_tangent)
  {
    CollapsedFrictionUpdate result;
    const unsigned int n = normal_axis;
    const double G_f = parameters.shear_modulus;
    // The two in-plane axes and, per axis, τ_n and Δγ = 2 Δε_in.
    const unsigned int axes[2] = {(n + 1) % 3, (n + 2) % 3};
    double tau_n[2], dgamma[2], tau[2] = {0, 0};
    for (unsigned int a = 0; a < 2; ++a)
    {
      tau_n[a] = previous[axes[a]][n];
      dgamma[a] = 2 * strain_increment[axes[a]][n];
    }
    if (parameters.active() && normal_traction > 0)
    {
      const double trial[2] = {tau_n[0] + G_f * dgamma[0], tau_n[1] + G_f * dgamma[1]};
      const double magnitude = std::hypot(trial[0], trial[1]);
      const double limit = parameters.friction_coefficient * normal_traction; // k of (F1)
      result.sliding = magnitude > limit;
      const double ratio = result.sliding ? limit / magnitude : 1.;
      for (unsigned int a = 0; a < 2; ++a)
        tau[a] = ratio * trial[a];
      if (with_tangent)
        for (unsigned int a = 0; a < 2; ++a)
        {
          // dσ_in = Σ_kl C_in,kl dε_kl and C_in,jn = C_in,nj share one entry: C_in,jn = ∂τ_i/∂γ_j
          // gives dσ_in = 2 C_in,jn dε_jn = ∂τ_i/∂γ_j dγ_j.
          for (unsigned int b = 0; b < 2; ++b)
          {
            const double direction_term = result.sliding ? trial[a] * trial[b] / (magnitude * magnitude) : 0.;
            result.tangent[axes[a]][n][axes[b]][n] = ratio * G_f * ((a == b ? 1. : 0.) - direction_term);
          }
          if (result.sliding) // dk = μ dσ_n: ∂τ_i/∂ε_kl gains μ t_i ∂σ_n/∂ε_kl (the stick part has no (k, k) entries)
            for (unsigned int k = 0; k < 3; ++k)
              for (unsigned int l = k; l < 3; ++l)
                result.tangent[axes[a]][n][k][l] +=
                  parameters.friction_coefficient * normal_traction_gradient[k][l] * trial[a] / magnitude;
        }
    }
    for (unsigned int a = 0; a < 2; ++a)
    {
      result.stress[axes[a]][n] = tau[a];
      // Trapezoid of the frictional slip (header): exact against the trapezoidal work of the step.
      if (G_f > 0)
        result.dissipation += 0.5 * (tau_n[a] + tau[a]) * (dgamma[a] - (tau[a] - tau_n[a]) / G_f);
    }
    return result;
  }

  double friction_energy_density(const CollapsedFrictionParameters &parameters,
                                 const SymmetricTensor<2, 3> &friction_stress)
  {
    return parameters.shear_modulus > 0 ? (friction_stress * friction_stress) / (4 * parameters.shear_modulus) : 0;
  }
} // namespace anticrack::fem
