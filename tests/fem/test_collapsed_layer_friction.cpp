// Tests of the Coulomb friction of a failed layer (fem/material/collapsed_layer_friction.h), on
// the layer plane of normal y (axis 1):
//  * simple shear of the layer plane under a fixed normal traction against the closed form of a
//    stick–slip interface: τ = G_f γ until τ = μ σ_n (Coulomb), then τ = μ σ_n whatever the slip;
//  * the dissipation equals the frictional work μ σ_n × slip of the closed form, and the work done
//    on a load–unload cycle equals stored + dissipated energy to round-off (energy conservation of
//    the update);
//  * the tangent against central differences of the update with a normal traction that depends on
//    every strain component (σ_n = K_d ⟨−tr ε − ε_d⟩ + a ε_nn + b ε_xy, the lock-up plus a
//    skeleton), stick and slide, with shear in both in-plane directions;
//  * uniaxial compaction of the layer, which is not slip, leaves the friction untouched;
//  * release when the faces separate, and the parameter checks.
//
// Units: a weak layer with K = 0.5 MPa, G = 0.3 MPa and K_d = 1 MPa, so G_f = 0.6 MPa; μ = 0.5 and
// σ_n = 2 kPa (the weight of a 0.8 m slab), so the friction limit is τ = 1 kPa at γ = 1.67e-3.
#include "fem/material/collapsed_layer_friction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace
{
  using namespace anticrack::fem;
  using dealii::SymmetricTensor;

  constexpr double K = 0.5e6, G = 0.3e6, K_d = 1e6, mu = 0.5, p_d = 2e3;
  const SymmetricTensor<2, 3> no_gradient;

  CollapsedFrictionParameters parameters() { return CollapsedFrictionParameters::of_layer(mu, K, G, K_d); }

  /// A simple-shear increment of the layer plane (x, n = y): Δε_xy = Δγ / 2.
  SymmetricTensor<2, 3> shear(double dgamma)
  {
    SymmetricTensor<2, 3> e;
    e[0][1] = dgamma / 2;
    return e;
  }

  TEST(CollapsedLayerFriction, StickStiffnessIsTheStifferStatesShearModulus)
  {
    // Locked up stiffer than intact (K_d > K): the densified layer's K_d G / K; else G.
    EXPECT_DOUBLE_EQ(parameters().shear_modulus, K_d * G / K);
    EXPECT_DOUBLE_EQ(CollapsedFrictionParameters::of_layer(mu, K, G, 0.1 * K).shear_modulus, G);
    EXPECT_TRUE(parameters().active());
    // μ = 0 is a frictionless failed layer, still the frictional law; no μ is no law.
    EXPECT_TRUE(CollapsedFrictionParameters::of_layer(0, K, G, K_d).active());
    EXPECT_FALSE(CollapsedFrictionParameters().active());
    const CollapsedFrictionUpdate frictionless =
      update_collapsed_friction(CollapsedFrictionParameters::of_layer(0, K, G, K_d), 1, {}, shear(1e-3), p_d, no_gradient, true);
    EXPECT_EQ(frictionless.stress.norm(), 0);
  }

  TEST(CollapsedLayerFriction, SimpleShearSticksThenSlidesAtCoulombsLimit)
  {
    // Closed form of an elastic–perfectly frictional interface: τ(γ) = min(G_f γ, μ p_d); slip
    // γ_s = γ − μ p_d / G_f beyond the limit, dissipation μ p_d γ_s. 400 steps of Δγ = 2e-5 go to
    // γ = 8e-3, about 5 times the stick range.
    const CollapsedFrictionParameters f = parameters();
    const double dgamma = 2e-5, tau_max = mu * p_d;
    SymmetricTensor<2, 3> s;
    double dissipated = 0;
    for (int i = 1; i <= 400; ++i)
    {
      const CollapsedFrictionUpdate u = update_collapsed_friction(f, 1, s, shear(dgamma), p_d, no_gradient, false);
      s = u.stress;
      dissipated += u.dissipation;
      const double gamma = i * dgamma;
      const double expected = std::min(f.shear_modulus * gamma, tau_max);
      // The return is exact (no iteration): only round-off of a few operations per step.
      EXPECT_NEAR(s[0][1], expected, 1e-12 * tau_max) << "step " << i;
      EXPECT_EQ(u.sliding, f.shear_modulus * gamma > tau_max * (1 + 1e-12)) << "step " << i;
      // The friction is a layer-plane traction in the direction of the shear.
      EXPECT_EQ(s[0][0], 0.);
      EXPECT_EQ(s[1][1], 0.);
      EXPECT_EQ(s[1][2], 0.);
      const double slip = std::max(gamma - tau_max / f.shear_modulus, 0.);
      // The trapezoid is exact on each sliding step but the first (which straddles the limit):
      // the error of that step is below τ_max Δγ / 2.
      EXPECT_NEAR(dissipated, tau_max * slip, 0.5 * tau_max * dgamma) << "step " << i;
    }
    EXPECT_NEAR(s[0][1], mu * p_d, 1e-12 * tau_max); // (F1) with equality
  }

  TEST(CollapsedLayerFriction, CycleWorkEqualsStoredPlusDissipated)
  {
    // Load, reverse past the opposite limit, unload partly, with the pressure varying: the
    // trapezoidal work Σ ½ (s_n + s_n+1) : Δε equals the stored energy plus the dissipation to
    // round-off, and the dissipation never decreases.
    const CollapsedFrictionParameters f = parameters();
    SymmetricTensor<2, 3> s, strain_step;
    double work = 0, dissipated = 0;
    const int n = 900;
    for (int i = 0; i < n; ++i)
    {
      const double dgamma = i < 300 ? 2e-5 : (i < 700 ? -3e-5 : 1e-5);
      strain_step = shear(dgamma);
      strain_step[0][0] = 1e-6 * std::sin(0.01 * i); // a stretch as well, and shear across the plane
      strain_step[1][2] = 5e-6 * std::cos(0.013 * i);
      const double pressure = p_d * (1 + 0.3 * std::sin(0.02 * i));
      const CollapsedFrictionUpdate u = update_collapsed_friction(f, 1, s, strain_step, pressure, no_gradient, false);
      work += 0.5 * ((s + u.stress) * strain_step);
      EXPECT_GE(u.dissipation, -1e-12 * mu * p_d * 3e-5) << "step " << i;
      dissipated += u.dissipation;
      s = u.stress;
    }
    const double stored = friction_energy_density(f, s);
    EXPECT_GT(dissipated, 0);
    EXPECT_NEAR(work, stored + dissipated, 1e-12 * (std::abs(work) + dissipated));
  }

  TEST(CollapsedLayerFriction, UniaxialCompactionIsNotSlip)
  {
    // The compaction of a collapsing layer (ε_nn only, laterally confined) has a deviatoric part,
    // but no layer-plane shear: it must leave the friction, and its capacity, untouched.
    const CollapsedFrictionParameters f = parameters();
    const SymmetricTensor<2, 3> s_n = update_collapsed_friction(f, 1, {}, shear(1e-3), p_d, no_gradient, false).stress;
    SymmetricTensor<2, 3> compaction;
    compaction[1][1] = -1e-3;
    const CollapsedFrictionUpdate u = update_collapsed_friction(f, 1, s_n, compaction, p_d + K_d * 1e-3, no_gradient, false);
    EXPECT_EQ((u.stress - s_n).norm(), 0);
    EXPECT_FALSE(u.sliding);
    EXPECT_EQ(u.dissipation, 0);
  }

  TEST(CollapsedLayerFriction, ReleasedWhenTheFacesSeparate)
  {
    const CollapsedFrictionParameters f = parameters();
    const CollapsedFrictionUpdate loaded = update_collapsed_friction(f, 1, {}, shear(1e-3), p_d, no_gradient, false);
    ASSERT_GT(loaded.stress.norm(), 0);
    const CollapsedFrictionUpdate open = update_collapsed_friction(f, 1, loaded.stress, shear(0), 0, no_gradient, true);
    EXPECT_EQ(open.stress.norm(), 0);
    EXPECT_EQ(open.tangent.norm(), 0);
    // The stored energy is dissipated on release.
    EXPECT_NEAR(open.dissipation, friction_energy_density(f, loaded.stress), 1e-12 * p_d);
  }

  TEST(CollapsedLayerFriction, TangentMatchesCentralDifferences)
  {
    // s(ε) = update(s_n, ε − ε_n, σ_n(ε)) with σ_n = K_d ⟨−tr ε − ε_d⟩ − a ε_yy + b ε_yz, whose
    // gradient ∂σ_n/∂ε the caller passes: the tangent includes dk/dε = μ ∂σ_n/∂ε when sliding,
    // on the diagonal and off it. Central differences with h = 1e-8 of strains ~1e-3 have a
    // truncation error ~h² |s'''| and round-off ~ε |s| / h ~ 1e-8 relative: 1e-5 relative of the
    // tangent's norm is far above both and far below any wrong term (e.g. the missing dk/dε).
    const CollapsedFrictionParameters f = parameters();
    const double e_d = 0.2;
    const double a = 1e3, b = 0.2e6; // small beside K_d (the case stays near the limit), large beside the tolerance
    auto pressure = [&](const SymmetricTensor<2, 3> &e) {
      return K_d * std::max(-dealii::trace(e) - e_d, 0.) - a * e[1][1] + b * e[1][2];
    };
    // ∂σ_n/∂ε as a symmetric tensor g with dσ_n = g : dε (an off-diagonal entry counts twice).
    SymmetricTensor<2, 3> gradient = -K_d * dealii::unit_symmetric_tensor<3>();
    gradient[1][1] -= a;
    gradient[1][2] += b / 2;
    SymmetricTensor<2, 3> strain_n;
    strain_n[1][1] = -(e_d + p_d / K_d);
    const SymmetricTensor<2, 3> s_n = update_collapsed_friction(f, 1, {}, shear(1e-3), p_d, no_gradient, false).stress;
    struct Case
    {
      const char *name;
      double dgamma;
      bool sliding;
    } cases[] = {{"stick", -1e-4, false}, {"slide", 5e-3, true}};
    for (const Case &c : cases)
    {
      SymmetricTensor<2, 3> strain = strain_n + shear(c.dgamma);
      strain[0][0] += 2e-5; // a general state: not only simple shear in x
      strain[2][2] -= 1e-5;
      strain[1][2] += 4e-4;
      const CollapsedFrictionUpdate u = update_collapsed_friction(f, 1, s_n, strain - strain_n, pressure(strain), gradient, true);
      ASSERT_EQ(u.sliding, c.sliding) << c.name;
      const double h = 1e-8;
      double largest_error = 0;
      for (unsigned int k = 0; k < 3; ++k)
        for (unsigned int l = k; l < 3; ++l)
        {
          SymmetricTensor<2, 3> dp = strain, dm = strain;
          // A symmetric perturbation of component (k, l): both ε_kl and ε_lk move by h.
          dp[k][l] += h;
          dm[k][l] -= h;
          const SymmetricTensor<2, 3> difference =
            (update_collapsed_friction(f, 1, s_n, dp - strain_n, pressure(dp), no_gradient, false).stress -
             update_collapsed_friction(f, 1, s_n, dm - strain_n, pressure(dm), no_gradient, false).stress) /
            (2 * h);
          for (unsigned int i = 0; i < 3; ++i)
            for (unsigned int j = i; j < 3; ++j)
            {
              // dσ_ij = C_ijkl dε_kl + C_ijlk dε_lk = (k == l ? 1 : 2) C_ijkl h
              const double analytic = (k == l ? 1. : 2.) * u.tangent[i][j][k][l];
              largest_error = std::max(largest_error, std::abs(analytic - difference[i][j]));
            }
        }
      EXPECT_LT(largest_error, 1e-5 * u.tangent.norm()) << c.name;
    }
  }

  TEST(CollapsedLayerFriction, BadParametersAreRefusedNamingThem)
  {
    struct Case
    {
      double mu, K, G, K_d;
      const char *name;
    } cases[] = {{-0.1, K, G, K_d, "friction coefficient"}, {2.5, K, G, K_d, "friction coefficient"},
                 {NAN, K, G, K_d, "friction coefficient"},  {mu, 0, G, K_d, "bulk modulus"},
                 {mu, K, -1, K_d, "shear modulus"},         {mu, K, G, -1, "lock-up modulus"}};
    for (const Case &c : cases)
    {
      try
      {
        CollapsedFrictionParameters::of_layer(c.mu, c.K, c.G, c.K_d);
        ADD_FAILURE() << c.name << " accepted";
      }
      catch (const std::invalid_argument &e)
      {
        EXPECT_NE(std::string(e.what()).find(c.name), std::string::npos) << e.what();
      }
    }
  }
} // namespace
