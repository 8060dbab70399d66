// Tests of fem/closed_forms (docs/fem_closed_forms.md): the elastic helpers against hand values; the
// PST deflection against its differential equations and boundary conditions (finite differences of
// the returned fields); the energy release rate against −ΔΠ/Δa of an independent numerical model
// (cubic Hermite beam and bar elements on springs, banded Cholesky), against G(0) and the large-cut
// asymptote; the cut-length inversion; Gaume 2017 and Heierli 2005 against hand values; the model-
// error estimates against the numerical model with the bending–shear coupling switched on; bad input.
//
// "Typical" parameters are those of docs/fem_closed_forms.md §7: H = 0.4 m, ρ = 250 kg/m³,
// E = 5 MPa, ν = 0.25; weak layer h = 2 cm, E_wl = 0.2 MPa, ν_wl = 0.2 (1/λ = 0.318 m, 1/μ = 0.716 m).
#include "fem/closed_forms.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
  using namespace anticrack::fem::closed_forms;

  constexpr double pi = 3.14159265358979323846;

  SlabOnFoundation typical(double slope_angle = 0)
  {
    SlabOnFoundation s;
    s.slab_thickness = 0.4;
    s.slab_youngs_modulus = 5e6;
    s.slab_poisson_ratio = 0.25;
    s.slab_density = 250;
    s.weak_layer_thickness = 0.02;
    s.weak_layer_youngs_modulus = 0.2e6;
    s.weak_layer_poisson_ratio = 0.2;
    s.slope_angle = slope_angle;
    return s;
  }

  /// A slab 400 times stiffer than the typical one: μ/λ ≈ 0.1, so that the bending–shear coupling is
  /// a small perturbation (ε_b = 1.5 (μ/λ)² ≈ 0.015) whose first-order size can be checked.
  SlabOnFoundation stiff_slab(double slope_angle = 0)
  {
    SlabOnFoundation s = typical(slope_angle);
    s.slab_youngs_modulus = 2e9;
    return s;
  }

  // --- Hand-computed ingredients (independent of the library's helper functions) -----------------

  double hand_plane_strain_modulus(const SlabOnFoundation &s)
  {
    return s.slab_youngs_modulus / (1 - s.slab_poisson_ratio * s.slab_poisson_ratio);
  }
  double hand_bending_stiffness(const SlabOnFoundation &s)
  {
    return hand_plane_strain_modulus(s) * std::pow(s.slab_thickness, 3) / 12;
  }
  double hand_normal_stiffness(const SlabOnFoundation &s)
  {
    const double nu = s.weak_layer_poisson_ratio;
    return s.weak_layer_youngs_modulus * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / s.weak_layer_thickness;
  }
  double hand_shear_stiffness(const SlabOnFoundation &s)
  {
    return s.weak_layer_youngs_modulus / (2 * (1 + s.weak_layer_poisson_ratio)) / s.weak_layer_thickness;
  }
  double hand_normal_load(const SlabOnFoundation &s)
  {
    return s.slab_density * s.gravity * s.slab_thickness * std::cos(s.slope_angle);
  }
  double hand_tangential_load(const SlabOnFoundation &s)
  {
    return s.slab_density * s.gravity * s.slab_thickness * std::sin(s.slope_angle);
  }

  // --- Finite differences ----------------------------------------------------------------------

  /// Fourth-order central difference of f at x with step h: error h⁴ f⁽⁵⁾/30 plus ~1.5 ε |f| / h.
  double derivative(const std::function<double(double)> &f, double x, double h)
  {
    return (-f(x + 2 * h) + 8 * f(x + h) - 8 * f(x - h) + f(x - 2 * h)) / (12 * h);
  }

  // --- Independent numerical model -------------------------------------------------------------

  /// The slab on the weak layer discretised with cubic Hermite elements for the deflection w and the
  /// axial displacement u (dofs w, w', u, u' per node) on a finite column [0, L] with free ends.
  /// Springs k_n act on w and k_t on the slip of the slab's bottom fibre s = u − e w' over x >= a;
  /// e = 0 is the uncoupled model of the closed forms, e = H/2 the coupled one (Eqs. 19, 21).
  /// Each element is integrated with 5-point Gauss, exact for these polynomials (degree <= 6).
  struct BeamModel
  {
    double bending_stiffness = 0;  // D
    double axial_stiffness = 0;    // E'H
    double normal_stiffness = 0;   // k_n
    double shear_stiffness = 0;    // k_t
    double normal_load = 0;        // q_n
    double tangential_load = 0;    // q_t
    double eccentricity = 0;       // e
    double column_length = 0;      // L
    unsigned int elements = 0;     // uniform mesh

    static BeamModel of(const SlabOnFoundation &s, double column_length, unsigned int elements, bool coupled)
    {
      BeamModel m;
      m.bending_stiffness = hand_bending_stiffness(s);
      m.axial_stiffness = hand_plane_strain_modulus(s) * s.slab_thickness;
      m.normal_stiffness = hand_normal_stiffness(s);
      m.shear_stiffness = hand_shear_stiffness(s);
      m.normal_load = hand_normal_load(s);
      m.tangential_load = hand_tangential_load(s);
      m.eccentricity = coupled ? s.slab_thickness / 2 : 0;
      m.column_length = column_length;
      m.elements = elements;
      return m;
    }

    double element_size() const { return column_length / elements; }

    /// The element's fields at one Gauss point as linear functions of its 8 dofs
    /// (w_i, w'_i, u_i, u'_i, w_{i+1}, w'_{i+1}, u_{i+1}, u'_{i+1}); the same for every element.
    struct GaussPoint
    {
      double weight = 0;
      double curvature[8] = {}, deflection[8] = {}, strain[8] = {}, axial[8] = {}, slip[8] = {};
    };

    std::array<GaussPoint, 5> gauss_points() const
    {
      const double point[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                               0.9061798459386640};
      const double weight[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                0.4786286704993665, 0.2369268850561891};
      const double h = element_size();
      std::array<GaussPoint, 5> points;
      for (unsigned int g = 0; g < 5; ++g)
        {
          const double t = (point[g] + 1) / 2;
          // Hermite cubics on [0, h] (value, slope at each end) and their x-derivatives.
          const double value[4] = {1 - 3 * t * t + 2 * t * t * t, h * (t - 2 * t * t + t * t * t),
                                   3 * t * t - 2 * t * t * t, h * (-t * t + t * t * t)};
          const double first[4] = {(-6 * t + 6 * t * t) / h, 1 - 4 * t + 3 * t * t, (6 * t - 6 * t * t) / h,
                                   -2 * t + 3 * t * t};
          const double second[4] = {(-6 + 12 * t) / (h * h), (-4 + 6 * t) / h, (6 - 12 * t) / (h * h),
                                    (-2 + 6 * t) / h};
          const unsigned int w_dof[4] = {0, 1, 4, 5}, u_dof[4] = {2, 3, 6, 7};
          GaussPoint &p = points[g];
          p.weight = weight[g] * h / 2;
          for (unsigned int i = 0; i < 4; ++i)
            {
              p.curvature[w_dof[i]] = second[i];
              p.deflection[w_dof[i]] = value[i];
              p.slip[w_dof[i]] = -eccentricity * first[i];
              p.strain[u_dof[i]] = first[i];
              p.axial[u_dof[i]] = value[i];
              p.slip[u_dof[i]] = value[i];
            }
        }
      return points;
    }

    /// Π = U − W at equilibrium with the weak layer removed over the first `cut_elements` elements.
    /// U is integrated element by element from the fields (w'', u', w, s) at the Gauss points: the
    /// quadratic form dᵀ K d would cancel terms ~(D/h³) w² of the cantilever's rigid motion and lose
    /// ~1e-3 of G on fine meshes.
    double potential_energy(unsigned int cut_elements) const
    {
      constexpr unsigned int dofs_per_node = 4, band = 7; // an element couples 8 consecutive dofs
      const unsigned int n = dofs_per_node * (elements + 1);
      const std::array<GaussPoint, 5> points = gauss_points();
      // Lower band of K: K(i, i − k) = factor[i][k], then overwritten by its Cholesky factor.
      std::vector<std::array<double, band + 1>> factor(n, std::array<double, band + 1>{});
      std::vector<double> load(n, 0.0);
      for (unsigned int e = 0; e < elements; ++e)
        {
          const bool supported = e >= cut_elements;
          const unsigned int first = dofs_per_node * e;
          for (const GaussPoint &p : points)
            for (unsigned int i = 0; i < 8; ++i)
              {
                load[first + i] += p.weight * (normal_load * p.deflection[i] + tangential_load * p.axial[i]);
                for (unsigned int j = 0; j <= i; ++j)
                  factor[first + i][i - j] +=
                    p.weight * (bending_stiffness * p.curvature[i] * p.curvature[j] +
                                axial_stiffness * p.strain[i] * p.strain[j] +
                                (supported ? normal_stiffness * p.deflection[i] * p.deflection[j] +
                                               shear_stiffness * p.slip[i] * p.slip[j]
                                           : 0.0));
              }
        }

      // Banded Cholesky K = L Lᵀ in place, then L y = f and Lᵀ d = y.
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int j = (i > band ? i - band : 0); j <= i; ++j)
          {
            double sum = factor[i][i - j];
            for (unsigned int k = (i > band ? i - band : 0); k < j; ++k)
              sum -= factor[i][i - k] * factor[j][j - k];
            factor[i][i - j] = i == j ? std::sqrt(sum) : sum / factor[j][0];
          }
      std::vector<double> d = load;
      for (unsigned int i = 0; i < n; ++i)
        {
          for (unsigned int k = (i > band ? i - band : 0); k < i; ++k)
            d[i] -= factor[i][i - k] * d[k];
          d[i] /= factor[i][0];
        }
      for (unsigned int i = n; i-- > 0;)
        {
          for (unsigned int k = i + 1; k <= std::min(n - 1, i + band); ++k)
            d[i] -= factor[k][k - i] * d[k];
          d[i] /= factor[i][0];
        }

      double strain_energy = 0, work = 0;
      for (unsigned int e = 0; e < elements; ++e)
        {
          const bool supported = e >= cut_elements;
          const double *de = &d[dofs_per_node * e];
          for (const GaussPoint &p : points)
            {
              double curvature = 0, deflection = 0, strain = 0, axial = 0, slip = 0;
              for (unsigned int i = 0; i < 8; ++i)
                {
                  curvature += p.curvature[i] * de[i];
                  deflection += p.deflection[i] * de[i];
                  strain += p.strain[i] * de[i];
                  axial += p.axial[i] * de[i];
                  slip += p.slip[i] * de[i];
                }
              strain_energy += p.weight / 2 *
                               (bending_stiffness * curvature * curvature + axial_stiffness * strain * strain +
                                (supported ? normal_stiffness * deflection * deflection + shear_stiffness * slip * slip
                                           : 0.0));
              work += p.weight * (normal_load * deflection + tangential_load * axial);
            }
        }
      return strain_energy - work;
    }

    /// G(a) ≈ −(Π(a + h) − Π(a − h)) / (2h) at a = cut_elements · h (central difference over one
    /// element each way).
    double energy_release_rate(unsigned int cut_elements) const
    {
      return -(potential_energy(cut_elements + 1) - potential_energy(cut_elements - 1)) / (2 * element_size());
    }
  };

  template <class Exception, class F>
  void expect_throw_naming(F &&f, const std::string &name)
  {
    try
      {
        f();
        ADD_FAILURE() << "no exception; expected one naming '" << name << "'";
      }
    catch (const Exception &e)
      {
        EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      }
  }

  // =============================================================================================
  // Elastic helpers

  TEST(ClosedFormsElastic, ModuliMatchHandValues)
  {
    // E = 1 MPa, ν = 0.25: E' = 1/0.9375 MPa, M = 0.75/(1.25·0.5) MPa = 1.2 MPa, G = 0.4 MPa.
    // Round-off of a few operations: 1e-14 relative.
    EXPECT_NEAR(plane_strain_modulus(1e6, 0.25), 1e6 / 0.9375, 1e-14 * 1e6);
    EXPECT_NEAR(constrained_modulus(1e6, 0.25), 1.2e6, 1e-14 * 1e6);
    EXPECT_NEAR(shear_modulus(1e6, 0.25), 0.4e6, 1e-14 * 1e6);
    // ν = 0: no lateral coupling, all three reduce to E (E', M) and E/2 (G).
    EXPECT_DOUBLE_EQ(plane_strain_modulus(3e5, 0), 3e5);
    EXPECT_DOUBLE_EQ(constrained_modulus(3e5, 0), 3e5);
  }

  TEST(ClosedFormsElastic, WaveSpeedsMatchHandValues)
  {
    // K = E/(3(1 − 2ν)) = 666 666.67 Pa, G = 0.4 MPa for E = 1 MPa, ν = 0.25, ρ = 300 kg/m³:
    // K + 4G/3 = 1.2 MPa = M, so c_p = sqrt(4000) = 63.2455532 m/s; c_s = sqrt(4e5/300) = 36.5148372 m/s.
    EXPECT_NEAR(p_wave_speed(1e6 / 1.5, 0.4e6, 300), 63.24555320336759, 1e-12);
    EXPECT_NEAR(shear_wave_speed(0.4e6, 300), 36.51483716701107, 1e-12);
    // c_p² ρ is the constrained modulus: the two helpers agree.
    EXPECT_NEAR(std::pow(p_wave_speed(1e6 / 1.5, 0.4e6, 300), 2) * 300, constrained_modulus(1e6, 0.25), 1e-8);
  }

  TEST(ClosedFormsElastic, RejectsBadInput)
  {
    expect_throw_naming<std::invalid_argument>([] { plane_strain_modulus(-1, 0.2); }, "youngs_modulus");
    expect_throw_naming<std::invalid_argument>([] { constrained_modulus(1e6, 0.5); }, "poisson_ratio");
    expect_throw_naming<std::invalid_argument>([] { shear_modulus(1e6, -1); }, "poisson_ratio");
    expect_throw_naming<std::invalid_argument>([] { p_wave_speed(1e6, 1e6, 0); }, "density");
    expect_throw_naming<std::invalid_argument>([] { shear_wave_speed(std::nan(""), 1); }, "shear_modulus");
    expect_throw_naming<std::invalid_argument>([] { constrained_modulus(1e6, 0.5); }, "(-1, 1/2)");
  }

  // =============================================================================================
  // Foundation parameters

  TEST(ClosedFormsFoundation, StiffnessesAndLengthsMatchHandValues)
  {
    const SlabOnFoundation s = typical(0.3);
    const double d = hand_bending_stiffness(s), kn = hand_normal_stiffness(s), kt = hand_shear_stiffness(s);
    EXPECT_NEAR(slab_bending_stiffness(s), d, 1e-13 * d);
    EXPECT_NEAR(normal_foundation_stiffness(s), kn, 1e-13 * kn);
    EXPECT_NEAR(shear_foundation_stiffness(s), kt, 1e-13 * kt);
    EXPECT_NEAR(normal_load(s), hand_normal_load(s), 1e-13 * hand_normal_load(s));
    EXPECT_NEAR(tangential_load(s), hand_tangential_load(s), 1e-13 * hand_tangential_load(s));
    // λ⁴ = k_n / (4D), μ² = k_t / (E'H).
    const double lambda = 1 / characteristic_length(s), mu = 1 / shear_lag_length(s);
    EXPECT_NEAR(4 * d * std::pow(lambda, 4), kn, 1e-12 * kn);
    EXPECT_NEAR(hand_plane_strain_modulus(s) * s.slab_thickness * mu * mu, kt, 1e-12 * kt);
    // The typical numbers of the doc (§7): 1/λ = 0.318108 m, 1/μ = Λ = 0.715542 m.
    EXPECT_NEAR(characteristic_length(typical()), 0.318108, 5e-7);
    EXPECT_NEAR(shear_lag_length(typical()), 0.715542, 5e-7);
  }

  TEST(ClosedFormsFoundation, RejectsBadParameters)
  {
    const auto with = [](auto change) {
      SlabOnFoundation s = typical();
      change(s);
      return s;
    };
    expect_throw_naming<std::invalid_argument>(
      [&] { with([](SlabOnFoundation &s) { s.slab_thickness = -0.1; }).check(); }, "slab_thickness");
    expect_throw_naming<std::invalid_argument>(
      [&] { with([](SlabOnFoundation &s) { s.slab_poisson_ratio = 0.5; }).check(); }, "slab_poisson_ratio");
    expect_throw_naming<std::invalid_argument>(
      [&] { with([](SlabOnFoundation &s) { s.weak_layer_poisson_ratio = 0.7; }).check(); },
      "weak_layer_poisson_ratio");
    expect_throw_naming<std::invalid_argument>(
      [&] { with([](SlabOnFoundation &s) { s.weak_layer_thickness = 0; }).check(); }, "weak_layer_thickness");
    expect_throw_naming<std::invalid_argument>(
      [&] { with([](SlabOnFoundation &s) { s.weak_layer_youngs_modulus = std::nan(""); }).check(); },
      "weak_layer_youngs_modulus");
    expect_throw_naming<std::invalid_argument>(
      [&] { with([](SlabOnFoundation &s) { s.slab_density = -250; }).check(); }, "slab_density");
    expect_throw_naming<std::invalid_argument>(
      [&] { with([](SlabOnFoundation &s) { s.slope_angle = pi / 2; }).check(); }, "slope_angle");
    // Every function checks its input.
    expect_throw_naming<std::invalid_argument>(
      [&] { energy_release_rate(with([](SlabOnFoundation &s) { s.slab_youngs_modulus = 0; }), 0.3); },
      "slab_youngs_modulus");
    expect_throw_naming<std::invalid_argument>([&] { energy_release_rate(typical(), -0.1); }, "cut_length");
    expect_throw_naming<std::invalid_argument>([&] { slab_deflection(typical(), 0.3, -1); }, "x");
    expect_throw_naming<std::invalid_argument>([&] { slab_axial_displacement(typical(), 0.3, -1); }, "x");
  }

  // =============================================================================================
  // Deflection: the ODEs and the boundary conditions, by finite differences of the returned fields

  /// The returned derivatives are the derivatives of the returned w: fourth-order differences with
  /// λh = 0.01 have truncation ~ (λh)⁴ · 4/30 ~ 1e-9 and round-off ~ 1.5 ε/(λh) ~ 3e-14 relative to
  /// the scale λⁿ w(a): 1e-7 leaves a margin and still catches any wrong factor or sign.
  TEST(ClosedFormsDeflection, DerivativesAreConsistent)
  {
    for (const double slope : {0.0, 0.5})
      for (const double a : {0.0, 0.2, 0.6})
        {
          const SlabOnFoundation s = typical(slope);
          const double lambda = 1 / characteristic_length(s), step = 0.01 / lambda;
          const double scale = weak_layer_compression_at_tip(s, a);
          const auto field = [&](int order) {
            return [&, order](double x) {
              const SlabDeflection d = slab_deflection(s, a, x);
              const double values[4] = {d.w, d.dw_dx, d.d2w_dx2, d.d3w_dx3};
              return values[order];
            };
          };
          // Points on the cantilever (if any) and on the supported part, away from the tip by > 2 steps.
          std::vector<double> points = {a + 0.1 / lambda, a + 1 / lambda, a + 3 / lambda};
          if (a > 0)
            points.insert(points.end(), {0.3 * a, 0.7 * a});
          for (const double x : points)
            for (int order = 1; order <= 3; ++order)
              EXPECT_NEAR(derivative(field(order - 1), x, step), field(order)(x),
                          1e-7 * scale * std::pow(lambda, order))
                << "a = " << a << ", x = " << x << ", derivative " << order;
        }
  }

  /// D w'''' + k_n w = q_n on the supported part and D w'''' = q_n on the cantilever, with w'''' the
  /// fourth-order difference of w''' (relative accuracy ~1e-9 as above). Residuals relative to
  /// q_n (1 + λa)², the size of k_n w(a).
  TEST(ClosedFormsDeflection, SatisfiesBeamOnFoundationEquation)
  {
    for (const double a : {0.0, 0.15, 0.4, 1.0})
      {
        const SlabOnFoundation s = typical(0.4);
        const double lambda = 1 / characteristic_length(s), step = 0.01 / lambda;
        const double d = hand_bending_stiffness(s), kn = hand_normal_stiffness(s), q = hand_normal_load(s);
        const double scale = q * std::pow(1 + lambda * a, 2);
        const auto third = [&](double x) { return slab_deflection(s, a, x).d3w_dx3; };
        for (const double x : {a + 0.05 / lambda, a + 0.5 / lambda, a + 1.5 / lambda, a + 4 / lambda})
          EXPECT_NEAR(d * derivative(third, x, step) + kn * slab_deflection(s, a, x).w, q, 1e-7 * scale)
            << "supported part, a = " << a << ", x = " << x;
        if (a > 0)
          {
            for (const double x : {0.2 * a, 0.8 * a})
              EXPECT_NEAR(d * derivative(third, x, 0.01 * a), q, 1e-7 * scale) << "cantilever, x = " << x;
          }
      }
  }

  /// The free end carries no moment and no shear; at the tip the supported solution carries the
  /// cantilever's moment M(a) = −q a²/2 and shear V(a) = −q a (M = −D w'', V = −D w'''), and w, w',
  /// w'', w''' are continuous. Far from the tip the slab settles uniformly by q/k_n.
  TEST(ClosedFormsDeflection, MeetsBoundaryAndTipConditions)
  {
    const SlabOnFoundation s = typical(0.4);
    const double d = hand_bending_stiffness(s), kn = hand_normal_stiffness(s), q = hand_normal_load(s);
    const double lambda = 1 / characteristic_length(s);
    for (const double a : {0.1, 0.3, 0.8})
      {
        const double moment_scale = q * a * a / 2, shear_scale = q * a;
        const SlabDeflection end = slab_deflection(s, a, 0);
        EXPECT_NEAR(-d * end.d2w_dx2, 0, 1e-12 * moment_scale);
        EXPECT_NEAR(-d * end.d3w_dx3, 0, 1e-12 * shear_scale);

        const SlabDeflection tip = slab_deflection(s, a, a);
        EXPECT_NEAR(-d * tip.d2w_dx2, -q * a * a / 2, 1e-12 * moment_scale);
        EXPECT_NEAR(-d * tip.d3w_dx3, -q * a, 1e-12 * shear_scale);
        EXPECT_NEAR(tip.w, weak_layer_compression_at_tip(s, a), 1e-14 * tip.w);

        // Continuity: the cantilever branch at Δx = 1e-6 a before the tip, extrapolated to the tip
        // with its next derivative; what is left is O(Δx²) ~ 1e-12 relative plus round-off.
        const double dx = 1e-6 * a;
        const SlabDeflection before = slab_deflection(s, a, a - dx);
        EXPECT_NEAR(before.w + dx * before.dw_dx, tip.w, 1e-10 * tip.w);
        EXPECT_NEAR(before.dw_dx + dx * before.d2w_dx2, tip.dw_dx, 1e-10 * lambda * tip.w);
        EXPECT_NEAR(before.d2w_dx2 + dx * before.d3w_dx3, tip.d2w_dx2, 1e-10 * moment_scale / d);
        EXPECT_NEAR(before.d3w_dx3 + dx * q / d, tip.d3w_dx3, 1e-10 * shear_scale / d);

        // e^{−30} ≈ 1e-13 of the tip amplitude is left 30/λ beyond the tip.
        EXPECT_NEAR(slab_deflection(s, a, a + 30 / lambda).w, q / kn, 1e-12 * q / kn);
        // The free end droops below the tip (the cantilever hangs down).
        EXPECT_GT(end.w, tip.w);
      }
  }

  /// E'H u'' − k_t u + q_t = 0 on the supported part, E'H u'' = −q_t on the free bar, N(0) = 0,
  /// N(a) = −q_t a, u → q_t/k_t (fourth-order differences as above).
  TEST(ClosedFormsDeflection, AxialDisplacementSatisfiesBarEquation)
  {
    const SlabOnFoundation s = typical(0.5);
    const double ea = hand_plane_strain_modulus(s) * s.slab_thickness, kt = hand_shear_stiffness(s);
    const double qt = hand_tangential_load(s), mu = 1 / shear_lag_length(s);
    for (const double a : {0.0, 0.3, 1.0})
      {
        const double scale = qt * (1 + mu * a);
        const auto strain = [&](double x) { return slab_axial_displacement(s, a, x).du_dx; };
        const auto displacement = [&](double x) { return slab_axial_displacement(s, a, x).u; };
        for (const double x : {a + 0.1 / mu, a + 1 / mu, a + 3 / mu})
          {
            EXPECT_NEAR(ea * derivative(strain, x, 0.01 / mu) - kt * displacement(x) + qt, 0, 1e-7 * scale);
            EXPECT_NEAR(derivative(displacement, x, 0.01 / mu), strain(x), 1e-7 * scale / ea);
          }
        if (a > 0)
          {
            EXPECT_NEAR(ea * derivative(strain, 0.5 * a, 0.01 * a), -qt, 1e-7 * scale);
            EXPECT_NEAR(ea * strain(0), 0, 1e-12 * scale * a);
            EXPECT_NEAR(ea * strain(a), -qt * a, 1e-12 * scale * a);
            EXPECT_NEAR(displacement(a - 1e-9), displacement(a), 1e-9 * displacement(a));
          }
        EXPECT_NEAR(displacement(a), weak_layer_slip_at_tip(s, a), 1e-14 * displacement(a));
        EXPECT_NEAR(displacement(a + 40 / mu), qt / kt, 1e-12 * qt / kt);
      }
  }

  // =============================================================================================
  // Energy release rate

  /// A = 0: the springs are uniformly compressed by q_n/k_n and slipped by q_t/k_t; cutting one
  /// releases its energy density q_n²/(2k_n) + q_t²/(2k_t).
  TEST(ClosedFormsEnergyReleaseRate, UncutColumnReleasesUniformSpringEnergy)
  {
    for (const double slope : {0.0, 0.3, -0.6})
      {
        const SlabOnFoundation s = typical(slope);
        const double qn = hand_normal_load(s), qt = hand_tangential_load(s);
        const double expected = qn * qn / (2 * hand_normal_stiffness(s)) + qt * qt / (2 * hand_shear_stiffness(s));
        EXPECT_NEAR(energy_release_rate(s, 0), expected, 1e-13 * expected);
        EXPECT_NEAR(energy_release_rate_mode_I(s, 0) + energy_release_rate_mode_II(s, 0),
                    energy_release_rate(s, 0), 1e-15 * expected);
      }
  }

  TEST(ClosedFormsEnergyReleaseRate, GrowsMonotonically)
  {
    const SlabOnFoundation s = typical(0.5);
    double previous = energy_release_rate(s, 0);
    for (int i = 1; i <= 200; ++i)
      {
        const double a = 0.01 * i, g = energy_release_rate(s, a);
        EXPECT_GT(g, previous) << "a = " << a;
        previous = g;
      }
    // The sign of the slope does not matter to the uncoupled model.
    EXPECT_DOUBLE_EQ(energy_release_rate(typical(0.5), 0.4), energy_release_rate(typical(-0.5), 0.4));
  }

  /// G_I = q²(1 + λa)⁴/(2k) = [M(a)²/(2D)] (1 + 1/(λa))⁴ with the cantilever's root moment
  /// M = q a²/2 (λ⁴ = k/(4D)): for a long cut the tip behaves as a clamped beam releasing M²/(2D).
  TEST(ClosedFormsEnergyReleaseRate, LongCutTendsToCantileverMomentLimit)
  {
    const SlabOnFoundation s = typical();
    const double d = hand_bending_stiffness(s), q = hand_normal_load(s);
    const double lambda = 1 / characteristic_length(s);
    for (const double lambda_a : {0.5, 2.0, 10.0, 100.0, 1e4})
      {
        const double a = lambda_a / lambda, moment = q * a * a / 2;
        const double ratio = energy_release_rate(s, a) / (moment * moment / (2 * d));
        EXPECT_NEAR(ratio, std::pow(1 + 1 / lambda_a, 4), 1e-12 * ratio) << "λa = " << lambda_a;
      }
    const double a = 1e4 / lambda, moment = q * a * a / 2;
    EXPECT_NEAR(energy_release_rate(s, a) / (moment * moment / (2 * d)), 1, 5e-4);
  }

  /// The closed form against −ΔΠ/Δa of the numerical model (uncoupled, e = 0). Errors of the
  /// numerical G: the central difference over δ = one element, (δ²/6) G'''/G = 4 (λδ)²/(1 + λa)³
  /// <= 9e-5 for λδ = 0.0047 (observed: 1.2e-5 at a = 0.3 m, falling 4× per halving of δ); the
  /// Hermite discretisation, O((λδ)⁴) in Π; the finite column, semi_infinite_column_error_estimate()
  /// < 1e-5 (checked); round-off of the solve, ~1e-5 at 8000 elements. So 3e-4 has a margin of
  /// three, and a missing factor (1 + λa) or a 1 % error in λ fails it by far.
  TEST(ClosedFormsEnergyReleaseRate, MatchesNumericalPotentialEnergyFlat)
  {
    const SlabOnFoundation s = typical();
    const double column = 6;
    const BeamModel model = BeamModel::of(s, column, 4000, false);
    for (const unsigned int cut_elements : {2u, 100u, 200u, 400u, 800u})
      {
        const double a = cut_elements * model.element_size();
        ASSERT_LT(semi_infinite_column_error_estimate(s, a + model.element_size(), column), 1e-5);
        const double expected = energy_release_rate(s, a);
        EXPECT_NEAR(model.energy_release_rate(cut_elements), expected, 3e-4 * expected) << "a = " << a;
      }
  }

  /// As above on a 30° slope: mode II adds q_t²(1 + μa)²/(2k_t) (μ(L − a) >= 6.7, so the
  /// semi-infinite bar is good to < 1e-4).
  TEST(ClosedFormsEnergyReleaseRate, MatchesNumericalPotentialEnergySlope)
  {
    const SlabOnFoundation s = typical(pi / 6);
    const double column = 6;
    const BeamModel model = BeamModel::of(s, column, 4000, false);
    for (const unsigned int cut_elements : {2u, 100u, 200u, 400u, 800u})
      {
        const double a = cut_elements * model.element_size();
        ASSERT_LT(semi_infinite_column_error_estimate(s, a + model.element_size(), column), 1e-4);
        const double expected = energy_release_rate(s, a);
        EXPECT_NEAR(model.energy_release_rate(cut_elements), expected, 3e-4 * expected) << "a = " << a;
        // Mode II matters here: without it the closed form would be off by more than the tolerance.
        EXPECT_GT(energy_release_rate_mode_II(s, a), 3e-3 * expected);
      }
  }

  // =============================================================================================
  // Cut length for a fracture energy

  TEST(ClosedFormsCutLength, InvertsEnergyReleaseRate)
  {
    for (const double slope : {0.0, 0.6})
      for (const double gc : {0.1, 0.5, 1.0, 10.0})
        {
          const SlabOnFoundation s = typical(slope);
          const double a = cut_length_for_fracture_energy(s, gc);
          EXPECT_GT(a, 0);
          // The root is bracketed to ~1e-15 relative; G' a / G <= 4, so G(a) within ~1e-14 of G_c.
          EXPECT_NEAR(energy_release_rate(s, a), gc, 1e-12 * gc) << "slope " << slope << ", G_c " << gc;
        }
  }

  /// Flat: (1 + λa)⁴ = G_c / G(0) in closed form.
  TEST(ClosedFormsCutLength, FlatCaseMatchesQuarticRoot)
  {
    const SlabOnFoundation s = typical();
    const double g0 = energy_release_rate(s, 0), lambda = 1 / characteristic_length(s);
    for (const double gc : {0.1, 0.5, 1.0})
      EXPECT_NEAR(cut_length_for_fracture_energy(s, gc), (std::pow(gc / g0, 0.25) - 1) / lambda, 1e-12);
  }

  TEST(ClosedFormsCutLength, RejectsUnreachableFractureEnergies)
  {
    const SlabOnFoundation s = typical(0.5);
    const double g0 = energy_release_rate(s, 0);
    expect_throw_naming<std::domain_error>([&] { cut_length_for_fracture_energy(s, g0); }, "G(0)");
    expect_throw_naming<std::domain_error>([&] { cut_length_for_fracture_energy(s, 0.5 * g0); }, "G(0)");
    expect_throw_naming<std::domain_error>([&] { cut_length_for_fracture_energy(s, 1e30); }, "characteristic lengths");
    expect_throw_naming<std::invalid_argument>([&] { cut_length_for_fracture_energy(s, -1); }, "fracture_energy");
    expect_throw_naming<std::invalid_argument>([&] { cut_length_for_fracture_energy(s, std::nan("")); },
                                               "fracture_energy");
  }

  /// The sanity numbers quoted in docs/fem_closed_forms.md §7 (flat typical snowpack).
  TEST(ClosedFormsCutLength, TypicalSnowpackNumbers)
  {
    const SlabOnFoundation s = typical();
    EXPECT_NEAR(energy_release_rate(s, 0), 0.0433062, 5e-7);
    EXPECT_NEAR(energy_release_rate(s, 0.2), 0.304742, 5e-6);
    EXPECT_NEAR(energy_release_rate(s, 0.4), 1.124632, 5e-6);
    EXPECT_NEAR(energy_release_rate(s, 0.6), 3.004874, 5e-6);
    EXPECT_NEAR(cut_length_for_fracture_energy(s, 0.5), 0.268273, 5e-6);
  }

  // =============================================================================================
  // Gaume et al. 2017 and Heierli 2005

  /// Flat: τ_g = 0, a_c = Λ sqrt(2 τ_p / σ_n), Λ = sqrt(E'Hh/G_wl) by hand.
  TEST(ClosedFormsGaume2017, FlatLimit)
  {
    const SlabOnFoundation s = typical();
    const double g_wl = s.weak_layer_youngs_modulus / (2 * (1 + s.weak_layer_poisson_ratio));
    const double lambda_gaume =
      std::sqrt(hand_plane_strain_modulus(s) * s.slab_thickness * s.weak_layer_thickness / g_wl);
    for (const double tau_p : {300.0, 1000.0, 3000.0})
      {
        const double expected = lambda_gaume * std::sqrt(2 * tau_p / hand_normal_load(s));
        EXPECT_NEAR(critical_cut_length_gaume2017(s, tau_p), expected, 1e-13 * expected);
      }
  }

  /// 35° slope, τ_p = 1 kPa, evaluated by hand from the printed formula: σ_n = 803.588 Pa,
  /// τ_g = 562.678 Pa, Λ = 0.715542 m → a_c = 0.398028 m. Also the tip shear criterion
  /// τ_g (1 + a_c/Λ) + σ_n a_c²/(2Λ²) = τ_p that the formula solves.
  TEST(ClosedFormsGaume2017, HandValueAndTipShearCriterion)
  {
    const SlabOnFoundation s = typical(35 * pi / 180);
    const double tau_p = 1000, a_c = critical_cut_length_gaume2017(s, tau_p);
    const double sigma_n = hand_normal_load(s), tau_g = hand_tangential_load(s), lambda_gaume = shear_lag_length(s);
    EXPECT_NEAR(a_c, lambda_gaume * (-tau_g + std::sqrt(tau_g * tau_g + 2 * sigma_n * (tau_p - tau_g))) / sigma_n,
                1e-13);
    EXPECT_NEAR(a_c, 0.398028, 5e-6);
    const double x = a_c / lambda_gaume;
    EXPECT_NEAR(tau_g * (1 + x) + sigma_n * x * x / 2, tau_p, 1e-10 * tau_p);
    // The mode-II bar of this library carries exactly the first part at the tip: k_t u(a) = τ_g (1 + a/Λ).
    EXPECT_NEAR(shear_foundation_stiffness(s) * weak_layer_slip_at_tip(s, a_c), tau_g * (1 + x), 1e-12 * tau_p);
    // Steeper slope (τ_g closer to τ_p) shortens a_c.
    EXPECT_LT(critical_cut_length_gaume2017(typical(40 * pi / 180), tau_p), a_c);
  }

  TEST(ClosedFormsGaume2017, RejectsStrengthBelowSlopeLoad)
  {
    const SlabOnFoundation s = typical(35 * pi / 180); // τ_g = 562.678 Pa
    expect_throw_naming<std::domain_error>([&] { critical_cut_length_gaume2017(s, 500); }, "tau_g");
    expect_throw_naming<std::invalid_argument>([&] { critical_cut_length_gaume2017(s, -1); },
                                               "peak_shear_strength");
  }

  /// The two pure limits of the first tip yield, solved by hand from the tip tractions: a strength
  /// in compression only, σ_c, on flat ground gives q_n (1 + λa)² = σ_c, a = (sqrt(σ_c/q_n) − 1)/λ;
  /// a constant shear strength τ_p on a slope gives q_t (1 + μa) = τ_p, a = (τ_p/q_t − 1)/μ (Λ = 1/μ).
  TEST(ClosedFormsFirstTipYield, CompressionAndShearLimits)
  {
    const SlabOnFoundation flat = typical();
    const double q_n = hand_normal_load(flat), sigma_c = 5 * q_n;
    const auto compression_only = [&](const double sigma) { return sigma < sigma_c ? 1e30 : std::nan(""); };
    EXPECT_NEAR(first_tip_yield_cut_length(flat, compression_only),
                (std::sqrt(5.0) - 1) * characteristic_length(flat), 1e-10 * characteristic_length(flat));
    const SlabOnFoundation slope = typical(35 * pi / 180);
    const double tau_g = hand_tangential_load(slope), tau_p = 3 * tau_g;
    EXPECT_NEAR(first_tip_yield_cut_length(slope, [&](double) { return tau_p; }),
                (tau_p / tau_g - 1) * shear_lag_length(slope), 1e-10 * shear_lag_length(slope));
    // A layer that the uncut column already breaks, and one that never fails, are refused.
    expect_throw_naming<std::domain_error>([&] { first_tip_yield_cut_length(slope, [&](double) { return 0.5 * tau_g; }); },
                                           "uncut column");
    expect_throw_naming<std::domain_error>([&] { first_tip_yield_cut_length(flat, [](double) { return 1e30; }); },
                                           "does not reach");
  }

  /// E = 5 MPa, H = 0.4 m, ρ = 250 kg/m³, h_f = 4 mm: D_f = 26 666.7 N m,
  /// c = (9.81 · 26 666.7 / (2 · 0.004 · 250 · 0.4))^{1/4} = 327 000^{1/4} = 23.91316 m/s.
  TEST(ClosedFormsHeierli2005, HandValue)
  {
    EXPECT_NEAR(flexural_wave_speed_heierli2005(5e6, 0.4, 250, 0.004), 23.91316, 5e-6);
    // c ∝ E^{1/4}, h_f^{−1/4}.
    EXPECT_NEAR(flexural_wave_speed_heierli2005(80e6, 0.4, 250, 0.004), 2 * 23.91316, 1e-5);
    EXPECT_NEAR(flexural_wave_speed_heierli2005(5e6, 0.4, 250, 0.064), 23.91316 / 2, 5e-6);
    expect_throw_naming<std::invalid_argument>([] { flexural_wave_speed_heierli2005(5e6, 0.4, 250, 0); },
                                               "collapse_height");
  }

  /// λ = 2.331 (2 h_f D_f / (g ρ H))^{1/4} = 2.331 (2 · 0.004 · 26 666.7 / 981)^{1/4} = 2.331 · 0.682 887
  /// = 1.591 81 m; and c λ / γ = sqrt(D_f / ρH) (the flexural wave of Eq. 16).
  TEST(ClosedFormsHeierli2005, TouchdownHandValue)
  {
    EXPECT_NEAR(touchdown_distance_heierli2005(5e6, 0.4, 250, 0.004), 2.331 * std::pow(2 * 0.004 * 5e6 * 0.064 / 12 / 981, 0.25),
                1e-12);
    EXPECT_NEAR(touchdown_distance_heierli2005(5e6, 0.4, 250, 0.004), 1.59181, 1e-5);
    const double c = flexural_wave_speed_heierli2005(5e6, 0.4, 250, 0.004);
    EXPECT_NEAR(c * touchdown_distance_heierli2005(5e6, 0.4, 250, 0.004) / 2.331, std::sqrt(5e6 * 0.064 / 12 / 100),
                1e-9);
    expect_throw_naming<std::invalid_argument>([] { touchdown_distance_heierli2005(5e6, 0.4, 0, 0.004); }, "slab_density");
  }

  // =============================================================================================
  // The strength a weak layer needs to carry the snowpack (Eqs. 27–28)

  /// Hand values: W = 1000 Pa flat, ν = 0.2 (k = 1/4): p = 500 Pa, q = 750 Pa; on 30°, σ_n = 866.0 Pa,
  /// τ = 500 Pa: p = 433.0 Pa, q = sqrt(649.5² + 3 · 500²) = 1074.8 Pa. β = 1/2, M = 1:
  /// p0² / 2 + 250 p0 − (2 · 750² + 500²) = 0 → p0 = −250 + sqrt(250² + 2 · 1 375 000) = 1427.05 Pa.
  TEST(ClosedFormsCarryingStrength, HandValues)
  {
    const auto flat = confined_layer_invariants(1000, 0, 0.2);
    EXPECT_NEAR(flat.p, 500, 1e-9);
    EXPECT_NEAR(flat.q, 750, 1e-9);
    const auto slope = confined_layer_invariants(1000, M_PI / 6, 0.2);
    EXPECT_NEAR(slope.p, 1000 * std::sqrt(3.) / 2 * 1.5 / 3, 1e-9);
    EXPECT_NEAR(slope.q, std::sqrt(std::pow(1000 * std::sqrt(3.) / 2 * 0.75, 2) + 3 * 500. * 500.), 1e-9);
    EXPECT_NEAR(strength_to_contain(500, 750, 0.5, 1), -250 + std::sqrt(250. * 250 + 2 * 1375000.), 1e-9);
    // β = 0: p0 = p + q² / (M² p), and the β → 0 limit of the general root is continuous
    EXPECT_NEAR(strength_to_contain(500, 750, 0, 1.2), 500 + 750. * 750 / (1.44 * 500), 1e-9);
    EXPECT_NEAR(strength_to_contain(500, 750, 1e-9, 1.2), 500 + 750. * 750 / (1.44 * 500), 1e-3);
    // hydrostatic: the compressive tip itself
    EXPECT_NEAR(strength_to_contain(500, 0, 0.7, 1.3), 500, 1e-9);
  }

  /// The root lies on the surface of the material's own yield function, and the yield function
  /// is homogeneous of degree 2 (the load factor of first yield is p0 / needed).
  TEST(ClosedFormsCarryingStrength, RootLiesOnTheCamClaySurface)
  {
    for (const double beta : {0.0, 0.3, 1.0})
      for (const double M : {0.6, 1.4})
        for (const double q : {0.0, 300.0, 2000.0})
        {
          const double p = 400;
          const double needed = strength_to_contain(p, q, beta, M);
          const double scale = M * M * needed * needed;
          // y = (1 + 2β) q² + M² (p + β p0)(p − p0), written out here again
          const auto y = [&](double pp, double qq, double p0) { return (1 + 2 * beta) * qq * qq + M * M * (pp + beta * p0) * (pp - p0); };
          EXPECT_NEAR(y(p, q, needed), 0, 1e-12 * scale);
          EXPECT_LT(y(p, q, 1.01 * needed), 0);
          EXPECT_GT(y(p, q, 0.99 * needed), 0);
          EXPECT_NEAR(y(0.8 * p, 0.8 * q, 0.8 * needed), 0, 1e-12 * scale);
        }
    EXPECT_THROW(strength_to_contain(0, 1, 0.5, 1), std::invalid_argument);
    EXPECT_THROW(strength_to_contain(1, 1, 1.5, 1), std::invalid_argument);
    EXPECT_THROW(confined_layer_invariants(-1, 0, 0.2), std::invalid_argument);
    EXPECT_THROW(confined_layer_invariants(1, 0, 0.5), std::invalid_argument);
  }

  // =============================================================================================
  // Steady-state touchdown (Eqs. 24–26)

  /// Euler–Bernoulli: a second derivation. With s = βλ, β = (k/4D)^{1/4} and the gap h_t = h_c − q/k
  /// under the settled slab, eliminating the tip amplitudes by hand from w''(λ) = 0 and w'(λ) = 0
  /// leaves s²(s+3)(s³+3s²+6s+6) / (18 (s+1)²) = k h_t / q; solved here by bisection. A stiff
  /// foundation (k → ∞) clamps the slab at the tip: λ → (72 D h_t / q)^{1/4} (1 − 1/s + ...), here
  /// s ≈ 2400.
  TEST(ClosedFormsTouchdown, EulerBernoulliMatchesTheHandReducedEquation)
  {
    for (const double collapse_height : {0.002, 0.003, 0.01})
    {
      const SlabOnFoundation s = typical();
      const double D = hand_bending_stiffness(s), k = hand_normal_stiffness(s), q = hand_normal_load(s);
      const double beta = std::pow(k / (4 * D), 0.25), target = k * (collapse_height - q / k) / q;
      const auto reduced = [](double x) {
        return x * x * (x + 3) * (x * x * x + 3 * x * x + 6 * x + 6) / (18 * (x + 1) * (x + 1));
      };
      double lo = 0, hi = 100;
      for (int i = 0; i < 200; ++i)
        (reduced((lo + hi) / 2) < target ? lo : hi) = (lo + hi) / 2;
      EXPECT_NEAR(steady_state_touchdown_distance(s, collapse_height, SlabShear::euler_bernoulli), lo / beta,
                  1e-9 * lo / beta)
        << "h_c = " << collapse_height;
    }
    SlabOnFoundation stiff = typical();
    stiff.weak_layer_youngs_modulus = 2e16;
    const double D = hand_bending_stiffness(stiff), q = hand_normal_load(stiff);
    EXPECT_NEAR(steady_state_touchdown_distance(stiff, 0.003, SlabShear::euler_bernoulli) /
                  std::pow(72 * D * 0.003 / q, 0.25),
                1, 1e-3);
  }

  /// Timoshenko: an independent implementation (transfer matrices of the first-order system
  /// (w, θ, M, V) by matrix exponentials, the supported part's decaying eigenvectors, the same three
  /// touchdown conditions, Brent's root) gives 0.986 224 646 m for the slab of Rosendahl-type PSTs
  /// E = 5 MPa, ν = 0.25, H = 0.4 m, ρ = 250 kg/m³ on E_wl = 0.2 MPa, ν_wl = 0, h = 2 cm, h_c = 3 mm
  /// (Euler–Bernoulli, 1.234 63 m, is checked above). The slab's shear shortens the span by 20 % here.
  TEST(ClosedFormsTouchdown, TimoshenkoMatchesAnIndependentTransferMatrixSolution)
  {
    SlabOnFoundation s = typical();
    s.weak_layer_poisson_ratio = 0;
    EXPECT_NEAR(steady_state_touchdown_distance(s, 0.003, SlabShear::timoshenko), 0.9862246455, 1e-8);
    // A settlement that already fills the collapse height, and a zero collapse height, are refused.
    expect_throw_naming<std::domain_error>(
      [&] { steady_state_touchdown_distance(s, 0.5 * hand_normal_load(s) / hand_normal_stiffness(s), SlabShear::timoshenko); },
      "settlement");
    expect_throw_naming<std::invalid_argument>(
      [&] { steady_state_touchdown_distance(s, 0, SlabShear::timoshenko); }, "collapse_height");
  }

  // =============================================================================================
  // Model-error estimates

  /// The four estimates by hand for the typical snowpack (λ = 3.14358 /m, μ = 1.39754 /m).
  TEST(ClosedFormsModelError, EstimatesMatchHandValues)
  {
    const SlabOnFoundation s = typical(pi / 6);
    const double lambda = 1 / characteristic_length(s), mu = 1 / shear_lag_length(s);
    const double h = s.slab_thickness, e_prime = hand_plane_strain_modulus(s);
    const double g_slab = s.slab_youngs_modulus / 2.5, g_wl = s.weak_layer_youngs_modulus / 2.4;
    // (a) (λH)² E'/(24 κ G) = (λH)² / (10 (1 − ν)) for κ = 5/6.
    EXPECT_NEAR(timoshenko_shear_error_estimate(s), std::pow(lambda * h, 2) * e_prime / (20 * g_slab), 1e-14);
    EXPECT_NEAR(timoshenko_shear_error_estimate(s), std::pow(lambda * h, 2) / 7.5, 1e-14);
    // (b) (9/8) G_wl / (E' H h λ²) = (9/8) (μ/λ)².
    EXPECT_NEAR(slab_rotation_coupling_error_estimate(s),
                9.0 / 8 * g_wl / (e_prime * h * s.weak_layer_thickness * lambda * lambda), 1e-14);
    EXPECT_NEAR(slab_rotation_coupling_error_estimate(s), 9.0 / 8 * std::pow(mu / lambda, 2), 1e-14);
    // (c) ν_wl = 0.2 is a table node: 4 · 0.03100 λh + 2 · 0.17434 μh.
    EXPECT_NEAR(weak_layer_thickness_error_estimate(s),
                4 * 0.03100 * lambda * s.weak_layer_thickness + 2 * 0.17434 * mu * s.weak_layer_thickness, 1e-14);
    // (d) 2 λH tan ψ.
    EXPECT_NEAR(slope_coupling_error_estimate(s), 2 * lambda * h * std::tan(pi / 6), 1e-14);
    EXPECT_NEAR(beam_model_error_estimate(s),
                timoshenko_shear_error_estimate(s) + slab_rotation_coupling_error_estimate(s) +
                  weak_layer_thickness_error_estimate(s) + slope_coupling_error_estimate(s),
                1e-15);
    // Between table nodes the coefficients are interpolated linearly: ν_wl = 0.225 lies halfway
    // between 0.2 and 0.25.
    SlabOnFoundation between = s;
    between.weak_layer_poisson_ratio = 0.225;
    EXPECT_NEAR(weak_layer_thickness_error_estimate(between),
                4 * (0.03100 + 0.05807) / 2 / characteristic_length(between) * s.weak_layer_thickness +
                  2 * (0.17434 + 0.16650) / 2 / shear_lag_length(between) * s.weak_layer_thickness,
                1e-14);
    SlabOnFoundation auxetic = s;
    auxetic.weak_layer_poisson_ratio = -0.5;
    expect_throw_naming<std::domain_error>([&] { weak_layer_thickness_error_estimate(auxetic); },
                                           "weak_layer_poisson_ratio");
  }

  /// (b) with the numerical model: the coupled model (weak-layer shear acting on the bottom fibre,
  /// slip u − (H/2) w') against the uncoupled one on the same mesh, flat. First order (Eq. 19, axial
  /// displacement held fixed): ΔG/G = −3 λa/(1 + λa)² ε_b. The free bar relieves part of the slip
  /// (a correction of order μ/λ ≈ 0.1), so the ratio lies in [0.8, 1]; it is within the estimate.
  TEST(ClosedFormsModelError, SlabRotationCouplingMatchesFirstOrder)
  {
    const SlabOnFoundation s = stiff_slab();
    const double lambda = 1 / characteristic_length(s), mu = 1 / shear_lag_length(s);
    ASSERT_NEAR(mu / lambda, 0.1, 0.01);
    const double epsilon_b = slab_rotation_coupling_error_estimate(s) / 0.75;
    const double column = 10 / mu; // the bar's response to the coupling decays over 1/μ
    const unsigned int elements = static_cast<unsigned int>(std::ceil(column * lambda / 0.005));
    const BeamModel uncoupled = BeamModel::of(s, column, elements, false);
    const BeamModel coupled = BeamModel::of(s, column, elements, true);
    for (const double lambda_a : {0.5, 1.0, 2.0})
      {
        const unsigned int cut = static_cast<unsigned int>(std::round(lambda_a / lambda / uncoupled.element_size()));
        const double a = cut * uncoupled.element_size(), x = lambda * a;
        const double g0 = uncoupled.energy_release_rate(cut);
        const double change = coupled.energy_release_rate(cut) / g0 - 1;
        const double first_order = -3 * x / ((1 + x) * (1 + x)) * epsilon_b;
        EXPECT_GE(change / first_order, 0.8) << "λa = " << x << ", ΔG/G = " << change;
        EXPECT_LE(change / first_order, 1.0) << "λa = " << x << ", ΔG/G = " << change;
        EXPECT_LE(std::abs(change), slab_rotation_coupling_error_estimate(s));
      }
  }

  /// (d) with the numerical model: the part of the coupled G that is odd in ψ (the two cut
  /// directions) against the first-order result of Eq. 21,
  ///   ΔG = −(q_n²/(2k_n)) 2λH tan ψ N(λa, μ/λ)/(m² + 2m + 2), m = μ/λ,
  ///   N = 3x²m² + 3x²m + 3xm² + 6xm + 2x + m² + 2m + 2, x = λa,
  /// within 10 % (second-order terms O(m²) and O((λH tan ψ)²) odd parts); and |ΔG|/G within the
  /// estimate 2λH |tan ψ|.
  TEST(ClosedFormsModelError, SlopeCouplingMatchesFirstOrder)
  {
    const double slope = 0.15;
    const SlabOnFoundation up = stiff_slab(slope), down = stiff_slab(-slope);
    const double lambda = 1 / characteristic_length(up), m = 1 / shear_lag_length(up) / lambda;
    const double column = 10 / (m * lambda);
    const unsigned int elements = static_cast<unsigned int>(std::ceil(column * lambda / 0.005));
    const BeamModel coupled_up = BeamModel::of(up, column, elements, true);
    const BeamModel coupled_down = BeamModel::of(down, column, elements, true);
    const double qn = hand_normal_load(up), kn = hand_normal_stiffness(up);
    for (const double lambda_a : {0.05, 0.5, 2.0})
      {
        const unsigned int cut = static_cast<unsigned int>(std::round(lambda_a / lambda / coupled_up.element_size()));
        const double a = cut * coupled_up.element_size(), x = lambda * a;
        const double odd = (coupled_up.energy_release_rate(cut) - coupled_down.energy_release_rate(cut)) / 2;
        const double n = 3 * x * x * m * m + 3 * x * x * m + 3 * x * m * m + 6 * x * m + 2 * x + m * m + 2 * m + 2;
        const double first_order = -qn * qn / (2 * kn) * 2 * lambda * up.slab_thickness * std::tan(slope) * n /
                                   (m * m + 2 * m + 2);
        EXPECT_NEAR(odd / first_order, 1, 0.1) << "λa = " << x;
        EXPECT_LE(std::abs(odd) / energy_release_rate(up, a), slope_coupling_error_estimate(up)) << "λa = " << x;
      }
  }

  /// The finite-column estimate bounds the numerical error of short columns (λ(L − a) = 3, where the
  /// estimate is 17 e^{−6} ≈ 0.04, and 3π/2 with a long cut, where the bound is nearly reached:
  /// 16.0 e^{−2λℓ} for λa → ∞, 15.3 e^{−2λℓ} at λa = 5), and the error is real (well above the
  /// numerical ~1e-5).
  TEST(ClosedFormsModelError, SemiInfiniteEstimateBoundsShortColumn)
  {
    const SlabOnFoundation s = typical(); // flat: mode I only
    const double lambda = 1 / characteristic_length(s);
    const double cases[4][2] = {{0.5, 3}, {1, 3}, {3, 3}, {5, 1.5 * pi}};
    for (const auto &c : cases)
      {
        const double lambda_a = c[0], lambda_l = c[1];
        const double column = (lambda_a + lambda_l) / lambda;
        const BeamModel model =
          BeamModel::of(s, column, static_cast<unsigned int>(std::round(column * lambda / 0.005)), false);
        const unsigned int cut = static_cast<unsigned int>(std::round(lambda_a / lambda / model.element_size()));
        const double a = cut * model.element_size();
        const double error = std::abs(model.energy_release_rate(cut) / energy_release_rate(s, a) - 1);
        const double estimate = semi_infinite_column_error_estimate(s, a, column);
        EXPECT_LE(error, estimate) << "λa = " << lambda_a << ", λℓ = " << lambda_l;
        EXPECT_GT(error, 1e-3) << "λa = " << lambda_a << ", λℓ = " << lambda_l;
        if (lambda_a == 5)
          {
            EXPECT_GT(error, 0.8 * estimate) << "the bound is nearly reached here";
          }
      }
    expect_throw_naming<std::invalid_argument>([&] { semi_infinite_column_error_estimate(s, 1, 1); },
                                               "column_length");
  }

  /// The mode-II part of the finite-column estimate: ψ = 1.5 rad makes mode II carry ~85 % of G;
  /// a = 2/μ, ℓ = 1/μ. The exact mode-II error is ((1 + μa coth μℓ)/(1 + μa))² − 1 = 0.46, the
  /// bound 2d + d² = 0.72 (d = coth 1 − 1); mode I (λℓ = 2.25) adds at most 17 e^{−4.5} of G_I.
  TEST(ClosedFormsModelError, SemiInfiniteEstimateBoundsShortColumnModeII)
  {
    const SlabOnFoundation s = typical(1.5);
    const double mu = 1 / shear_lag_length(s), lambda = 1 / characteristic_length(s);
    const double column = 3 / mu;
    const BeamModel model =
      BeamModel::of(s, column, static_cast<unsigned int>(std::round(column * lambda / 0.005)), false);
    const unsigned int cut = static_cast<unsigned int>(std::round(2 / mu / model.element_size()));
    const double a = cut * model.element_size();
    ASSERT_GT(energy_release_rate_mode_II(s, a), 0.8 * energy_release_rate(s, a));
    const double error = std::abs(model.energy_release_rate(cut) / energy_release_rate(s, a) - 1);
    const double estimate = semi_infinite_column_error_estimate(s, a, column);
    EXPECT_LE(error, estimate);
    EXPECT_GT(error, 0.4 * estimate);
  }
} // namespace
