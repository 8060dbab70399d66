// Closed forms of the PST and the elastic helpers. The equations (numbers as in the header) are
// derived in docs/fem_closed_forms.md; comments here say which one each function evaluates.
#include "fem/closed_forms.h"

#include <boost/math/tools/toms748_solve.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

namespace anticrack::fem::closed_forms
{
  namespace
  {
    constexpr double half_pi = 1.57079632679489661923;

    std::string describe(const char *name, double value, const char *range)
    {
      std::ostringstream out;
      out << std::setprecision(10) << "closed forms: '" << name << "' = " << value << " must be " << range;
      return out.str();
    }

    void require(bool condition, const char *name, double value, const char *range)
    {
      if (!condition || !std::isfinite(value))
        throw std::invalid_argument(describe(name, value, range));
    }

    void require_positive(const char *name, double value)
    {
      require(value > 0, name, value, "finite and > 0");
    }

    void require_poisson_ratio(const char *name, double value)
    {
      require(value > -1 && value < 0.5, name, value, "in (-1, 1/2)");
    }

    void require_cut_length(double cut_length)
    {
      require(cut_length >= 0, "cut_length", cut_length, "finite and >= 0 [m]");
    }

    double weak_layer_shear_modulus(const SlabOnFoundation &s)
    {
      return shear_modulus(s.weak_layer_youngs_modulus, s.weak_layer_poisson_ratio);
    }

    double slab_plane_strain_modulus(const SlabOnFoundation &s)
    {
      return plane_strain_modulus(s.slab_youngs_modulus, s.slab_poisson_ratio);
    }

    /// Piecewise-linear interpolation in a table over ν_wl = −0.3, −0.25, ..., 0.45.
    double interpolate_in_poisson_ratio(const std::array<double, 16> &table, double poisson_ratio)
    {
      constexpr double first = -0.3, step = 0.05;
      const double last = first + step * (table.size() - 1);
      if (!(poisson_ratio >= first && poisson_ratio <= last))
        {
          std::ostringstream out;
          out << std::setprecision(10) << "closed forms: the weak-layer edge coefficients are tabulated for "
              << "weak_layer_poisson_ratio in [" << first << ", " << last << "], not " << poisson_ratio;
          throw std::domain_error(out.str());
        }
      const double position = (poisson_ratio - first) / step;
      const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(position), table.size() - 2);
      const double t = position - i;
      return (1 - t) * table[i] + t * table[i + 1];
    }

    /// Edge coefficients of a plane-strain elastic strip of thickness h, bonded to rigid bodies above
    /// and below, with a free end face (Eq. 20): the continuum stores C h less energy than the
    /// springs under the same top displacement, in units of the spring energy density ½ k δ² times
    /// h. Computed with Q4 elements graded to the corners (640 × 160 on a strip 8h long; the
    /// 320 × 80 mesh agrees within 0.1 % for ν <= 0.3 and 0.2 % at 0.45), docs/fem_closed_forms.md §6.
    /// Mode I: top displaced normal to the layer; C_I = 0 at ν = 0, where uniaxial strain already
    /// satisfies the free face.
    constexpr std::array<double, 16> edge_coefficient_normal = {{
      0.02206, 0.01668, 0.01167, 0.00722, 0.00354, 0.00099, 0.0, 0.00125,
      0.00570, 0.01484, 0.03100, 0.05807, 0.10303, 0.17996, 0.32310, 0.65637}};
    /// Mode II: top displaced parallel to the layer (the free face must carry no shear).
    constexpr std::array<double, 16> edge_coefficient_shear = {{
      0.23125, 0.22678, 0.22210, 0.21720, 0.21206, 0.20665, 0.20093, 0.19489,
      0.18848, 0.18165, 0.17434, 0.16650, 0.15803, 0.14883, 0.13875, 0.12757}};

