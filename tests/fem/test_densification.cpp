// Tests of the residual response after collapse in fem/material/cohesive_cam_clay: the residual floor of p0
// and the densification lock-up σ = σ_cc − K_d ⟨−tr ε − ε_d⟩ I (header, "Residual response after
// collapse"). Hydrostatic collapse to the floor and lock-up against the closed form, the Cam-Clay
// history unchanged by the lock-up (bit-for-bit), the tangent against central differences with the
// lock-up engaged, the equilibrium compaction under a large load, the P-wave modulus, parameter
// checks and the residual floor.
//
// Units: the weak layer has K = 0.5 MPa, G = 0.3 MPa, p0 = 1 kPa (elastic range p0/K = 2e-3), the
// residual floor 0.2 p0 = 200 Pa, ε_d = 0.2 and K_d = 1 MPa (of the order of a slab's modulus).
#include "fem/material/cohesive_cam_clay.h"
#include "tests/fem/cam_clay_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
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

  /// Round-off tolerance for stresses relative to the largest stress in play: a few dozen operations
  /// and local solves converged to ~1e-14 relative; 1e-12 leaves a margin and catches formula errors.
  constexpr double round_off = 1e-12;

  /// The material of test_cohesive_cam_clay.cpp: K = 1 MPa, G = 0.6 MPa, p0 = 10 kPa.
  CamClayParameters stiff(double xi, HardeningLaw law)
  {
    CamClayParameters m;
    m.bulk_modulus = 1e6;
    m.shear_modulus = 0.6e6;
    m.M = 0.8;
    m.beta = 0.3;
    m.p0_initial = 1e4;
    m.hardening_factor = xi;
    m.p0_floor = 100;
    m.law = law;
    return m;
  }



  /// Bitwise equality of all components.
  bool identical(const SymmetricTensor<2, 3> &a, const SymmetricTensor<2, 3> &b)
  {
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        if (!(a[i][j] == b[i][j]))
          return false;
    return true;
  }

  bool identical(const SymmetricTensor<4, 3> &a, const SymmetricTensor<4, 3> &b)
  {
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        for (unsigned int k = 0; k < 3; ++k)
          for (unsigned int l = k; l < 3; ++l)
            if (!(a[i][j][k][l] == b[i][j][k][l]))
              return false;
    return true;
  }

  /// The state at the end of a monotonic hydrostatic path from the initial state to tr ε =
  /// `volumetric_strain` in steps of at most 1e-3 (half an elastic range of the weak layer).
  CamClayUpdate hydrostatic_path(const CamClayParameters &m, double volumetric_strain)
  {
    const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(volumetric_strain) / 1e-3)));
    CamClayState state = CamClayState::initial(m);
    CamClayUpdate u;
    for (int i = 1; i <= steps; ++i)
      {
        u = update_stress(m, state, hydrostatic(volumetric_strain * i / steps));
        state = u.state;
      }
    return u;
  }

  /// ‖C_fd − C‖ / ‖C‖ over the 6×6 components with C_fd from central differences of update_stress,
  /// step h = 1e-5 elastic ranges (as in test_cohesive_cam_clay.cpp): truncation ~(1e-5)² relative;
  /// round-off ε |σ| / h with |σ| <= K_d · 0.05 = 5e4 Pa here gives ~1e-11/h/(K + K_d) ~ 1e-9
  /// relative. Also checks that the strain is at least 100 h beyond ε_d (the kink of the lock-up
  /// is not straddled) and that the two updates agree.
  double tangent_error(const CamClayParameters &m, const CamClayState &previous, const SymmetricTensor<2, 3> &strain)
  {
    const double h = 1e-5 * m.p0_initial / m.bulk_modulus;
    EXPECT_GT(std::abs(-dealii::trace(strain) - m.densification_strain), 100 * h);
    const CamClayTangentUpdate t = update_stress_and_tangent(m, previous, strain);
    const CamClayUpdate u = update_stress(m, previous, strain);
    EXPECT_TRUE(identical(t.update.stress, u.stress)) << "the tangent update differs from update_stress";
    return central_difference_error(m, previous, strain, t.tangent, h);
  }


  // ---------------------------------------------------------------------------------------------
  // The residual response under hydrostatic compaction

  TEST(Densification, HydrostaticCollapseDropsToTheFloorThenLocksUp)
  {
    // tr ε from 0 to −0.25 in steps of 1e-4: elastic up to p0 (1 kPa at tr ε = −2e-3), collapse to
    // the floor in one step, plastic flow at p = p0_floor up to −tr ε = ε_d, then
    // p = p0_floor + K_d (−tr ε − ε_d). The Cam-Clay part sits on the tip of the floor surface to
    // the projection's tolerance (16 ε relative) and p_d is K_d times a difference of O(0.1) strains
    // resolved to ~ε: the error is ~1e-16 of p plus K_d · 1e-17 ~ 1e-11 Pa, so round_off · p.
    const CamClayParameters m = weak_layer();
    const double K = m.bulk_modulus, K_d = m.densification_modulus, e_d = m.densification_strain;
    const double floor = m.p0_floor;
    ASSERT_EQ(floor, 200);
    CamClayState state = CamClayState::initial(m);
    double p_peak = 0;
    int collapse_step = -1;
    int steps_beyond = 0;
    for (int i = 1; i <= 2500; ++i)
      {
        const double compaction = i * 1e-4; // −tr ε
        const CamClayUpdate u = update_stress(m, state, hydrostatic(-compaction));
        state = u.state;
        const double p = mean_pressure(u.stress);
        if (collapse_step < 0 && !u.plastic)
          {
            p_peak = std::max(p_peak, p);
            EXPECT_NEAR(p, K * compaction, round_off * m.p0_initial) << "elastic step " << i;
            continue;
          }
        if (collapse_step < 0)
          collapse_step = i;
        EXPECT_TRUE(u.plastic) << "step " << i; // flow continues at the floor: never elastic again
        EXPECT_EQ(u.state.p0, floor) << "step " << i;
        const double locked = std::max(compaction - e_d, 0.0);
        EXPECT_NEAR(u.densification_pressure, K_d * locked, round_off * (floor + K_d * locked)) << "step " << i;
        EXPECT_NEAR(p, floor + K_d * locked, round_off * (floor + K_d * locked)) << "step " << i;
        steps_beyond += locked > 0;
      }
    // The peak is p0 to within one step (K · 1e-4 = 50 Pa), the collapse comes right after it.
    EXPECT_GT(p_peak, m.p0_initial - K * 1e-4);
    EXPECT_LE(p_peak, m.p0_initial * (1 + round_off));
    // Steps 20 (exactly on the tip, where round-off decides) or 21 collapse; 0.2/1e-4 = 2000 is
    // exactly at ε_d (engaged or not by round-off), 2001 … 2500 are beyond.
    EXPECT_TRUE(collapse_step == 20 || collapse_step == 21) << collapse_step;
    EXPECT_TRUE(steps_beyond == 500 || steps_beyond == 501) << steps_beyond;

    // The design's two points beyond ε_d and the slope between them, reached along the path.
    const double p22 = mean_pressure(hydrostatic_path(m, -0.22).stress);
    const double p25 = mean_pressure(hydrostatic_path(m, -0.25).stress);
    EXPECT_NEAR(p22, floor + K_d * 0.02, round_off * p22);
    EXPECT_NEAR(p25, floor + K_d * 0.05, round_off * p25);
    EXPECT_NEAR((p25 - p22) / 0.03, K_d, 1e-9 * K_d);

    // Unloading by 1e-4 is elastic for both parts, in parallel: Δp = −(K + K_d) 1e-4.
    const CamClayUpdate unloaded = update_stress(m, state, hydrostatic(-0.25 + 1e-4));
    EXPECT_FALSE(unloaded.plastic);
    EXPECT_NEAR(mean_pressure(unloaded.stress), floor + K_d * 0.05 - (K + K_d) * 1e-4, round_off * p25);

    // Without the lock-up the collapsed layer carries only the floor at any compaction.
    const CamClayParameters off = weak_layer(false);
    EXPECT_NEAR(mean_pressure(hydrostatic_path(off, -0.25).stress), floor, round_off * m.p0_initial);
  }

  TEST(Densification, LargeLoadCompactsToJustBeyondTheDensificationStrain)
  {
    // The equilibrium compaction under p = 10 kPa (10 p0): bisection on tr ε of p(tr ε) − 10 kPa
    // along monotonic hydrostatic paths, bracket tr ε in [−0.999, 0]. p <= p0 = 1 kPa before the
    // lock-up, so the root is beyond ε_d, where p rises monotonically: the root is unique and the
    // closed form is −tr ε = ε_d + (p − p0_floor)/K_d = 0.2098. Bisection to a bracket of 1e-13
    // and p resolved to ~1e-16 relative: 1e-10 on the strain.
    const double load = 1e4;
    const CamClayParameters m = weak_layer();
    const auto excess = [&](double volumetric_strain) {
      return mean_pressure(hydrostatic_path(m, volumetric_strain).stress) - load;
    };
    double lo = -0.999, hi = 0; // excess(lo) > 0 > excess(hi)
    ASSERT_GT(excess(lo), 0);
    ASSERT_LT(excess(hi), 0);
    while (hi - lo > 1e-13)
      {
        const double mid = 0.5 * (lo + hi);
        (excess(mid) > 0 ? lo : hi) = mid;
      }
    const double compaction = -0.5 * (lo + hi);
    EXPECT_LT(compaction, 1); // no inversion
    EXPECT_NEAR(compaction, m.densification_strain + (load - m.p0_floor) / m.densification_modulus, 1e-10);
    EXPECT_GT(compaction, m.densification_strain);
    EXPECT_LT(compaction, m.densification_strain + 0.01); // "ε_d + small": 9.8e-3 here

    // Without the lock-up no compaction short of inversion carries the load: p stays at the floor.
    const CamClayParameters off = weak_layer(false);
    EXPECT_LT(mean_pressure(hydrostatic_path(off, -0.999).stress), load);
  }

  // ---------------------------------------------------------------------------------------------
  // The lock-up leaves the Cam-Clay model alone

  TEST(Densification, OffOrDisengagedIsBitForBitTheCamClayModel)
  {
    // 200 random increments with a compaction drift (1e-3 per step, tr ε reaches ~ −0.2), for each
    // law, run three times: (a) lock-up off; (b) ε_d = 0.9, K_d = 1e9, never engaged on this path;
    // (c) ε_d = 0.05, K_d = 1e6, engaged on the second half of the path. (b) must equal (a) bit for bit:
    // stress, state, iterations and tangent. (c) must have the same Cam-Clay history (ε_p, α, p0,
    // plastic, Δγ) bit for bit, and its stress must be (a)'s minus p_d I computed the same way, so
    // also bit for bit; its tangent differs by K_d I⊗I to round-off.
    std::mt19937_64 engine(31415);
    for (const HardeningLaw law : {HardeningLaw::signed_volumetric, HardeningLaw::collapse})
      {
        const CamClayParameters off = stiff(law == HardeningLaw::collapse ? 0.5 : 5, law);
        CamClayParameters far = off;
        far.densification_strain = 0.9;
        far.densification_modulus = 1e9;
        CamClayParameters on = off;
        on.densification_strain = 0.05;
        on.densification_modulus = 1e6;
        CamClayState a = CamClayState::initial(off), b = CamClayState::initial(far), c = CamClayState::initial(on);
        unsigned int engaged = 0, plastic = 0;
        const SymmetricTensor<4, 3> IxI =
          dealii::outer_product(dealii::unit_symmetric_tensor<3>(), dealii::unit_symmetric_tensor<3>());
        for (int i = 0; i < 200; ++i)
          {
            const SymmetricTensor<2, 3> strain = a.strain + random_tensor(engine, 3e-3) + hydrostatic(-1e-3);
            const CamClayTangentUpdate ta = update_stress_and_tangent(off, a, strain);
            const CamClayTangentUpdate tb = update_stress_and_tangent(far, b, strain);
            const CamClayTangentUpdate tc = update_stress_and_tangent(on, c, strain);
            const CamClayUpdate &ua = ta.update, &ub = tb.update, &uc = tc.update;
            ASSERT_LT(-dealii::trace(strain), 0.9);
            EXPECT_EQ(ua.densification_pressure, 0);
            EXPECT_EQ(ub.densification_pressure, 0);
            // (b) = (a)
            EXPECT_TRUE(identical(ub.stress, ua.stress)) << "step " << i;
            EXPECT_TRUE(identical(tb.tangent, ta.tangent)) << "step " << i;
            EXPECT_TRUE(identical(update_stress(far, b, strain).stress, update_stress(off, a, strain).stress));
            EXPECT_TRUE(identical(ub.state.plastic_strain, ua.state.plastic_strain)) << "step " << i;
            EXPECT_EQ(ub.state.alpha, ua.state.alpha);
            EXPECT_EQ(ub.state.p0, ua.state.p0);
            EXPECT_EQ(ub.iterations, ua.iterations);
            // (c): same history, stress shifted by exactly −p_d I
            EXPECT_TRUE(identical(uc.state.plastic_strain, ua.state.plastic_strain)) << "step " << i;
            EXPECT_EQ(uc.state.alpha, ua.state.alpha);
            EXPECT_EQ(uc.state.p0, ua.state.p0);
            EXPECT_EQ(uc.plastic, ua.plastic);
            EXPECT_EQ(uc.plastic_multiplier, ua.plastic_multiplier);
            const double p_d = densification_pressure(on, strain);
            EXPECT_EQ(uc.densification_pressure, p_d);
            EXPECT_EQ(p_d, std::max(-dealii::trace(strain) - on.densification_strain, 0.0) * on.densification_modulus);
            SymmetricTensor<2, 3> expected = ua.stress;
            if (p_d > 0)
              expected -= p_d * dealii::unit_symmetric_tensor<3>();
            EXPECT_TRUE(identical(uc.stress, expected)) << "step " << i;
            const SymmetricTensor<4, 3> added = tc.tangent - ta.tangent;
            const double expected_modulus = p_d > 0 ? on.densification_modulus : 0;
            EXPECT_LT((added - expected_modulus * IxI).norm(), round_off * (ta.tangent.norm() + on.densification_modulus))
              << "step " << i;
            engaged += p_d > 0;
            plastic += ua.plastic;
            a = ua.state;
            b = ub.state;
            c = uc.state;
          }
        // The path does what the test needs: the lock-up engaged and plastic flow on many steps.
        EXPECT_GT(engaged, 50u);
        EXPECT_GT(plastic, 50u);
      }
  }

  // ---------------------------------------------------------------------------------------------
  // Consistent tangent

  TEST(Densification, TangentMatchesCentralDifferencesWithLockUpAndPlasticFlow)
  {
    // Lock-up engaged and the step plastic: the weak layer at the floor (collapse law, fixed p0) in
    // compaction with shear, the hardening signed law (non-symmetric tangent) and the collapse law
    // above the floor, and a sub-stepped integration.
    SymmetricTensor<2, 3> shear;
    shear[0][1] = 2e-3;
    shear[1][2] = -1e-3;
    shear[0][0] = 1e-3;
    shear[1][1] = -1e-3;
    struct Case
    {
      std::string name;
      CamClayParameters m;
      CamClayState previous;
      SymmetricTensor<2, 3> strain;
    };
    std::vector<Case> cases;
    {
      const CamClayParameters m = weak_layer();
      const CamClayState before = hydrostatic_path(m, -0.21).state;
      cases.push_back({"weak layer at the floor", m, before, hydrostatic(-0.22) + shear});
    }
    {
      CamClayParameters m = stiff(5, HardeningLaw::signed_volumetric);
      m.densification_strain = 0.02;
      m.densification_modulus = 2e6;
      SymmetricTensor<2, 3> strain = hydrostatic(-0.03);
      strain[0][1] = 0.8e-2;
      strain[1][2] = -0.3e-2;
      cases.push_back({"signed law, hardening", m, CamClayState::initial(m), strain});
      const CamClayUpdate before = update_stress(m, CamClayState::initial(m), 0.5 * strain);
      cases.push_back({"signed law, hardening, second step", m, before.state, strain});
      CamClayParameters tight = m;
      tight.max_iterations = 5; // forces sub-steps (CamClayTangent.MatchesCentralDifferencesThroughSubsteps)
      SymmetricTensor<2, 3> substepped = hydrostatic(-0.03); // that test's strain, 1e-2 beyond ε_d
      substepped[0][1] = 2e-2;
      cases.push_back({"signed law, sub-stepped", tight, CamClayState::initial(tight), substepped});
    }
    {
      CamClayParameters m = stiff(0.5, HardeningLaw::collapse);
      m.densification_strain = 0.01;
      m.densification_modulus = 2e6;
      SymmetricTensor<2, 3> strain = hydrostatic(-0.015);
      strain[0][1] = 0.8e-2;
      cases.push_back({"collapse law above the floor", m, CamClayState::initial(m), strain});
    }
    for (const auto &c : cases)
      {
        const CamClayTangentUpdate t = update_stress_and_tangent(c.m, c.previous, c.strain);
        EXPECT_TRUE(t.update.plastic) << c.name;
        EXPECT_GT(t.update.densification_pressure, 0) << c.name;
        EXPECT_LT(tangent_error(c.m, c.previous, c.strain), 1e-6) << c.name;
      }
    EXPECT_EQ(update_stress(cases[0].m, cases[0].previous, cases[0].strain).state.p0, cases[0].m.p0_floor);
    EXPECT_GT(update_stress(cases[1].m, cases[1].previous, cases[1].strain).state.p0, cases[1].m.p0_initial);
    EXPECT_GT(update_stress(cases[3].m, cases[3].previous, cases[3].strain).substeps, 1u);
    const CamClayUpdate collapse = update_stress(cases[4].m, cases[4].previous, cases[4].strain);
    EXPECT_LT(collapse.state.p0, cases[4].m.p0_initial);
    EXPECT_GT(collapse.state.p0, cases[4].m.p0_floor);
  }

  // ---------------------------------------------------------------------------------------------
  // P-wave modulus

  TEST(Densification, PWaveModulusAddsTheLockUpBeyondTheDensificationStrain)
  {
    const CamClayParameters m = weak_layer();
    const double elastic = m.bulk_modulus + 4 * m.shear_modulus / 3;
    const double locked = elastic + m.densification_modulus;
    SymmetricTensor<2, 3> shear;
    shear[0][1] = 0.05;
    EXPECT_NEAR(p_wave_modulus(m, SymmetricTensor<2, 3>()), elastic, round_off * elastic);
    EXPECT_NEAR(p_wave_modulus(m, hydrostatic(0.1)), elastic, round_off * elastic);
    EXPECT_NEAR(p_wave_modulus(m, hydrostatic(-0.19) + shear), elastic, round_off * elastic);
    EXPECT_NEAR(p_wave_modulus(m, hydrostatic(-0.21) + shear), locked, round_off * locked);
    EXPECT_NEAR(p_wave_modulus(m, hydrostatic(-0.9)), locked, round_off * locked);
    // Off: never more than the elastic modulus.
    EXPECT_NEAR(p_wave_modulus(weak_layer(false), hydrostatic(-0.9)), elastic, round_off * elastic);

    // It is the uniaxial-strain stiffness C_xxxx of an elastic step, without and with the lock-up:
    // a stress-free state at −tr ε = 0.19 or 0.21 (ε_p = ε), strained by 1e-5 along x.
    for (const double compaction : {0.19, 0.21})
      {
        CamClayState state = CamClayState::initial(m);
        state.strain = state.plastic_strain = hydrostatic(-compaction);
        SymmetricTensor<2, 3> strain = state.strain;
        strain[0][0] -= 1e-5;
        const CamClayTangentUpdate t = update_stress_and_tangent(m, state, strain);
        ASSERT_FALSE(t.update.plastic);
        const double modulus = p_wave_modulus(m, strain);
        EXPECT_NEAR(t.tangent[0][0][0][0], modulus, round_off * modulus) << compaction;
        EXPECT_NEAR(modulus, compaction > 0.2 ? locked : elastic, round_off * locked) << compaction;
      }
  }

  // ---------------------------------------------------------------------------------------------
  // Parameters and the residual floor

  TEST(DensificationParameters, BadValuesAreRejectedNamingTheParameterAndTheRange)
  {
    EXPECT_NO_THROW(weak_layer().check());
    EXPECT_NO_THROW(weak_layer(false).check());
    const struct
    {
      std::string name, range;
      double strain, modulus;
    } cases[] = {
      {"densification_strain", "in [0, 1)", 1, 1e6},
      {"densification_strain", "in [0, 1)", 1.5, 1e6},
      {"densification_strain", "in [0, 1)", -0.1, 1e6},
      {"densification_strain", "in [0, 1)", std::nan(""), 1e6},
      {"densification_modulus", ">= 0 [Pa]", 0.2, -1},
      {"densification_modulus", ">= 0 [Pa]", 0.2, INFINITY},
      {"densification_modulus", "> 0 [Pa] when densification_strain > 0", 0.2, 0},
      {"densification_modulus", "0 when densification_strain = 0", 0, 1e6},
    };
    for (const auto &c : cases)
      {
        CamClayParameters m = weak_layer();
        m.densification_strain = c.strain;
        m.densification_modulus = c.modulus;
        const std::string message = invalid_argument_message([&] { m.check(); });
        EXPECT_NE(message.find("'" + c.name + "'"), std::string::npos) << c.name << ": '" << message << "'";
        EXPECT_NE(message.find(c.range), std::string::npos) << c.range << ": '" << message << "'";
        EXPECT_THROW(CamClayState::initial(m), std::invalid_argument) << c.name;
      }
  }

  TEST(DensificationParameters, ResidualFloorIsTheRatioOfP0WithAPositiveMinimum)
  {
    EXPECT_NEAR(residual_p0_floor(1e3, 0.2), 200, round_off * 1e3);
    EXPECT_EQ(residual_p0_floor(1e3, 1), 1e3);
    EXPECT_NEAR(residual_p0_floor(1e3, 0), min_residual_strength_ratio * 1e3, round_off * 1e3);
    EXPECT_NEAR(residual_p0_floor(1e3, 1e-6), min_residual_strength_ratio * 1e3, round_off * 1e3);
    EXPECT_GT(residual_p0_floor(1e-3, 0), 0);
    for (const double ratio : {-0.1, 1.1, double(NAN)})
      EXPECT_NE(invalid_argument_message([&] { residual_p0_floor(1e3, ratio); }).find("residual strength ratio"),
                std::string::npos)
        << ratio;
    for (const double p0 : {0.0, -1.0, double(INFINITY)})
      EXPECT_NE(invalid_argument_message([&] { residual_p0_floor(p0, 0.2); }).find("p0_initial"), std::string::npos)
        << p0;

    // A ratio of 0 gives valid parameters, and the collapsed layer rests on the minimum floor and
    // then on the lock-up.
    CamClayParameters m = weak_layer();
    m.p0_floor = residual_p0_floor(m.p0_initial, 0);
    const CamClayUpdate u = hydrostatic_path(m, -0.25);
    EXPECT_EQ(u.state.p0, m.p0_floor);
    const double p = m.p0_floor + m.densification_modulus * 0.05;
    EXPECT_NEAR(mean_pressure(u.stress), p, round_off * p);
  }
} // namespace

