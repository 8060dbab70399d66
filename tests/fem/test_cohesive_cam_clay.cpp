// Tests of fem/material/cohesive_cam_clay: the cohesive Cam-Clay material point (docs/physics.md §2). Strength
// tips and the peak shear against the closed forms of the surface, one return against the docs/physics.md
// formulas for q(Δγ) and p(Δγ), the hardening laws against the hydrostatic closed form, consistency
// over random strain paths, the tangent against central differences, plane strain against rotated 3D
// strains, extreme parameters and parameter checks.
//
// Units: K = 1 MPa, G = 0.6 MPa (E = 1.5 MPa, ν = 0.25), p0 = 10 kPa, so the elastic range of strain
// is p0/K = 1e-2. Stresses are compared relative to p0 (or M² p0² for y).
#include "fem/material/cohesive_cam_clay.h"
#include "tests/fem/cam_clay_test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace
{
  using namespace anticrack::fem;
  using namespace anticrack::fem::test_support;
  using dealii::SymmetricTensor;

  /// Round-off tolerance for stresses relative to p0 after a few dozen operations and a local solve
  /// converged to ~1e-14 relative: 1e-12 leaves a margin and still catches any formula error.
  constexpr double round_off = 1e-12;

  /// Consistency tolerance for y/(M² p0²) asked of the return mapping; the solver reaches ~1e-14.
  constexpr double yield_tolerance = 1e-10;

  CamClayParameters parameters(double beta, double xi, HardeningLaw law = HardeningLaw::signed_volumetric)
  {
    CamClayParameters m;
    m.bulk_modulus = 1e6;
    m.shear_modulus = 0.6e6;
    m.M = 0.8;
    m.beta = beta;
    m.p0_initial = 1e4;
    m.hardening_factor = xi;
    m.p0_floor = 100;
    m.law = law;
    return m;
  }


  double q_max(const CamClayParameters &m, double p0)
  {
    return m.M * p0 * (1 + m.beta) / (2 * std::sqrt(1 + 2 * m.beta));
  }

  /// y / (M² p0²) at the stress and p0 of an update.
  double relative_yield(const CamClayUpdate &u, const CamClayParameters &m)
  {
    const double p0 = u.state.p0;
    return yield_function(mean_pressure(u.stress), von_mises(u.stress), p0, m) / (m.M * m.M * p0 * p0);
  }

  bool finite(const SymmetricTensor<2, 3> &t)
  {
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        if (!std::isfinite(t[i][j]))
          return false;
    return true;
  }


  /// Q t Qᵀ for a rotation Q.
  SymmetricTensor<2, 3> rotate(const SymmetricTensor<2, 3> &t, const dealii::Tensor<2, 3> &Q)
  {
    SymmetricTensor<2, 3> r;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = 0; l < 3; ++l)
            r[i][j] += Q[i][k] * t[k][l] * Q[j][l];
    return r;
  }

  /// Rotation by `angle` about the unit vector `axis` (Rodrigues).
  dealii::Tensor<2, 3> rotation(dealii::Tensor<1, 3> axis, double angle)
  {
    axis /= axis.norm();
    dealii::Tensor<2, 3> Q;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        Q[i][j] = (i == j ? std::cos(angle) : 0) + (1 - std::cos(angle)) * axis[i] * axis[j];
    Q[0][1] -= std::sin(angle) * axis[2];
    Q[1][0] += std::sin(angle) * axis[2];
    Q[0][2] += std::sin(angle) * axis[1];
    Q[2][0] -= std::sin(angle) * axis[1];
    Q[1][2] -= std::sin(angle) * axis[0];
    Q[2][1] += std::sin(angle) * axis[0];
    return Q;
  }

  /// Drives a material point along strains[0], strains[1], ... and returns the updates.
  std::vector<CamClayUpdate> drive(const CamClayParameters &m, const std::vector<SymmetricTensor<2, 3>> &strains)
  {
    std::vector<CamClayUpdate> updates;
    CamClayState state = CamClayState::initial(m);
    for (const auto &strain : strains)
      {
        updates.push_back(update_stress(m, state, strain));
        state = updates.back().state;
      }
    return updates;
  }


  // ---------------------------------------------------------------------------------------------
  // Parameters

  TEST(CamClayParameters, ElasticModuliFromYoungsModulusAndPoissonRatio)
  {
    CamClayParameters m;
    m.set_elastic_moduli(1.5e6, 0.25);
    // K = E/(3(1 − 2ν)) = 1.5e6/1.5, G = E/(2(1 + ν)) = 1.5e6/2.5.
    EXPECT_NEAR(m.bulk_modulus, 1e6, 1e6 * round_off);
    EXPECT_NEAR(m.shear_modulus, 0.6e6, 0.6e6 * round_off);
    EXPECT_NE(invalid_argument_message([&] { m.set_elastic_moduli(1e6, 0.5); }).find("Poisson"), std::string::npos);
    EXPECT_NE(invalid_argument_message([&] { m.set_elastic_moduli(-1, 0.2); }).find("Young"), std::string::npos);
  }

  TEST(CamClayParameters, BadValuesAreRejectedNamingTheParameter)
  {
    EXPECT_NO_THROW(parameters(0.3, 5).check());
    const struct
    {
      std::string name;
      std::function<void(CamClayParameters &)> spoil;
    } cases[] = {
      {"bulk_modulus", [](CamClayParameters &m) { m.bulk_modulus = 0; }},
      {"shear_modulus", [](CamClayParameters &m) { m.shear_modulus = -1; }},
      {"shear_modulus", [](CamClayParameters &m) { m.shear_modulus = std::nan(""); }},
      {"'M'", [](CamClayParameters &m) { m.M = 0; }},
      {"beta", [](CamClayParameters &m) { m.beta = -0.1; }},
      {"beta", [](CamClayParameters &m) { m.beta = 1.5; }},
      {"p0_floor", [](CamClayParameters &m) { m.p0_floor = 0; }},
      {"p0_initial", [](CamClayParameters &m) { m.p0_initial = 50; }}, // below the floor
      {"p0_initial", [](CamClayParameters &m) { m.p0_initial = 1e30; }}, // beyond K sinh(50)
      {"hardening_factor", [](CamClayParameters &m) { m.hardening_factor = -1; }},
      {"hardening_factor", [](CamClayParameters &m) { m.hardening_factor = INFINITY; }},
      {"law", [](CamClayParameters &m) { m.law = static_cast<HardeningLaw>(7); }},
      {"max_iterations", [](CamClayParameters &m) { m.max_iterations = 0; }},
      {"max_substeps", [](CamClayParameters &m) { m.max_substeps = 0; }},
    };
    for (const auto &c : cases)
      {
        CamClayParameters m = parameters(0.3, 5);
        c.spoil(m);
        const std::string message = invalid_argument_message([&] { m.check(); });
        EXPECT_NE(message.find(c.name), std::string::npos) << c.name << ": '" << message << "'";
        // The initial state refuses the same parameters.
        EXPECT_THROW(CamClayState::initial(m), std::invalid_argument) << c.name;
      }
  }

  // ---------------------------------------------------------------------------------------------
  // Helpers and the elastic branch

  TEST(CamClayInvariants, MeanPressureAndVonMisesOfSimpleStates)
  {
    // Uniaxial tension σ_xx = 3: p = −1, q = 3; pure shear σ_xy = 1: p = 0, q = sqrt(3).
    SymmetricTensor<2, 3> uniaxial;
    uniaxial[0][0] = 3;
    EXPECT_NEAR(mean_pressure(uniaxial), -1, round_off);
    EXPECT_NEAR(von_mises(uniaxial), 3, round_off);
    SymmetricTensor<2, 3> shear;
    shear[0][1] = 1;
    EXPECT_NEAR(mean_pressure(shear), 0, round_off);
    EXPECT_NEAR(von_mises(shear), std::sqrt(3.0), round_off);
    // The tips and the apex of the surface.
    const CamClayParameters m = parameters(0.3, 0);
    const double scale = m.M * m.M * 1e8; // M² p0²
    EXPECT_NEAR(yield_function(1e4, 0, 1e4, m), 0, round_off * scale);
    EXPECT_NEAR(yield_function(-3e3, 0, 1e4, m), 0, round_off * scale);
    EXPECT_NEAR(yield_function(0.35e4, q_max(m, 1e4), 1e4, m), 0, round_off * scale);
    EXPECT_LT(yield_function(0.35e4, 0.99 * q_max(m, 1e4), 1e4, m), -1e-3 * scale);
    EXPECT_GT(yield_function(1.01e4, 0, 1e4, m), 1e-3 * scale);
  }

  TEST(CamClayStrength, LayerPlaneShearStrengthIsWhereTheConfinedPointFirstYields)
  {
    // A laterally confined point (ε_xx = ε_yy = ε_xy = 0) under the layer-plane traction: its
    // lateral stress ratio follows from Hooke's law, and the shear strain that makes σ_xz equal
    // layer_plane_shear_strength(σ) puts the elastic stress on the surface (y = 0 to round-off),
    // while 0.1 % less stays elastic and 0.1 % more yields, for normal stresses across the surface.
    const CamClayParameters m = parameters(0.3, 0);
    const double nu = (3 * m.bulk_modulus - 2 * m.shear_modulus) / (2 * (3 * m.bulk_modulus + m.shear_modulus));
    const double k = nu / (1 - nu);
    const CamClayState initial = CamClayState::initial(m);
    const double constrained = m.bulk_modulus + 4 * m.shear_modulus / 3;
    for (const double sigma : {-2e3, 0.0, 2e3, 3.5e3, 5e3, 6e3})
    {
      const double tau_p = layer_plane_shear_strength(sigma, k, 1e4, m);
      ASSERT_TRUE(std::isfinite(tau_p)) << "sigma = " << sigma;
      const auto strain = [&](const double shear_scale) {
        SymmetricTensor<2, 3> e;
        e[2][2] = -sigma / constrained;
        e[0][2] = shear_scale * tau_p / (2 * m.shear_modulus);
        return e;
      };
      const CamClayUpdate on = update_stress(m, initial, strain(0.999));
      EXPECT_NEAR(on.stress[0][0], k * on.stress[2][2], round_off * 1e4);
      EXPECT_NEAR(-on.stress[2][2], sigma, round_off * 1e4);
      EXPECT_FALSE(on.plastic) << "sigma = " << sigma;
      EXPECT_TRUE(update_stress(m, initial, strain(1.001)).plastic) << "sigma = " << sigma;
      const SymmetricTensor<2, 3> e = strain(1);
      const SymmetricTensor<2, 3> stress = m.bulk_modulus * dealii::trace(e) * dealii::unit_symmetric_tensor<3>() +
                                           2 * m.shear_modulus * dealii::deviator(e);
      EXPECT_NEAR(yield_function(mean_pressure(stress), von_mises(stress), 1e4, m) / (m.M * m.M * 1e8), 0, 1e-10)
        << "sigma = " << sigma;
    }
    // Free sides (k = 0) at σ = 0: pure shear, q = √3 τ meets the surface at p = 0,
    // (1 + 2β) 3 τ² = M² β p0².
    EXPECT_NEAR(layer_plane_shear_strength(0, 0, 1e4, m), m.M * 1e4 * std::sqrt(m.beta / (3 * (1 + 2 * m.beta))), 1e-8);
    // Beyond the compressive tip of the confined path's image there is no strength.
    EXPECT_TRUE(std::isnan(layer_plane_shear_strength(3e4, k, 1e4, m)));
  }

  TEST(CamClayStrength, LayerPlaneCompressiveStrengthIsWhereTheConfinedPointFirstYieldsInCompression)
  {
    // The laterally confined point compressed along the layer normal alone: the FE's own return
    // mapping stays elastic at 0.999 σ_c and yields at 1.001 σ_c; τ_p vanishes there; the
    // hydrostatic path (k = 1) meets the surface at its tip p0.
    const CamClayParameters m = parameters(0.3, 0);
    const double nu = (3 * m.bulk_modulus - 2 * m.shear_modulus) / (2 * (3 * m.bulk_modulus + m.shear_modulus));
    const double k = nu / (1 - nu), p0 = 1e4;
    const double sigma_c = layer_plane_compressive_strength(k, p0, m);
    const CamClayState initial = CamClayState::initial(m);
    const double constrained = m.bulk_modulus + 4 * m.shear_modulus / 3;
    const auto compressed = [&](const double scale) {
      SymmetricTensor<2, 3> e;
      e[2][2] = -scale * sigma_c / constrained;
      return update_stress(m, initial, e);
    };
    EXPECT_FALSE(compressed(0.999).plastic);
    EXPECT_TRUE(compressed(1.001).plastic);
    EXPECT_NEAR(-compressed(0.999).stress[2][2], 0.999 * sigma_c, round_off * p0);
    // τ_p ∝ √(σ_c − σ) at the root: 1e-12 below it τ_p is ~1e-6 of the surface's size, 1e-9 above none.
    EXPECT_LT(layer_plane_shear_strength(sigma_c * (1 - 1e-12), k, p0, m), 1e-6 * p0);
    EXPECT_TRUE(std::isnan(layer_plane_shear_strength(sigma_c * (1 + 1e-9), k, p0, m)));
    EXPECT_NEAR(layer_plane_compressive_strength(1, p0, m), p0, round_off * p0);
    // The root is written in two forms (B < 0 and B > 0): both meet at β = 1 (B = 0).
    CamClayParameters symmetric = m;
    symmetric.beta = 1;
    const double a = (1 + 2 * k) / 3, A = m.M * m.M * a * a + 3 * (1 - k) * (1 - k);
    EXPECT_NEAR(layer_plane_compressive_strength(k, p0, symmetric), m.M * p0 / std::sqrt(A), round_off * p0);
  }

  TEST(CamClayElastic, StressIsLinearInsideTheSurface)
  {
    const CamClayParameters m = parameters(0.3, 5);
    const CamClayState initial = CamClayState::initial(m);
    EXPECT_NEAR(initial.p0, 1e4, 1e4 * round_off);
    SymmetricTensor<2, 3> strain;
    strain[0][0] = -2e-3;
    strain[1][1] = 1e-3;
    strain[0][1] = 1e-3;
    const CamClayUpdate u = update_stress(m, initial, strain);
    const SymmetricTensor<2, 3> expected = m.bulk_modulus * dealii::trace(strain) * dealii::unit_symmetric_tensor<3>() +
                                           2 * m.shear_modulus * dealii::deviator(strain);
    EXPECT_FALSE(u.plastic);
    EXPECT_EQ(u.iterations, 0u);
    EXPECT_LT(relative_yield(u, m), 0);
    EXPECT_LT((u.stress - expected).norm(), round_off * 1e4);
    EXPECT_EQ(u.state.alpha, initial.alpha);
    EXPECT_EQ(u.state.plastic_strain.norm(), 0);
  }

  // ---------------------------------------------------------------------------------------------
  // Strength of the perfectly plastic surface (ξ = 0)

  TEST(CamClayStrength, HydrostaticCompressionReachesP0AndStays)
  {
    for (const double beta : {0.0, 0.3, 1.0})
      {
        const CamClayParameters m = parameters(beta, 0);
        std::vector<SymmetricTensor<2, 3>> path;
        for (int i = 1; i <= 60; ++i)
          path.push_back(hydrostatic(-i * 0.05 * m.p0_initial / m.bulk_modulus)); // to 3 p0/K
        const auto updates = drive(m, path);
        for (std::size_t i = 0; i < path.size(); ++i)
          {
            const double p_elastic = -m.bulk_modulus * dealii::trace(path[i]);
            const double p = mean_pressure(updates[i].stress);
            EXPECT_NEAR(p, std::min(p_elastic, m.p0_initial), round_off * m.p0_initial)
              << "beta " << beta << " step " << i;
            EXPECT_NEAR(von_mises(updates[i].stress), 0, round_off * m.p0_initial);
            // Elastic below p0 = K e (step i = 19 is on the tip, where round-off decides), plastic after.
            if (i != 19)
              {
                EXPECT_EQ(updates[i].plastic, i > 19) << "beta " << beta << " step " << i;
              }
          }
      }
  }

  TEST(CamClayStrength, HydrostaticTensionReachesMinusBetaP0)
  {
    for (const double beta : {0.0, 0.3, 1.0})
      {
        const CamClayParameters m = parameters(beta, 0);
        std::vector<SymmetricTensor<2, 3>> path;
        for (int i = 1; i <= 40; ++i)
          path.push_back(hydrostatic(i * 0.05 * m.p0_initial / m.bulk_modulus)); // to 2 p0/K
        const auto updates = drive(m, path);
        EXPECT_NEAR(mean_pressure(updates.back().stress), -beta * m.p0_initial, round_off * m.p0_initial) << beta;
        for (const auto &u : updates)
          EXPECT_GE(mean_pressure(u.stress), -beta * m.p0_initial * (1 + round_off)) << beta;
      }
  }

  TEST(CamClayStrength, ShearAtTheCriticalPressureReachesQmax)
  {
    // tr ε = −p_c/K keeps p_tr = p_c; there ∂y/∂p = 0, so the flow is deviatoric and p stays p_c
    // while simple shear ε_xy drives q to q_max and holds it there.
    for (const double beta : {0.0, 0.3, 1.0})
      {
        const CamClayParameters m = parameters(beta, 0);
        const double p_c = 0.5 * (1 - beta) * m.p0_initial;
        std::vector<SymmetricTensor<2, 3>> path;
        for (int i = 1; i <= 50; ++i)
          {
            SymmetricTensor<2, 3> strain = hydrostatic(-p_c / m.bulk_modulus);
            strain[0][1] = i * 2e-4;
            path.push_back(strain);
          }
        const auto updates = drive(m, path);
        for (const auto &u : updates)
          {
            EXPECT_NEAR(mean_pressure(u.stress), p_c, round_off * m.p0_initial);
            EXPECT_LE(von_mises(u.stress), q_max(m, m.p0_initial) * (1 + round_off));
          }
        EXPECT_TRUE(updates.back().plastic);
        EXPECT_NEAR(von_mises(updates.back().stress), q_max(m, m.p0_initial), round_off * m.p0_initial) << beta;
      }
  }

  TEST(CamClayStrength, ShearAtConstantMeanStrainTendsToQmaxAtCriticalPressure)
  {
    // Away from p_c the associative flow changes the volume, which moves p towards p_c at constant
    // total volume; q stays below q_max and approaches it as p -> p_c (critical state).
    const CamClayParameters m = parameters(0.3, 0);
    const double p_c = 0.35 * m.p0_initial;
    for (const double p_start : {0.9 * m.p0_initial, -0.2 * m.p0_initial})
      {
        std::vector<SymmetricTensor<2, 3>> path;
        for (int i = 1; i <= 400; ++i)
          {
            SymmetricTensor<2, 3> strain = hydrostatic(-p_start / m.bulk_modulus);
            strain[0][1] = i * 5e-4;
            path.push_back(strain);
          }
        const auto updates = drive(m, path);
        for (const auto &u : updates)
          EXPECT_LE(von_mises(u.stress), q_max(m, m.p0_initial) * (1 + round_off));
        // 0.2 of simple shear is many elastic ranges: p_c and q_max are reached to 1e-6.
        EXPECT_NEAR(mean_pressure(updates.back().stress), p_c, 1e-6 * m.p0_initial) << p_start;
        EXPECT_NEAR(von_mises(updates.back().stress), q_max(m, m.p0_initial), 1e-6 * m.p0_initial) << p_start;
        EXPECT_NEAR(relative_yield(updates.back(), m), 0, yield_tolerance);
      }
  }

  // ---------------------------------------------------------------------------------------------
  // Return mapping

  TEST(CamClayReturn, OneStepMatchesTheClosedForm)
  {
    // One plastic step from the initial state without hardening: with the returned Δγ, docs/physics.md §2
    // gives q = q_tr/(1 + 6GΔγ(1 + 2β)), p = (p_tr + 2KΔγM² p_c)/(1 + 2KΔγM²); s keeps the direction
    // of s_tr; Δε_p = Δγ ∂y/∂σ; σ = C : (ε − ε_p).
    for (const double beta : {0.0, 0.3, 1.0})
      {
        const CamClayParameters m = parameters(beta, 0);
        const double K = m.bulk_modulus, G = m.shear_modulus, M2 = m.M * m.M, p0 = m.p0_initial;
        SymmetricTensor<2, 3> strain;
        strain[0][0] = -3e-2;
        strain[1][1] = 1e-2;
        strain[0][2] = 1.5e-2;
        const CamClayUpdate u = update_stress(m, CamClayState::initial(m), strain);
        ASSERT_TRUE(u.plastic);
        const double dgamma = u.plastic_multiplier;
        const double p_tr = -K * dealii::trace(strain);
        const SymmetricTensor<2, 3> s_tr = 2 * G * dealii::deviator(strain);
        const double q_tr = std::sqrt(1.5) * s_tr.norm();
        const double p_c = 0.5 * (1 - beta) * p0;
        const double p = (p_tr + 2 * K * dgamma * M2 * p_c) / (1 + 2 * K * dgamma * M2);
        const double q = q_tr / (1 + 6 * G * dgamma * (1 + 2 * beta));
        EXPECT_NEAR(mean_pressure(u.stress), p, round_off * p0) << beta;
        EXPECT_NEAR(von_mises(u.stress), q, round_off * p0) << beta;
        EXPECT_NEAR(relative_yield(u, m), 0, yield_tolerance) << beta;
        const SymmetricTensor<2, 3> s = dealii::deviator(u.stress);
        EXPECT_LT((s / s.norm() - s_tr / s_tr.norm()).norm(), round_off) << beta;
        const SymmetricTensor<2, 3> flow =
          (-2 * M2 * (p - p_c) / 3) * dealii::unit_symmetric_tensor<3>() + (3 * (1 + 2 * beta)) * s;
        EXPECT_LT((u.state.plastic_strain - dgamma * flow).norm(), round_off * p0 / K) << beta;
        const SymmetricTensor<2, 3> elastic = strain - u.state.plastic_strain;
        const SymmetricTensor<2, 3> sigma =
          K * dealii::trace(elastic) * dealii::unit_symmetric_tensor<3>() + 2 * G * dealii::deviator(elastic);
        EXPECT_LT((u.stress - sigma).norm(), round_off * p0) << beta;
        EXPECT_EQ(u.substeps, 1u);
      }
  }

  TEST(CamClayReturn, RandomIncrementsEndOnOrInsideTheSurface)
  {
    // 1000 random increments for each law and β: 50 random walks of 20 increments from the initial
    // state (restarting keeps p0 away from the floor, where hardening is inactive), increments of
    // 0.3 elastic ranges per component (most steps are plastic). ξ = 5 for the signed law; ξ = 0.5
    // for the collapse law, which with ξ = 5 falls to the floor at the first compaction
    // (CollapseCompactionLowersP0; covered by CamClayExtreme). After every update: finite, y <= 0
    // (= 0 if plastic) to 1e-10 M² p0², p0 = p0(α) >= floor, α evolving by its law.
    std::mt19937_64 engine(20240611);
    for (const HardeningLaw law : {HardeningLaw::signed_volumetric, HardeningLaw::collapse})
      for (const double beta : {0.0, 0.3, 1.0})
        {
          const CamClayParameters m = parameters(beta, law == HardeningLaw::collapse ? 0.5 : 5, law);
          CamClayState state;
          unsigned int plastic = 0, hardening = 0;
          for (int i = 0; i < 1000; ++i)
            {
              if (i % 20 == 0)
                state = CamClayState::initial(m);
              const SymmetricTensor<2, 3> strain =
                state.strain + random_tensor(engine, 0.3 * m.p0_initial / m.bulk_modulus);
              const CamClayUpdate u = update_stress(m, state, strain);
              ASSERT_TRUE(finite(u.stress) && finite(u.state.plastic_strain) && std::isfinite(u.state.alpha));
              const double y = relative_yield(u, m);
              EXPECT_LE(y, yield_tolerance);
              if (u.plastic)
                {
                  ++plastic;
                  hardening += u.state.p0 != state.p0 && u.state.p0 > m.p0_floor;
                  EXPECT_NEAR(y, 0, yield_tolerance) << "step " << i;
                }
              EXPECT_GE(u.state.p0, m.p0_floor);
              EXPECT_EQ(u.state.p0, hardening_p0(u.state.alpha, m));
              const double volumetric = dealii::trace(u.state.plastic_strain - state.plastic_strain);
              const double expected_alpha =
                state.alpha + (law == HardeningLaw::collapse ? std::abs(volumetric) : volumetric);
              // α and tr ε_p are sums of O(1e-2) terms: 1e-14 absolute is round-off.
              EXPECT_NEAR(u.state.alpha, expected_alpha, 1e-14 + 1e-12 * std::abs(volumetric)) << "step " << i;
              state = u.state;
            }
          EXPECT_GT(plastic, 200u) << "too few plastic steps to test the return";
          EXPECT_GT(hardening, 200u) << "too few plastic steps that change p0 above the floor";
        }
  }

  TEST(CamClayReturn, NonFiniteStrainThrows)
  {
    const CamClayParameters m = parameters(0.3, 5);
    SymmetricTensor<2, 3> strain;
    strain[1][2] = std::nan("");
    EXPECT_THROW(update_stress(m, CamClayState::initial(m), strain), ReturnMappingError);
  }

  TEST(CamClayReturn, SubsteppingRecoversFromATightIterationBudget)
  {
    // A large compaction-and-shear step with hardening needs several Newton iterations (up to 6 per
    // scalar solve here). With only five it fails in one step and succeeds in sub-steps, which start
    // closer to the surface; the result is still on
    // the surface and close to the one-step result (backward Euler over a shorter step). With one
    // iteration and no sub-steps allowed it fails with the trial state in the message.
    CamClayParameters m = parameters(0.3, 5);
    SymmetricTensor<2, 3> strain = hydrostatic(-3e-2);
    strain[0][1] = 2e-2;
    const CamClayUpdate one_step = update_stress(m, CamClayState::initial(m), strain);
    EXPECT_EQ(one_step.substeps, 1u);
    m.max_iterations = 5;
    const CamClayUpdate substepped = update_stress(m, CamClayState::initial(m), strain);
    EXPECT_GT(substepped.substeps, 1u);
    EXPECT_NEAR(relative_yield(substepped, m), 0, yield_tolerance);
    // Sub-stepping changes the integration of the hardening path: within 10 % of p0 here.
    EXPECT_NEAR(substepped.state.p0, one_step.state.p0, 0.1 * one_step.state.p0);
    m.max_iterations = 1;
    m.max_substeps = 1;
    try
      {
        update_stress(m, CamClayState::initial(m), strain);
        ADD_FAILURE() << "no ReturnMappingError";
      }
    catch (const ReturnMappingError &e)
      {
        EXPECT_NE(std::string(e.what()).find("trial p"), std::string::npos) << e.what();
      }
  }

  // ---------------------------------------------------------------------------------------------
  // Hardening laws

  TEST(CamClayHardening, SignedCompactionRaisesP0ByTheClosedForm)
  {
    // Hydrostatic compaction stays at the tip p = p0(α), α = α_0 + tr ε_p, so the backward-Euler
    // result is exact and path independent: tr ε = −p/K + tr ε_p with tr ε_p = −asinh(p/K)/ξ − α_0.
    const CamClayParameters m = parameters(0.3, 5);
    const CamClayState initial = CamClayState::initial(m);
    const double K = m.bulk_modulus, xi = m.hardening_factor;
    std::vector<SymmetricTensor<2, 3>> path;
    for (int i = 1; i <= 100; ++i)
      path.push_back(hydrostatic(-i * 1e-3));
    const auto updates = drive(m, path);
    double previous_p0 = initial.p0;
    for (std::size_t i = 0; i < path.size(); ++i)
      {
        const CamClayUpdate &u = updates[i];
        const double p = mean_pressure(u.stress);
        EXPECT_GE(u.state.p0, previous_p0);
        previous_p0 = u.state.p0;
        if (!u.plastic)
          continue;
        EXPECT_NEAR(p, u.state.p0, round_off * u.state.p0);
        EXPECT_NEAR(u.state.p0, K * std::sinh(-xi * u.state.alpha), round_off * u.state.p0);
        EXPECT_NEAR(u.state.alpha - initial.alpha, dealii::trace(u.state.plastic_strain), 1e-14);
        const double closed_form = -p / K - std::asinh(p / K) / xi - initial.alpha;
        EXPECT_NEAR(dealii::trace(path[i]), closed_form, 1e-13) << "step " << i;
      }
    EXPECT_GT(updates.back().state.p0, 5 * m.p0_initial);
    // One step to the end gives the same state.
    const CamClayUpdate direct = update_stress(m, initial, path.back());
    EXPECT_NEAR(direct.state.p0, updates.back().state.p0, round_off * direct.state.p0);
  }

  TEST(CamClayHardening, SignedDilationSoftensToTheFloor)
  {
    const CamClayParameters m = parameters(0.3, 5);
    std::vector<SymmetricTensor<2, 3>> path;
    for (int i = 1; i <= 100; ++i)
      path.push_back(hydrostatic(i * 2e-3));
    const auto updates = drive(m, path);
    double previous_p0 = m.p0_initial;
    for (const auto &u : updates)
      {
        EXPECT_LE(u.state.p0, previous_p0);
        EXPECT_GE(u.state.p0, m.p0_floor);
        previous_p0 = u.state.p0;
        EXPECT_GE(mean_pressure(u.stress), -m.beta * u.state.p0 - round_off * m.p0_initial);
      }
    EXPECT_EQ(updates.back().state.p0, m.p0_floor);
    EXPECT_NEAR(mean_pressure(updates.back().stress), -m.beta * m.p0_floor, round_off * m.p0_initial);
  }

  TEST(CamClayHardening, CollapseCompactionLowersP0)
  {
    // Collapse law: α = α_0 + |tr ε_p| rises towards 0 under compaction, so p0 = K sinh(−ξ α) falls.
    // With ξ cosh(ξ α) < 1 (ξ = 0.5) the hydrostatic response is stable: p = p0 along the path, down to
    // the floor, where it stays.
    {
      const CamClayParameters m = parameters(0.3, 0.5, HardeningLaw::collapse);
      const CamClayState initial = CamClayState::initial(m);
      std::vector<SymmetricTensor<2, 3>> path;
      for (int i = 1; i <= 100; ++i)
        path.push_back(hydrostatic(-i * 2e-3));
      const auto updates = drive(m, path);
      double previous_p0 = initial.p0;
      for (const auto &u : updates)
        {
          EXPECT_LE(u.state.p0, previous_p0);
          EXPECT_GE(u.state.p0, m.p0_floor);
          previous_p0 = u.state.p0;
          if (!u.plastic)
            continue;
          EXPECT_NEAR(mean_pressure(u.stress), u.state.p0, round_off * m.p0_initial);
          EXPECT_LE(dealii::trace(u.state.plastic_strain), 0);
          EXPECT_NEAR(u.state.alpha - initial.alpha, -dealii::trace(u.state.plastic_strain), 1e-14);
          EXPECT_NEAR(u.state.p0, std::max(m.bulk_modulus * std::sinh(-m.hardening_factor * u.state.alpha), m.p0_floor),
                      round_off * m.p0_initial);
        }
      EXPECT_LT(updates[30].state.p0, 0.9 * m.p0_initial);
      EXPECT_EQ(updates.back().state.p0, m.p0_floor);
    }
    // With ξ = 5 (ξ cosh > 1) collapse feeds itself: the first plastic step collapses to the floor.
    {
      const CamClayParameters m = parameters(0.3, 5, HardeningLaw::collapse);
      const auto updates = drive(m, {hydrostatic(-0.9e-2), hydrostatic(-1.1e-2)});
      EXPECT_FALSE(updates[0].plastic);
      EXPECT_TRUE(updates[1].plastic);
      EXPECT_EQ(updates[1].state.p0, m.p0_floor);
      EXPECT_NEAR(mean_pressure(updates[1].stress), m.p0_floor, round_off * m.p0_initial);
    }
  }

  TEST(CamClayHardening, CollapseDilationAlsoSoftens)
  {
    const CamClayParameters m = parameters(0.3, 5, HardeningLaw::collapse);
    const auto updates = drive(m, {hydrostatic(4e-3), hydrostatic(6e-3)});
    ASSERT_TRUE(updates[1].plastic);
    EXPECT_GT(dealii::trace(updates[1].state.plastic_strain), 0);
    EXPECT_LT(updates[1].state.p0, m.p0_initial);
    EXPECT_NEAR(relative_yield(updates[1], m), 0, yield_tolerance);
  }

  // ---------------------------------------------------------------------------------------------
  // Consistent tangent

  /// ‖C_fd − C‖ / ‖C‖ over the 6×6 components, C_fd by central differences of update_stress with a
  /// step of 1e-5 elastic ranges: truncation ~(1e-5)² relative, round-off ~1e-14 p0 / (1e-5 p0/K · K)
  /// = 1e-9, both well below the 1e-6 asked for.
  double tangent_error(const CamClayParameters &m, const CamClayState &previous, const SymmetricTensor<2, 3> &strain,
                       unsigned int *substeps = nullptr)
  {
    const CamClayTangentUpdate t = update_stress_and_tangent(m, previous, strain);
    const CamClayUpdate u = update_stress(m, previous, strain);
    EXPECT_EQ((t.update.stress - u.stress).norm(), 0) << "the tangent update differs from update_stress";
    if (substeps)
      *substeps = t.update.substeps;
    return central_difference_error(m, previous, strain, t.tangent, 1e-5 * m.p0_initial / m.bulk_modulus);
  }

  TEST(CamClayTangent, MatchesCentralDifferences)
  {
    SymmetricTensor<2, 3> mixed;
    mixed[0][0] = -1.5e-2;
    mixed[1][1] = 0.4e-2;
    mixed[0][1] = 0.8e-2;
    mixed[1][2] = -0.3e-2;
    SymmetricTensor<2, 3> dilating = mixed;
    dilating[0][0] = 0.6e-2;
    dilating[2][2] = 0.6e-2;
    struct Case
    {
      std::string name;
      CamClayParameters m;
      SymmetricTensor<2, 3> strain;
    };
    const std::vector<Case> cases = {
      {"elastic", parameters(0.3, 5), 0.1 * mixed},
      {"plastic, no hardening", parameters(0.3, 0), mixed},
      {"plastic, no hardening, beta 0", parameters(0, 0), mixed},
      {"plastic, no hardening, beta 1, dilating", parameters(1, 0), dilating},
      {"hydrostatic (s_tr = 0), no hardening", parameters(0.3, 0), hydrostatic(-2e-2)},
      {"signed law, compaction", parameters(0.3, 5), mixed},
      {"signed law, dilation", parameters(0.3, 5), dilating},
      {"signed law, hydrostatic", parameters(0.3, 5), hydrostatic(-2e-2)},
      {"collapse law, compaction", parameters(0.3, 0.5, HardeningLaw::collapse), mixed},
      {"collapse law, dilation", parameters(0.3, 5, HardeningLaw::collapse), dilating},
      {"collapse law at the floor", parameters(0.3, 5, HardeningLaw::collapse), 3 * mixed},
    };
    for (const auto &c : cases)
      {
        const CamClayState initial = CamClayState::initial(c.m);
        // From the initial state, and from a plastic state reached before (ε_p,n ≠ 0, α_n ≠ α_0).
        EXPECT_LT(tangent_error(c.m, initial, c.strain), 1e-6) << c.name;
        const CamClayUpdate before = update_stress(c.m, initial, 0.7 * c.strain + 0.5 * hydrostatic(-1e-2));
        EXPECT_LT(tangent_error(c.m, before.state, c.strain), 1e-6) << c.name << ", second step";
      }
    // The cases are what their names say.
    EXPECT_FALSE(update_stress(cases[0].m, CamClayState::initial(cases[0].m), cases[0].strain).plastic);
    for (std::size_t i = 1; i < cases.size(); ++i)
      EXPECT_TRUE(update_stress(cases[i].m, CamClayState::initial(cases[i].m), cases[i].strain).plastic)
        << cases[i].name;
    const CamClayParameters &floor = cases.back().m;
    EXPECT_EQ(update_stress(floor, CamClayState::initial(floor), cases.back().strain).state.p0, floor.p0_floor);
  }

  TEST(CamClayTangent, MatchesCentralDifferencesThroughSubsteps)
  {
    CamClayParameters m = parameters(0.3, 5);
    m.max_iterations = 5; // forces sub-steps (see SubsteppingRecoversFromATightIterationBudget)
    SymmetricTensor<2, 3> strain = hydrostatic(-3e-2);
    strain[0][1] = 2e-2;
    unsigned int substeps = 0;
    EXPECT_LT(tangent_error(m, CamClayState::initial(m), strain, &substeps), 1e-6);
    EXPECT_GT(substeps, 1u);
    // From a state on the surface, so that the first sub-step is plastic too.
    const CamClayUpdate before = update_stress(m, CamClayState::initial(m), 0.5 * strain);
    ASSERT_TRUE(before.plastic);
    EXPECT_LT(tangent_error(m, before.state, 1.5 * strain, &substeps), 1e-6);
    EXPECT_GT(substeps, 1u);
  }

  TEST(CamClayTangent, IsSymmetricWithoutHardeningOnly)
  {
    // Associative perfect plasticity has a major-symmetric algorithmic tangent; hardening breaks it
    // (docs/physics.md §2). A sign or factor error in the coupling terms breaks the first property.
    SymmetricTensor<2, 3> strain;
    strain[0][0] = -2e-2;
    strain[1][1] = 0.5e-2;
    strain[0][2] = 1e-2;
    const auto asymmetry = [&](const CamClayParameters &m) {
      const SymmetricTensor<4, 3> C = update_stress_and_tangent(m, CamClayState::initial(m), strain).tangent;
      double difference = 0, norm = 0;
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < 3; ++j)
          for (unsigned int k = 0; k < 3; ++k)
            for (unsigned int l = 0; l < 3; ++l)
              {
                difference += std::pow(C[i][j][k][l] - C[k][l][i][j], 2);
                norm += std::pow(C[i][j][k][l], 2);
              }
      return std::sqrt(difference / norm);
    };
    EXPECT_LT(asymmetry(parameters(0.3, 0)), round_off);
    EXPECT_GT(asymmetry(parameters(0.3, 5)), 1e-3);
  }

  // ---------------------------------------------------------------------------------------------
  // Plane strain

  TEST(CamClayPlaneStrain, IsA3DStrainOfThatShape)
  {
    // A random plane-strain path: no out-of-plane shear stress or plastic strain appears, σ_zz is the
    // elastic out-of-plane stress of ε_e,zz = −ε_p,zz, the full 3D (p, q) is on the surface, and the
    // same path seen in a rotated 3D frame (where it is not plane) gives the rotated stresses.
    std::mt19937_64 engine(7);
    std::normal_distribution<double> normal(0, 0.4e-2);
    const dealii::Tensor<2, 3> Q = rotation(dealii::Tensor<1, 3>({1.0, -2.0, 0.5}), 0.7);
    for (const HardeningLaw law : {HardeningLaw::signed_volumetric, HardeningLaw::collapse})
      {
        const CamClayParameters m = parameters(0.3, 5, law);
        CamClayState plane = CamClayState::initial(m);
        CamClayState rotated = plane;
        unsigned int plastic = 0;
        SymmetricTensor<2, 2> strain_2d;
        for (int i = 0; i < 200; ++i)
          {
            for (unsigned int a = 0; a < 2; ++a)
              for (unsigned int b = a; b < 2; ++b)
                strain_2d[a][b] += normal(engine);
            const CamClayUpdate u = update_stress(m, plane, plane_strain(strain_2d));
            const CamClayUpdate r = update_stress(m, rotated, rotate(plane_strain(strain_2d), Q));
            plane = u.state;
            rotated = r.state;
            EXPECT_EQ(u.stress[0][2], 0);
            EXPECT_EQ(u.stress[1][2], 0);
            EXPECT_EQ(u.state.plastic_strain[0][2], 0);
            EXPECT_EQ(u.state.plastic_strain[1][2], 0);
            const SymmetricTensor<2, 3> elastic = u.state.strain - u.state.plastic_strain;
            const double sigma_zz = m.bulk_modulus * dealii::trace(elastic) +
                                    2 * m.shear_modulus * (elastic[2][2] - dealii::trace(elastic) / 3);
            EXPECT_NEAR(u.stress[2][2], sigma_zz, round_off * m.p0_initial);
            if (u.plastic)
              {
                ++plastic;
                EXPECT_NEAR(relative_yield(u, m), 0, yield_tolerance);
              }
            // Rotation mixes components of size ~p0: round-off ~1e-15 p0 per step accumulates over
            // the path through the state.
            EXPECT_LT((rotate(u.stress, Q) - r.stress).norm(), 1e-10 * m.p0_initial) << "step " << i;
            EXPECT_NEAR(r.state.p0, u.state.p0, 1e-10 * u.state.p0);
          }
        EXPECT_GT(plastic, 40u);
      }
  }

  // ---------------------------------------------------------------------------------------------
  // Extreme parameters

  TEST(CamClayExtreme, ConvergeOrThrowNeverNaN)
  {
    // β = 0 (tensile tip at the origin), β = 1, p0 = 1e-6 K, ξ = 1e3, with random increments of
    // 0.3 elastic ranges and of 1e-2 (many elastic ranges for p0 = 1e-6 K). Every update either
    // returns finite values on or inside the surface or throws ReturnMappingError.
    struct Case
    {
      std::string name;
      CamClayParameters m;
    };
    std::vector<Case> cases;
    for (const HardeningLaw law : {HardeningLaw::signed_volumetric, HardeningLaw::collapse})
      {
        const std::string suffix = law == HardeningLaw::collapse ? ", collapse" : ", signed";
        cases.push_back({"beta 0" + suffix, parameters(0, 5, law)});
        cases.push_back({"beta 1" + suffix, parameters(1, 5, law)});
        CamClayParameters small = parameters(0.3, 5, law);
        small.p0_initial = 1e-6 * small.bulk_modulus;
        small.p0_floor = 1e-9 * small.bulk_modulus;
        cases.push_back({"p0 1e-6 K" + suffix, small});
        cases.push_back({"xi 1e3" + suffix, parameters(0.3, 1e3, law)});
        CamClayParameters all = small;
        all.beta = 0;
        all.hardening_factor = 1e3;
        cases.push_back({"beta 0, p0 1e-6 K, xi 1e3" + suffix, all});
      }
    std::mt19937_64 engine(99);
    for (const auto &c : cases)
      for (const double scale : {0.3 * c.m.p0_initial / c.m.bulk_modulus, 1e-2})
        {
          CamClayState state = CamClayState::initial(c.m);
          unsigned int failures = 0;
          for (int i = 0; i < 300; ++i)
            {
              const SymmetricTensor<2, 3> strain = state.strain + random_tensor(engine, scale);
              try
                {
                  const CamClayUpdate u = update_stress(c.m, state, strain);
                  ASSERT_TRUE(finite(u.stress) && std::isfinite(u.state.alpha) && std::isfinite(u.state.p0)) << c.name;
                  EXPECT_LE(relative_yield(u, c.m), yield_tolerance) << c.name << " step " << i;
                  if (u.plastic)
                    {
                      EXPECT_NEAR(relative_yield(u, c.m), 0, yield_tolerance) << c.name << " step " << i;
                    }
                  EXPECT_GE(u.state.p0, c.m.p0_floor);
                  state = u.state;
                }
              catch (const ReturnMappingError &)
                {
                  ++failures;
                }
            }
          // The safeguarded solves converge in all these cases; a failure would be reported here.
          EXPECT_EQ(failures, 0u) << c.name << ", scale " << scale;
        }
  }
} // namespace