    /// Largest |ΔG|/G of the finite-column mode-I error over a >= 0 and λℓ >= 2, in units of
    /// e^{−2λℓ} (a scan of the exact finite solution: 16.01 at λℓ ≈ 3π/2, a → ∞), rounded up.
    constexpr double finite_column_mode_I_coefficient = 17;
  } // namespace

  // --- Eq. 1 -------------------------------------------------------------------------------------

  double plane_strain_modulus(double youngs_modulus, double poisson_ratio)
  {
    require_positive("youngs_modulus", youngs_modulus);
    require_poisson_ratio("poisson_ratio", poisson_ratio);
    return youngs_modulus / (1 - poisson_ratio * poisson_ratio);
  }

  double constrained_modulus(double youngs_modulus, double poisson_ratio)
  {
    require_positive("youngs_modulus", youngs_modulus);
    require_poisson_ratio("poisson_ratio", poisson_ratio);
    return youngs_modulus * (1 - poisson_ratio) / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
  }

  double shear_modulus(double youngs_modulus, double poisson_ratio)
  {
    require_positive("youngs_modulus", youngs_modulus);
    require_poisson_ratio("poisson_ratio", poisson_ratio);
    return youngs_modulus / (2 * (1 + poisson_ratio));
  }

  double p_wave_speed(double bulk_modulus, double shear_modulus, double density)
  {
    require_positive("bulk_modulus", bulk_modulus);
    require_positive("shear_modulus", shear_modulus);
    require_positive("density", density);
    return std::sqrt((bulk_modulus + 4 * shear_modulus / 3) / density);
  }

  double shear_wave_speed(double shear_modulus, double density)
  {
    require_positive("shear_modulus", shear_modulus);
    require_positive("density", density);
    return std::sqrt(shear_modulus / density);
  }


  // --- Eqs. 2–3 ----------------------------------------------------------------------------------

  void SlabOnFoundation::check() const
  {
    require_positive("slab_thickness [m]", slab_thickness);
    require_positive("slab_youngs_modulus [Pa]", slab_youngs_modulus);
    require_poisson_ratio("slab_poisson_ratio", slab_poisson_ratio);
    require_positive("slab_density [kg/m^3]", slab_density);
    require_positive("weak_layer_thickness [m]", weak_layer_thickness);
    require_positive("weak_layer_youngs_modulus [Pa]", weak_layer_youngs_modulus);
    require_poisson_ratio("weak_layer_poisson_ratio", weak_layer_poisson_ratio);
    require_positive("gravity [m/s^2]", gravity);
    require(std::abs(slope_angle) < half_pi, "slope_angle [rad]", slope_angle, "in (-pi/2, pi/2)");
  }

  double slab_bending_stiffness(const SlabOnFoundation &s)
  {
    s.check();
    return slab_plane_strain_modulus(s) * std::pow(s.slab_thickness, 3) / 12;
  }

  double slab_axial_stiffness(const SlabOnFoundation &s)
  {
    s.check();
    return slab_plane_strain_modulus(s) * s.slab_thickness;
  }

  double normal_foundation_stiffness(const SlabOnFoundation &s)
  {
    s.check();
    return constrained_modulus(s.weak_layer_youngs_modulus, s.weak_layer_poisson_ratio) / s.weak_layer_thickness;
  }

  double shear_foundation_stiffness(const SlabOnFoundation &s)
  {
    s.check();
    return weak_layer_shear_modulus(s) / s.weak_layer_thickness;
  }

  double normal_load(const SlabOnFoundation &s)
  {
    s.check();
    return s.slab_density * s.gravity * s.slab_thickness * std::cos(s.slope_angle);
  }

  double tangential_load(const SlabOnFoundation &s)
  {
    s.check();
    return s.slab_density * s.gravity * s.slab_thickness * std::sin(s.slope_angle);
  }

  double characteristic_length(const SlabOnFoundation &s)
  {
    return std::pow(4 * slab_bending_stiffness(s) / normal_foundation_stiffness(s), 0.25);
  }

  double shear_lag_length(const SlabOnFoundation &s)
  {
    return std::sqrt(slab_axial_stiffness(s) / shear_foundation_stiffness(s));
  }

  // --- Eqs. 4–7, 11: the fields -------------------------------------------------------------------

  SlabDeflection slab_deflection(const SlabOnFoundation &s, double cut_length, double x)
  {
    require_cut_length(cut_length);
    require(x >= 0, "x", x, "finite and >= 0 [m]");
    const double a = cut_length;
    const double lambda = 1 / characteristic_length(s);
    const double bending_stiffness = slab_bending_stiffness(s);
    const double q = normal_load(s);
    const double settlement = q / normal_foundation_stiffness(s);
    // Eqs. 5–6: w = q/k + e^{−λξ}(C1 cos λξ + C2 sin λξ), ξ = x − a; the tip conditions fix
    // C1 = w(a) − q/k (Eq. 7) and C2 = −(q/k)(λa)².
    const double c1 = weak_layer_compression_at_tip(s, a) - settlement;
    const double c2 = -settlement * (lambda * a) * (lambda * a);
    const double xi = x - a;
    SlabDeflection d;
    if (xi >= 0)
      {
        const double decay = std::exp(-lambda * xi), c = std::cos(lambda * xi), sn = std::sin(lambda * xi);
        d.w = settlement + decay * (c1 * c + c2 * sn);
        d.dw_dx = lambda * decay * ((c2 - c1) * c - (c1 + c2) * sn);
        d.d2w_dx2 = 2 * lambda * lambda * decay * (c1 * sn - c2 * c);
        d.d3w_dx3 = 2 * lambda * lambda * lambda * decay * ((c1 + c2) * c + (c2 - c1) * sn);
        return d;
      }
    // Eq. 4: the cantilever D w'''' = q is the Taylor quartic about the tip, with the tip's w, w'
    // and the statically determinate w''(a) = q a²/(2D), w'''(a) = q a / D (free end at x = 0).
    const SlabDeflection tip = slab_deflection(s, a, a);
    const double fourth = q / bending_stiffness;
    d.w = tip.w + xi * (tip.dw_dx + xi * (tip.d2w_dx2 / 2 + xi * (tip.d3w_dx3 / 6 + xi * fourth / 24)));
    d.dw_dx = tip.dw_dx + xi * (tip.d2w_dx2 + xi * (tip.d3w_dx3 / 2 + xi * fourth / 6));
    d.d2w_dx2 = tip.d2w_dx2 + xi * (tip.d3w_dx3 + xi * fourth / 2);
    d.d3w_dx3 = tip.d3w_dx3 + xi * fourth;
    return d;
  }

  SlabAxialDisplacement slab_axial_displacement(const SlabOnFoundation &s, double cut_length, double x)
  {
    require_cut_length(cut_length);
    require(x >= 0, "x", x, "finite and >= 0 [m]");
    const double a = cut_length;
    const double mu = 1 / shear_lag_length(s);
    const double slip = tangential_load(s) / shear_foundation_stiffness(s);
    // Eq. 11: u = q_t/k_t + B e^{−μξ} with B = u(a) − q_t/k_t, so that N(a) = E'H u'(a) = −q_t a.
    const double amplitude = weak_layer_slip_at_tip(s, a) - slip;
    const double xi = x - a;
    if (xi >= 0)
      {
        const double decay = std::exp(-mu * xi);
        return {slip + amplitude * decay, -mu * amplitude * decay};
      }
    // The free bar E'H u'' = −q_t with N(0) = 0: the Taylor quadratic about the tip.
    const double tip_strain = -mu * amplitude;
    const double strain_gradient = -tangential_load(s) / slab_axial_stiffness(s);
    return {weak_layer_slip_at_tip(s, a) + xi * (tip_strain + xi * strain_gradient / 2),
            tip_strain + xi * strain_gradient};
  }

  double weak_layer_compression_at_tip(const SlabOnFoundation &s, double cut_length)
  {
    require_cut_length(cut_length);
    // Eq. 7
    const double one_plus_lambda_a = 1 + cut_length / characteristic_length(s);
    return normal_load(s) / normal_foundation_stiffness(s) * one_plus_lambda_a * one_plus_lambda_a;
  }

  double weak_layer_slip_at_tip(const SlabOnFoundation &s, double cut_length)
  {
    require_cut_length(cut_length);
    // Eq. 11
    return tangential_load(s) / shear_foundation_stiffness(s) * (1 + cut_length / shear_lag_length(s));
  }

  // --- Eqs. 9–14: energy release rate -------------------------------------------------------------

  double energy_release_rate_mode_I(const SlabOnFoundation &s, double cut_length)
  {
    // Eq. 9: G = −dΠ/da is the spring energy density at the tip (envelope theorem).
    const double w = weak_layer_compression_at_tip(s, cut_length);
    return normal_foundation_stiffness(s) * w * w / 2;
  }

  double energy_release_rate_mode_II(const SlabOnFoundation &s, double cut_length)
  {
    // Eq. 12
    const double u = weak_layer_slip_at_tip(s, cut_length);
    return shear_foundation_stiffness(s) * u * u / 2;
  }

  double energy_release_rate(const SlabOnFoundation &s, double cut_length)
  {
    return energy_release_rate_mode_I(s, cut_length) + energy_release_rate_mode_II(s, cut_length);
  }

  double cut_length_for_fracture_energy(const SlabOnFoundation &s, double fracture_energy)
  {
    require_positive("fracture_energy [J/m^2]", fracture_energy);
    const double g0 = energy_release_rate(s, 0);
    if (g0 >= fracture_energy)
      {
        std::ostringstream out;
        out << std::setprecision(10) << "closed forms: the uncut column already releases G(0) = " << g0
            << " J/m^2 >= fracture_energy = " << fracture_energy << " J/m^2: no saw cut is needed";
        throw std::domain_error(out.str());
      }
    // Eq. 14: f(a) = G(a) − G_c increases strictly from f(0) < 0. Double the upper end of the
    // bracket from 1/λ until f >= 0 or the cap is passed.
    const double length = characteristic_length(s);
    const double cap = maximum_cut_length_in_characteristic_lengths * length;
    const auto f = [&](double a) { return energy_release_rate(s, a) - fracture_energy; };
    double lower = 0, upper = length;
    while (f(upper) < 0)
      {
        if (upper >= cap)
          {
            std::ostringstream out;
            out << std::setprecision(10) << "closed forms: fracture_energy = " << fracture_energy
                << " J/m^2 exceeds G = " << energy_release_rate(s, cap) << " J/m^2 at the largest cut length "
                << cap << " m (" << maximum_cut_length_in_characteristic_lengths << " characteristic lengths)";
            throw std::domain_error(out.str());
          }
        lower = upper;
        upper = std::min(2 * upper, cap);
      }
    if (f(upper) == 0)
      return upper;
    std::uintmax_t iterations = 200;
    // 50 bits: the bracket ends within ~1e-15 relative; G is smooth, so TOMS 748 gets there in a
    // handful of steps.
    const auto [left, right] = boost::math::tools::toms748_solve(
      f, lower, upper, f(lower), f(upper), boost::math::tools::eps_tolerance<double>(50), iterations);
    return (left + right) / 2;
  }

  // --- Eqs. 15–16: literature ------------------------------------------------------------------------

  double critical_cut_length_gaume2017(const SlabOnFoundation &s, double peak_shear_strength)
  {
    require_positive("peak_shear_strength [Pa]", peak_shear_strength);
    const double sigma_n = normal_load(s), tau_g = tangential_load(s), tau_p = peak_shear_strength;
    if (tau_p <= tau_g)
      {
        std::ostringstream out;
        out << std::setprecision(10) << "closed forms: peak_shear_strength = " << tau_p
            << " Pa must exceed the slope-parallel weight tau_g = " << tau_g
            << " Pa (otherwise the weak layer fails without a cut)";
        throw std::domain_error(out.str());
      }
    // Eq. 15; the root is written as 2(τ_p − τ_g) / (τ_g + sqrt(...)) so that it does not cancel
    // when τ_g² ≫ σ_n (τ_p − τ_g) (steep slopes); the two forms are equal.
    const double root = std::sqrt(tau_g * tau_g + 2 * sigma_n * (tau_p - tau_g));
    return shear_lag_length(s) * 2 * (tau_p - tau_g) / (tau_g + root);
  }

  double first_tip_yield_cut_length(const SlabOnFoundation &s, const std::function<double(double)> &shear_strength)
  {
    s.check();
    const double lambda = 1 / characteristic_length(s);
    const double q_n = normal_load(s), q_t = std::abs(tangential_load(s));
    const double k_n = normal_foundation_stiffness(s), k_t = shear_foundation_stiffness(s);
    // Failed: the tip's shear traction k_t |u(a)| (Eq. 11) at or above the strength at its normal
    // traction k_n w(a) (Eq. 7); a NaN strength, σ beyond the surface, fails too.
    const auto fails = [&](const double a) {
      const double strength = shear_strength(k_n * weak_layer_compression_at_tip(s, a));
      return !(k_t * std::abs(weak_layer_slip_at_tip(s, a)) < strength);
    };
    if (fails(0))
      throw std::domain_error("closed forms: the weak layer under the uncut column already reaches its strength "
                              "(sigma_n = " + std::to_string(q_n) + " Pa, tau_g = " + std::to_string(q_t) + " Pa)");
    const double step = 0.01 / lambda, cap = maximum_cut_length_in_characteristic_lengths / lambda;
    double lower = 0, upper = step;
    while (!fails(upper))
    {
      if (upper >= cap)
        throw std::domain_error("closed forms: the crack tip does not reach the weak layer's strength up to a cut of " +
                                std::to_string(cap) + " m");
      lower = upper;
      upper = std::min(upper + step, cap);
    }
    while (upper - lower > 1e-12 * upper)
    {
      const double middle = 0.5 * (lower + upper);
      (fails(middle) ? upper : lower) = middle;
    }
    return upper;
  }

  double flexural_wave_speed_heierli2005(double youngs_modulus,
                                         double slab_thickness,
                                         double slab_density,
                                         double collapse_height,
                                         double gravity)
  {
    require_positive("youngs_modulus [Pa]", youngs_modulus);
    require_positive("slab_thickness [m]", slab_thickness);
    require_positive("slab_density [kg/m^3]", slab_density);
    require_positive("collapse_height [m]", collapse_height);
    require_positive("gravity [m/s^2]", gravity);
    // Eq. 16 (docs/physics.md §3 uses E, not E', in D_f).
    const double flexural_rigidity = youngs_modulus * std::pow(slab_thickness, 3) / 12;
    return std::pow(gravity * flexural_rigidity / (2 * collapse_height * slab_density * slab_thickness), 0.25);
  }

  double touchdown_distance_heierli2005(double youngs_modulus,
                                        double slab_thickness,
                                        double slab_density,
                                        double collapse_height,
                                        double gravity)
  {
    // Eq. 23 written through Eq. 16: λ_H = γ sqrt(D_f / ρH) / c (the speed checks the arguments).
    const double speed =
      flexural_wave_speed_heierli2005(youngs_modulus, slab_thickness, slab_density, collapse_height, gravity);
    const double flexural_rigidity = youngs_modulus * std::pow(slab_thickness, 3) / 12;
    return heierli2005_touchdown_factor * std::sqrt(flexural_rigidity / (slab_density * slab_thickness)) / speed;
  }

  // --- Eqs. 24–26: steady-state touchdown --------------------------------------------------------------

  double steady_state_touchdown_distance(const SlabOnFoundation &s, double collapse_height, SlabShear shear)
  {
    s.check();
    require_positive("collapse_height [m]", collapse_height);
    const double D = slab_bending_stiffness(s), k = normal_foundation_stiffness(s), q = normal_load(s);
    if (!(collapse_height > q / k))
    {
      std::ostringstream out;
      out << std::setprecision(6) << "closed forms: the settlement q_n / k_n = " << q / k
          << " m of the slab on the weak layer already fills the collapse height " << collapse_height
          << " m: the slab rests on the collapsed layer right behind the tip";
      throw std::domain_error(out.str());
    }
    // 1/S: the slab's shear compliance (0 for Euler–Bernoulli).
    const double shear_compliance =
      shear == SlabShear::timoshenko
        ? 1 / (rectangular_shear_correction * shear_modulus(s.slab_youngs_modulus, s.slab_poisson_ratio) *
               s.slab_thickness)
        : 0.;

    // The supported part x <= 0, Eq. 24: w = q/k + w̃, with w̃ = Σ c_j φ_j decaying as x → −∞, each
    // mode e^{rx} a root of D r⁴ − D k r²/S + k = 0 with Re r > 0. A mode carries the state
    // (w̃, θ, M, V) = (1, −k/(D r³), k/r², k/r) e^{rx} (w' = θ + V/S, θ' = −M/D, M' = V, V' = k w̃).
    using Complex = std::complex<double>;
    const Complex discriminant = std::sqrt(Complex(std::pow(D * k * shear_compliance, 2) - 4 * D * k));
    const std::array<Complex, 2> roots = {{std::sqrt((D * k * shear_compliance + discriminant) / (2 * D)),
                                           std::sqrt((D * k * shear_compliance - discriminant) / (2 * D))}};
    const auto mode_state = [&](Complex r) {
      return std::array<Complex, 4>{{1., -k / (D * r * r * r), k / (r * r), k / r}};
    };
    // Two real modes: Re and Im of one complex root (the pair is conjugate), or the two real roots.
    std::array<std::array<double, 4>, 2> modes;
    const bool oscillating = std::abs(roots[0].imag()) > 1e-12 * std::abs(roots[0]);
    for (unsigned int i = 0; i < 4; ++i)
    {
      const std::array<Complex, 4> first = mode_state(roots[0]), second = mode_state(roots[1]);
      modes[0][i] = first[i].real();
      modes[1][i] = oscillating ? first[i].imag() : second[i].real();
    }

    // The unsupported span 0 <= x <= λ under q (Eq. 25), from the tip state (w0, θ0, M0, V0):
    // V = V0 − q x, M = M0 + V0 x − q x²/2, θ = θ0 − (M0 x + V0 x²/2 − q x³/6)/D,
    // w = w0 + θ0 x − (M0 x²/2 + V0 x³/6 − q x⁴/24)/D + (V0 x − q x²/2)/S.
    struct SpanEnd
    {
      double w, theta, moment, shear_force;
    };
    const auto span_end = [&](const std::array<double, 4> &tip, double x, bool with_load) {
      const double load = with_load ? q : 0.;
      const double w0 = tip[0] + (with_load ? q / k : 0.), theta0 = tip[1], M0 = tip[2], V0 = tip[3];
      return SpanEnd{w0 + theta0 * x - (M0 * x * x / 2 + V0 * x * x * x / 6 - load * std::pow(x, 4) / 24) / D +
                       (V0 * x - load * x * x / 2) * shear_compliance,
                     theta0 - (M0 * x + V0 * x * x / 2 - load * x * x * x / 6) / D, M0 + V0 * x - load * x * x / 2,
                     V0 - load * x};
    };
    // At the touchdown x = λ (Eq. 26): w' = θ + V/S = 0 and M = sqrt(D S) θ, i.e. M + sqrt(D/S) V = 0
    // (the rested slab, w' = 0 on the base, is a rotational spring sqrt(D S); M = 0 without shear).
    // Both are linear in the two mode amplitudes; the deflection there, less h_c, is the residual.
    const double rested_arm = std::sqrt(D * shear_compliance);
    const auto conditions = [&](const SpanEnd &e) {
      return std::array<double, 2>{{e.theta + e.shear_force * shear_compliance, e.moment + rested_arm * e.shear_force}};
    };
    const std::array<double, 4> no_tip_state = {{0., 0., 0., 0.}};
    const auto touchdown_gap = [&](double span) {
      const SpanEnd load_part = span_end(no_tip_state, span, true);
      const SpanEnd first = span_end(modes[0], span, false), second = span_end(modes[1], span, false);
      const std::array<double, 2> b = conditions(load_part), a0 = conditions(first), a1 = conditions(second);
      const double det = a0[0] * a1[1] - a1[0] * a0[1];
      const double c0 = (-b[0] * a1[1] + a1[0] * b[1]) / det, c1 = (-a0[0] * b[1] + b[0] * a0[1]) / det;
      return load_part.w + c0 * first.w + c1 * second.w - collapse_height;
    };
    // The gap (negative at λ = 0, where the slab sits q/k < h_c deep) closes as the span grows: a
    // bracket doubled from the bending length, then TOMS 748.
    const double bending_length = std::pow(4 * D / k, 0.25);
    double lower = 0, upper = bending_length;
    while (touchdown_gap(upper) < 0)
    {
      lower = upper;
      upper *= 2;
      if (upper > 1e9 * bending_length)
        throw std::domain_error("closed forms: no touchdown within 1e9 bending lengths (4D/k)^{1/4}");
    }
    std::uintmax_t iterations = 200;
    const auto [left, right] =
      boost::math::tools::toms748_solve(touchdown_gap, lower, upper, touchdown_gap(lower), touchdown_gap(upper),
                                        boost::math::tools::eps_tolerance<double>(50),
                                        iterations);
    return (left + right) / 2;
  }

  // --- Eqs. 18–22: model error -----------------------------------------------------------------------

  double timoshenko_shear_error_estimate(const SlabOnFoundation &s)
  {
    // Eq. 18: ΔG/G = 2φ λa/(1 + λa)² <= φ/2, φ = D λ² / (κ G H) = (λH)² E' / (12 κ G).
    const double lambda_h = s.slab_thickness / characteristic_length(s);
    const double slab_shear_modulus = shear_modulus(s.slab_youngs_modulus, s.slab_poisson_ratio);
    return lambda_h * lambda_h * slab_plane_strain_modulus(s) /
           (24 * rectangular_shear_correction * slab_shear_modulus);
  }

  double slab_rotation_coupling_error_estimate(const SlabOnFoundation &s)
  {
    // Eq. 19: ΔG/G = −3 λa/(1 + λa)² ε_b, |·| <= (3/4) ε_b, ε_b = k_t H² / (8 D λ²).
    const double length = characteristic_length(s);
    const double epsilon = shear_foundation_stiffness(s) * s.slab_thickness * s.slab_thickness * length * length /
                           (8 * slab_bending_stiffness(s));
    return 0.75 * epsilon;
  }

  double weak_layer_thickness_error_estimate(const SlabOnFoundation &s)
  {
    // Eq. 20: ΔG_I/G_I = 4 C_I λh/(1 + λa), ΔG_II/G_II = 2 C_II μh/(1 + μa).
    s.check();
    const double h = s.weak_layer_thickness;
    return 4 * interpolate_in_poisson_ratio(edge_coefficient_normal, s.weak_layer_poisson_ratio) * h /
             characteristic_length(s) +
           2 * interpolate_in_poisson_ratio(edge_coefficient_shear, s.weak_layer_poisson_ratio) * h /
             shear_lag_length(s);
  }

  double slope_coupling_error_estimate(const SlabOnFoundation &s)
  {
    // Eq. 21
    return 2 * s.slab_thickness / characteristic_length(s) * std::abs(std::tan(s.slope_angle));
  }

  double beam_model_error_estimate(const SlabOnFoundation &s)
  {
    return timoshenko_shear_error_estimate(s) + slab_rotation_coupling_error_estimate(s) +
           weak_layer_thickness_error_estimate(s) + slope_coupling_error_estimate(s);
  }

  double semi_infinite_column_error_estimate(const SlabOnFoundation &s, double cut_length, double column_length)
  {
    require_cut_length(cut_length);
    require(column_length > cut_length, "column_length", column_length, "finite and > cut_length [m]");
    // Eq. 22: each mode's relative error weighted by its share of G.
    const double supported_length = column_length - cut_length;
    const double mode_I = finite_column_mode_I_coefficient *
                          std::exp(-2 * supported_length / characteristic_length(s));
    const double d = 1 / std::tanh(supported_length / shear_lag_length(s)) - 1;
    const double mode_II = 2 * d + d * d;
    return (energy_release_rate_mode_I(s, cut_length) * mode_I +
            energy_release_rate_mode_II(s, cut_length) * mode_II) /
           energy_release_rate(s, cut_length);
  }

  StressInvariants confined_layer_invariants(double overburden, double slope_angle, double poisson_ratio)
  {
    require(overburden >= 0, "overburden", overburden, "finite and >= 0 [Pa]");
    require(std::abs(slope_angle) < half_pi, "slope_angle", slope_angle, "in (-pi/2, pi/2) [rad]");
    require_poisson_ratio("poisson_ratio", poisson_ratio);
    // Eq. 27: uniaxial strain normal to the slope, k = ν / (1 − ν) on both in-plane stresses.
    const double k = poisson_ratio / (1 - poisson_ratio);
    const double normal = overburden * std::cos(slope_angle), shear = overburden * std::sin(slope_angle);
    return {normal * (1 + 2 * k) / 3, std::sqrt(std::pow(normal * (1 - k), 2) + 3 * shear * shear)};
  }

  double strength_to_contain(double p, double q, double beta, double M)
  {
    require_positive("p", p);
    require(q >= 0, "q", q, "finite and >= 0 [Pa]");
    require(beta >= 0 && beta <= 1, "beta", beta, "in [0, 1]");
    require_positive("M", M);
    // Eq. 28: M² β p0² + M² (1 − β) p p0 − ((1 + 2β) q² + M² p²) = 0, its positive root.
    const double c = (1 + 2 * beta) * q * q / (M * M) + p * p;
    if (beta == 0)
      return c / p;
    return (-(1 - beta) * p + std::sqrt((1 - beta) * (1 - beta) * p * p + 4 * beta * c)) / (2 * beta);
  }
} // namespace anticrack::fem::closed_forms