// The normal stress a collapsed layer carries while it keeps compacting in uniaxial strain at its
// residual (confined_flow_normal_stress): driven far past the collapse (strain 0.1, fifty times the
// elastic range) without the lock-up, the return mapping's layer-normal stress settles on the
// closed form, for several surfaces. Tolerance 1e-6: the elastic strain's approach to the flow
// state decays with the compaction (exp(−x K/p0)), far below it at x = 0.1.
TEST(ConfinedFlow, NormalStressOfSteadyCompactionAtTheFloor)
{
  for (const double beta : {0.0, 0.3, 0.8})
    for (const double M : {0.6, 1.2, 2.2})
    {
      CamClayParameters m = weak_layer(false);
      m.beta = beta, m.M = M;
      CamClayState state = CamClayState::initial(m);
      double normal = 0;
      for (int i = 1; i <= 2000; ++i)
      {
        SymmetricTensor<2, 3> strain;
        strain[1][1] = -0.1 * i / 2000.0;
        const CamClayUpdate u = update_stress(m, state, strain);
        state = u.state;
        normal = -u.stress[1][1];
      }
      ASSERT_NEAR(state.p0, m.p0_floor, 1e-9 * m.p0_floor);
      EXPECT_NEAR(normal / confined_flow_normal_stress(m.p0_floor, m), 1, 1e-6) << "beta " << beta << ", M " << M;
    }
}
