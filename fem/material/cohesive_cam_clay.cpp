// Cohesive Cam-Clay material point: parameters, return mapping and consistent tangent. The equations
// are in the header; the comments here say how the two scalar problems are bracketed and solved and
// how the tangent is assembled.
#include "fem/material/cohesive_cam_clay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>

namespace anticrack::fem
{
  namespace
  {
    using dealii::SymmetricTensor;

    constexpr double eps = std::numeric_limits<double>::epsilon();

    /// |f| <= this ends the projection (f = M a / r − 1 is relative: y = r² − M² a² is then within
    /// ~32 ε M² a² of 0). It is a few times the round-off of f, so that Newton reaches it.
    constexpr double projection_tolerance = 16 * eps;
    /// The hardening solve ends when |R| <= 64 ε (|δ| + |h| + (|p_tr| + p0)/K) + 8 ε |R'| (|α_n| + |δ|),
    /// the two sources of round-off in R: the projection's tolerance leaves an error of up to
    /// ~16 ε |p_c − p_tr|/K in v = tr Δε_p (Δγ is ill-conditioned when the trial is barely outside),
    /// and α = α_n + δ is only resolved to ε |α|, which R' (up to ξ K cosh/K ~ 1e3 for ξ = 1e3)
    /// amplifies. Below this Newton cannot improve δ.
    constexpr double hardening_tolerance = 64 * eps;
    constexpr double alpha_resolution = 8 * eps;

    bool finite(const SymmetricTensor<2, 3> &t)
    {
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = i; j < 3; ++j)
          if (!std::isfinite(t[i][j]))
            return false;
      return true;
    }

    bool finite(const SymmetricTensor<4, 3> &t)
    {
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = i; j < 3; ++j)
          for (unsigned int k = 0; k < 3; ++k)
            for (unsigned int l = k; l < 3; ++l)
              if (!std::isfinite(t[i][j][k][l]))
                return false;
      return true;
    }

    std::string format(const SymmetricTensor<2, 3> &t)
    {
      std::ostringstream out;
      out << std::setprecision(10) << "[xx " << t[0][0] << ", yy " << t[1][1] << ", zz " << t[2][2]
          << ", xy " << t[0][1] << ", xz " << t[0][2] << ", yz " << t[1][2] << "]";
      return out.str();
    }

    void require(bool condition, const char *name, double value, const char *range)
    {
      if (!condition)
        {
          std::ostringstream out;
          out << std::setprecision(10) << "cohesive Cam-Clay parameter '" << name << "' = " << value
              << " must be " << range;
          throw std::invalid_argument(out.str());
        }
    }

    /// p0(α) and dp0/dα (one-sided 0 where the floor or the cap is active).
    struct Strength
    {
      double p0;
      double slope;
      bool at_floor;
    };

    Strength strength(const CamClayParameters &m, double alpha)
    {
      if (m.hardening_factor == 0)
        return {std::max(m.p0_initial, m.p0_floor), 0, m.p0_initial <= m.p0_floor};
      const double argument = m.hardening_factor * std::max(-alpha, 0.0);
      if (argument >= max_sinh_argument)
        return {std::max(m.bulk_modulus * std::sinh(max_sinh_argument), m.p0_floor), 0, false};
      const double p0 = m.bulk_modulus * std::sinh(argument);
      if (p0 <= m.p0_floor)
        return {m.p0_floor, 0, true};
      return {p0, -m.hardening_factor * m.bulk_modulus * std::cosh(argument), false};
    }

    /// The lock-up at a total strain: p_d = K_d ⟨−tr ε − ε_d⟩ and whether it is engaged (−tr ε > ε_d,
    /// so that the tangent K_d I⊗I is that of the locked side strictly beyond ε_d). The only place
    /// the formula is written: the update, its tangent, densification_pressure() and
    /// p_wave_modulus() all call it.
    struct LockUp
    {
      double pressure = 0;
      bool engaged = false;
    };

    LockUp lock_up(const CamClayParameters &m, const SymmetricTensor<2, 3> &total_strain)
    {
      LockUp l;
      if (m.densification_strain > 0)
        {
          const double excess = -dealii::trace(total_strain) - m.densification_strain;
          if (excess > 0)
            {
              l.pressure = m.densification_modulus * excess;
              l.engaged = true;
            }
        }
      return l;
    }

    /// Projection of the trial point (p_tr, q_tr) on the surface of a fixed p0.
    struct Projection
    {
      bool plastic = false;
      bool converged = true;
      unsigned int iterations = 0;
      double dgamma = 0; ///< Δγ
      double c = 0;      ///< 2 K M² Δγ
      double d = 1;      ///< 1 + 6 G (1 + 2β) Δγ
      double p = 0;
      double q = 0;
    };

    /// Partial derivatives of y(Δγ, p0; p_tr, q_tr) (header) and of v = tr Δε_p
    /// = 2 M² Δγ (p_c − p_tr)/(1 + c) at a plastic projection.
    struct Sensitivities
    {
      double y_dgamma, y_p0, y_ptr, y_qtr;
      double v, v_dgamma, v_p0, v_ptr;
      double p_dgamma, p_p0; ///< of p = p_c + (p_tr − p_c)/(1 + c)
      double q_dgamma;       ///< of q = q_tr / d
    };

    /// The return mapping of one (sub-)step in the invariants; see update_stress() in the header.
    class ReturnMapping
    {
    public:
      explicit ReturnMapping(const CamClayParameters &parameters)
        : m(parameters)
        , M2(parameters.M * parameters.M)
        , k_q(6 * parameters.shear_modulus * (1 + 2 * parameters.beta))
        , k_p(2 * parameters.bulk_modulus * M2)
      {}

      /// Converged return of one (sub-)step with the derivatives of (p, q, α_{n+1}) with respect
      /// to (p_tr, q_tr, α_n), which the tangent needs.
      struct Result
      {
        bool converged = true;
        bool plastic = false;
        unsigned int iterations = 0;
        double p = 0, q = 0, d = 1, dgamma = 0, volumetric = 0, alpha = 0, p0 = 0;
        std::array<double, 3> dp{{1, 0, 0}}, dq{{0, 1, 0}}, dalpha{{0, 0, 1}};
      };

      Result solve(double p_tr, double q_tr, double alpha_n, bool derivatives) const;

    private:
      /// One evaluation of the hardening residual R(δ) = δ − h(v) and of dR/dδ.
      struct Evaluation
      {
        double delta = 0;
        Strength strength{0, 0, false};
        Projection projection;
        double v = 0;     ///< tr Δε_p
        double h = 0;     ///< increment of α: v (signed law) or |v| (collapse)
        double dh_dv = 1; ///< 1 or sign(v)
        double residual = 0;
        double slope = 1;
      };

      Projection project(double p_tr, double q_tr, double p0, double guess) const;
      Sensitivities sensitivities(double p_tr, double q_tr, double p0, const Projection &x) const;
      Evaluation evaluate(double p_tr, double q_tr, double alpha_n, double delta, double guess) const;

      const CamClayParameters &m;
      const double M2;  ///< M²
      const double k_q; ///< d = 1 + k_q Δγ
      const double k_p; ///< 1 + c = 1 + k_p Δγ
    };

    // For fixed p0, r(Δγ)² = A/d² + B/(1 + c)² with A = (1 + 2β) q_tr², B = M² (p_tr − p_c)², and
    // y = r² − M² a². Since d and 1 + c both lie between 1 + k_min Δγ and 1 + k_max Δγ (k over the
    // terms with A, B > 0), r_tr/(1 + k_max Δγ) <= r(Δγ) <= r_tr/(1 + k_min Δγ), which brackets the
    // root of f = M a / r − 1 between (r_tr/(M a) − 1)/k_max and (r_tr/(M a) − 1)/k_min (one point
    // when one term vanishes or k_q = k_p: then f is linear in Δγ and Newton is exact). f increases.
    // Newton starts from `guess` (the Δγ of the previous hardening iterate) when it is in the bracket.
    Projection ReturnMapping::project(double p_tr, double q_tr, double p0, double guess) const
    {
      Projection x;
      x.p = p_tr;
      x.q = q_tr;
      const double p_c = 0.5 * (1 - m.beta) * p0;
      const double target = m.M * 0.5 * (1 + m.beta) * p0; // M a
      const double A = (1 + 2 * m.beta) * q_tr * q_tr;
      const double B = M2 * (p_tr - p_c) * (p_tr - p_c);
      const double r_trial = std::sqrt(A + B);
      if (!(r_trial > target))
        return x;

      x.plastic = true;
      const double k_min = A > 0 && B > 0 ? std::min(k_q, k_p) : (A > 0 ? k_q : k_p);
      const double k_max = A > 0 && B > 0 ? std::max(k_q, k_p) : (A > 0 ? k_q : k_p);
      const double excess = r_trial / target - 1;
      double lo = excess / k_max;
      double hi = excess / k_min;
      // Without a guess: the root of the tangent of 1/r at Δγ = 0, 1/r ≈ (1 + k_w Δγ)/r_tr with
      // k_w = (A k_q + B k_p)/(A + B), which lies in the bracket.
      const double k_w = (A * k_q + B * k_p) / (A + B);
      double dgamma = guess > lo && guess < hi ? guess : std::clamp(excess / k_w, lo, hi);
      double step_before_last = hi - lo;
      double last_step = step_before_last;
      for (unsigned int iteration = 1;; ++iteration)
        {
          const double d = 1 + k_q * dgamma;
          const double e = 1 + k_p * dgamma;
          const double r2 = A / (d * d) + B / (e * e);
          const double r = std::sqrt(r2);
          const double f = target / r - 1;
          x.iterations = iteration;
          x.dgamma = dgamma;
          x.c = k_p * dgamma;
          x.d = d;
          x.q = q_tr / d;
          x.p = p_c + (p_tr - p_c) / e;
          if (!std::isfinite(f))
            {
              x.converged = false;
              return x;
            }
          if (std::abs(f) <= projection_tolerance)
            return x;
          (f < 0 ? lo : hi) = dgamma;
          if (hi - lo <= 4 * eps * hi)
            return x;
          if (iteration >= m.max_iterations)
            {
              x.converged = false;
              return x;
            }
          // f' = M a (A k_q/d³ + B k_p/(1 + c)³)/r³ > 0.
          const double df = target * (A * k_q / (d * d * d) + B * k_p / (e * e * e)) / (r2 * r);
          const double newton = dgamma - f / df;
          // Bisect when Newton leaves the bracket or does not halve the step before last (rtsafe).
          const double next =
            newton > lo && newton < hi && std::abs(newton - dgamma) <= 0.5 * std::abs(step_before_last) ?
              newton :
              0.5 * (lo + hi);
          step_before_last = last_step;
          last_step = next - dgamma;
          dgamma = next;
        }
    }

    Sensitivities ReturnMapping::sensitivities(double p_tr, double q_tr, double p0, const Projection &x) const
    {
      const double beta = m.beta;
      const double p_c = 0.5 * (1 - beta) * p0;
      const double a = 0.5 * (1 + beta) * p0;
      const double A = (1 + 2 * beta) * q_tr * q_tr;
      const double diff = p_tr - p_c;
      const double d = x.d;
      const double e = 1 + x.c;
      Sensitivities s;
      s.y_dgamma = -2 * A * k_q / (d * d * d) - 2 * M2 * diff * diff * k_p / (e * e * e);
      s.y_p0 = -M2 * (1 - beta) * diff / (e * e) - M2 * (1 + beta) * a;
      s.y_ptr = 2 * M2 * diff / (e * e);
      s.y_qtr = 2 * (1 + 2 * beta) * q_tr / (d * d);
      s.v = -2 * M2 * x.dgamma * diff / e;
      s.v_dgamma = -2 * M2 * diff / (e * e);
      s.v_p0 = M2 * x.dgamma * (1 - beta) / e;
      s.v_ptr = -2 * M2 * x.dgamma / e;
      s.p_dgamma = -k_p * diff / (e * e);
      s.p_p0 = 0.5 * (1 - beta) * x.c / e;
      s.q_dgamma = -k_q * q_tr / (d * d);
      return s;
    }

    ReturnMapping::Evaluation
    ReturnMapping::evaluate(double p_tr, double q_tr, double alpha_n, double delta, double guess) const
    {
      Evaluation e;
      e.delta = delta;
      e.strength = strength(m, alpha_n + delta);
      e.projection = project(p_tr, q_tr, e.strength.p0, guess);
      double dv_dp0 = 0;
      if (e.projection.plastic)
        {
          const Sensitivities s = sensitivities(p_tr, q_tr, e.strength.p0, e.projection);
          e.v = s.v;
          // Total derivative along the surface: dΔγ/dp0 = −y_p0 / y_Δγ.
          dv_dp0 = s.v_p0 - s.v_dgamma * s.y_p0 / s.y_dgamma;
        }
      const bool collapse = m.law == HardeningLaw::collapse;
      e.h = collapse ? std::abs(e.v) : e.v;
      e.dh_dv = collapse ? (e.v > 0 ? 1.0 : (e.v < 0 ? -1.0 : 0.0)) : 1.0;
      e.residual = delta - e.h;
      e.slope = 1 - e.dh_dv * dv_dp0 * e.strength.slope;
      return e;
    }

    // Bracket of R(δ) = δ − h(v(δ)), from |v| < |p_c − p_tr|/K (v = (c/(1 + c))(p_c − p_tr)/K) and
    // p_c = (1 − β) p0/2 nondecreasing in p0 (β <= 1), p0 nonincreasing in α:
    //  * signed law, V = (p_c,n − p_tr)/K: for V > 0, δ in [0, V] has p0 <= p0_n, so v <= V and
    //    R(V) >= 0 >= R(0) = −v_n; for V < 0 symmetrically R(V) <= 0 <= R(0). At fixed Δγ R would
    //    increase (∂v/∂p0 >= 0, dp0/dα <= 0); through Δγ(p0) monotonicity is not proven, and the
    //    bracket is what guarantees a root.
    //  * collapse law: δ >= 0 and p0 in [p0_floor, p0_n], so |v| <= W = max(|p_c,n − p_tr|,
    //    |p_c,floor − p_tr|)/K and R(0) <= 0 <= R(W). R need not be monotone (compaction that softens
    //    feeds itself: under hydrostatic loading with ξ cosh(ξ α) > 1 the point collapses to the
    //    floor in one step); bisection keeps a sign change, so some root is always found.
    ReturnMapping::Result ReturnMapping::solve(double p_tr, double q_tr, double alpha_n, bool derivatives) const
    {
      Result result;
      result.p = p_tr;
      result.q = q_tr;
      result.alpha = alpha_n;
      Evaluation e = evaluate(p_tr, q_tr, alpha_n, 0, 0);
      result.p0 = e.strength.p0;
      result.iterations = e.projection.iterations;
      if (!e.projection.converged)
        {
          result.converged = false;
          return result;
        }
      if (!e.projection.plastic)
        return result;

      const bool collapse = m.law == HardeningLaw::collapse;
      const bool fixed_strength = m.hardening_factor == 0 || (collapse && e.strength.at_floor);
      if (fixed_strength)
        // p0 does not depend on δ: R = δ − h(v_n) is solved by δ = h(v_n).
        e.delta = e.h;
      else if (e.residual != 0)
        {
          const double K = m.bulk_modulus;
          const double p_c_n = 0.5 * (1 - m.beta) * e.strength.p0;
          double lo, hi;
          if (collapse)
            {
              const double p_c_floor = 0.5 * (1 - m.beta) * m.p0_floor;
              lo = 0;
              hi = std::max(std::abs(p_c_n - p_tr), std::abs(p_c_floor - p_tr)) / K;
            }
          else
            {
              const double V = (p_c_n - p_tr) / K;
              lo = std::min(0.0, V);
              hi = std::max(0.0, V);
            }
          double step_before_last = hi - lo;
          double last_step = step_before_last;
          for (unsigned int iteration = 1;; ++iteration)
            {
              ++result.iterations;
              const double tolerance =
                hardening_tolerance * (std::abs(e.delta) + std::abs(e.h) + (std::abs(p_tr) + e.strength.p0) / K) +
                alpha_resolution * std::abs(e.slope) * (std::abs(alpha_n) + std::abs(e.delta));
              if (std::abs(e.residual) <= tolerance)
                break;
              (e.residual < 0 ? lo : hi) = e.delta;
              if (hi - lo <= 4 * eps * (std::abs(alpha_n) + std::abs(lo) + std::abs(hi)))
                break;
              if (iteration >= m.max_iterations)
                {
                  result.converged = false;
                  return result;
                }
              const double newton = e.delta - e.residual / e.slope;
              const double next = e.slope > 0 && newton > lo && newton < hi &&
                                      std::abs(newton - e.delta) <= 0.5 * std::abs(step_before_last) ?
                                    newton :
                                    0.5 * (lo + hi);
              step_before_last = last_step;
              last_step = next - e.delta;
              e = evaluate(p_tr, q_tr, alpha_n, next, e.projection.dgamma);
              result.iterations += e.projection.iterations;
              if (!e.projection.converged || !std::isfinite(e.residual))
                {
                  result.converged = false;
                  return result;
                }
            }
        }

      const Projection &x = e.projection;
      result.plastic = x.plastic;
      result.p = x.p;
      result.q = x.q;
      result.d = x.d;
      result.dgamma = x.dgamma;
      result.volumetric = e.v;
      result.alpha = alpha_n + e.delta;
      result.p0 = e.strength.p0;
      if (!x.plastic || !derivatives)
        return result;

      // Implicit derivatives of the local system R1 = y(Δγ, p0(α)) = 0, R2 = α − α_n − h(v) = 0 in
      // the unknowns (Δγ, α) with respect to X = (p_tr, q_tr, α_n): J dU/dX = −∂R/∂X.
      const Sensitivities s = sensitivities(p_tr, q_tr, e.strength.p0, x);
      const double dp0 = e.strength.slope;
      const double J11 = s.y_dgamma;
      const double J12 = s.y_p0 * dp0;
      const double J21 = -e.dh_dv * s.v_dgamma;
      const double J22 = 1 - e.dh_dv * s.v_p0 * dp0;
      const double det = J11 * J22 - J12 * J21;
      const std::array<double, 3> b1{{-s.y_ptr, -s.y_qtr, 0}};
      const std::array<double, 3> b2{{e.dh_dv * s.v_ptr, 0, 1}};
      for (unsigned int X = 0; X < 3; ++X)
        {
          const double ddgamma = (b1[X] * J22 - J12 * b2[X]) / det;
          const double dalpha = (J11 * b2[X] - J21 * b1[X]) / det;
          result.dp[X] = (X == 0 ? 1 / (1 + x.c) : 0) + s.p_dgamma * ddgamma + s.p_p0 * dp0 * dalpha;
          result.dq[X] = (X == 1 ? 1 / x.d : 0) + s.q_dgamma * ddgamma;
          result.dalpha[X] = dalpha;
        }
      return result;
    }

    /// The tangent chain through the sub-steps: derivatives of ε_p and α with respect to the final
    /// total strain ε, and of the current stress.
    struct TangentChain
    {
      SymmetricTensor<4, 3> dplastic;
      SymmetricTensor<2, 3> dalpha;
      SymmetricTensor<4, 3> dstress;
    };

    /// Integrates ε_n -> total_strain in n equal sub-steps. False if a local solve failed or gave a
    /// non-finite value (result is then unspecified). With `chain`, also the tangent.
    bool integrate(const CamClayParameters &m,
                   const ReturnMapping &mapping,
                   const CamClayState &previous,
                   const SymmetricTensor<2, 3> &total_strain,
                   unsigned int n,
                   CamClayUpdate &result,
                   TangentChain *chain)
    {
      const double K = m.bulk_modulus;
      const double G = m.shear_modulus;
      const SymmetricTensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
      const SymmetricTensor<2, 3> increment = total_strain - previous.strain;
      result = CamClayUpdate();
      result.state = previous;
      result.substeps = n;
      CamClayState &state = result.state;
      if (chain)
        *chain = TangentChain();
      for (unsigned int j = 1; j <= n; ++j)
        {
          const SymmetricTensor<2, 3> strain =
            j == n ? total_strain : SymmetricTensor<2, 3>(previous.strain + (double(j) / n) * increment);
          const SymmetricTensor<2, 3> trial_strain = strain - state.plastic_strain;
          const double p_tr = -K * dealii::trace(trial_strain);
          const SymmetricTensor<2, 3> s_tr = 2 * G * dealii::deviator(trial_strain);
          const double s_norm = s_tr.norm();
          const double q_tr = std::sqrt(1.5) * s_norm;
          const ReturnMapping::Result local = mapping.solve(p_tr, q_tr, state.alpha, chain != nullptr);
          result.iterations += local.iterations;
          if (!local.converged)
            return false;

          const SymmetricTensor<2, 3> s = s_tr / local.d; // radial return: direction of s_tr kept
          result.stress = s - local.p * I;
          // Δε_p = (tr Δε_p / 3) I + 3 (1 + 2β) Δγ s (flow rule; equals ε_e,tr − C⁻¹ : σ).
          state.plastic_strain += (local.volumetric / 3) * I + (3 * (1 + 2 * m.beta) * local.dgamma) * s;
          state.alpha = local.alpha;
          state.p0 = local.p0;
          result.plastic = result.plastic || local.plastic;
          result.plastic_multiplier += local.dgamma;
          if (!finite(result.stress) || !finite(state.plastic_strain) || !std::isfinite(state.alpha))
            return false;

          if (chain)
            {
              // σ = −p I + sqrt(2/3) q n, n = s_tr/|s_tr|, dp_tr = −K I : dε_e, dq_tr = sqrt(6) G n : dε_e,
              // dn = (2G/|s_tr|)(I_dev − n ⊗ n) : dε_e, and q/q_tr = 1/d. The n terms vanish with q_tr
              // (p, α depend on q_tr², dq/dq_tr − 1/d = O(q_tr²)), so they are dropped when s_tr = 0.
              const SymmetricTensor<4, 3> IxI = dealii::outer_product(I, I);
              SymmetricTensor<4, 3> local_tangent =
                K * local.dp[0] * IxI + (2 * G / local.d) * dealii::deviator_tensor<3>();
              SymmetricTensor<2, 3> dstress_dalpha = -local.dp[2] * I;
              SymmetricTensor<2, 3> dalpha_dtrial = -K * local.dalpha[0] * I;
              if (s_norm > 0)
                {
                  const SymmetricTensor<2, 3> n_dir = s_tr / s_norm;
                  local_tangent += -std::sqrt(6.0) * G * local.dp[1] * dealii::outer_product(I, n_dir) -
                                   std::sqrt(2.0 / 3) * K * local.dq[0] * dealii::outer_product(n_dir, I) +
                                   2 * G * (local.dq[1] - 1 / local.d) * dealii::outer_product(n_dir, n_dir);
                  dstress_dalpha += std::sqrt(2.0 / 3) * local.dq[2] * n_dir;
                  dalpha_dtrial += std::sqrt(6.0) * G * local.dalpha[1] * n_dir;
                }
              // dε_e,tr/dε = (j/n) I − dε_p,{j−1}/dε; afterwards ε_p,j = ε_j − C⁻¹ : σ_j. In the first
              // sub-step dε_p,0/dε = 0 and dα_0/dε = 0, so one step costs no 4th-order products.
              const double t = double(j) / n;
              if (j == 1)
                {
                  chain->dstress = t * local_tangent;
                  chain->dalpha = t * dalpha_dtrial;
                }
              else
                {
                  const SymmetricTensor<4, 3> dtrial = t * dealii::identity_tensor<3>() - chain->dplastic;
                  chain->dstress = local_tangent * dtrial + dealii::outer_product(dstress_dalpha, chain->dalpha);
                  chain->dalpha = dalpha_dtrial * dtrial + local.dalpha[2] * chain->dalpha;
                }
              if (j < n)
                {
                  const SymmetricTensor<4, 3> compliance =
                    (1 / (9 * K)) * IxI + (1 / (2 * G)) * dealii::deviator_tensor<3>();
                  chain->dplastic = t * dealii::identity_tensor<3>() - compliance * chain->dstress;
                }
            }
        }
      state.strain = total_strain;
      return true;
    }

    CamClayUpdate run(const CamClayParameters &m,
                      const CamClayState &previous,
                      const SymmetricTensor<2, 3> &total_strain,
                      TangentChain *chain)
    {
      const auto describe = [&](const std::string &what) {
        const SymmetricTensor<2, 3> trial = total_strain - previous.plastic_strain;
        std::ostringstream out;
        out << std::setprecision(10) << "cohesive Cam-Clay return mapping: " << what
            << "; trial p = " << -m.bulk_modulus * dealii::trace(trial)
            << " Pa, q = " << std::sqrt(1.5) * 2 * m.shear_modulus * dealii::deviator(trial).norm()
            << " Pa, previous p0 = " << previous.p0 << " Pa, alpha = " << previous.alpha
            << ", strain = " << format(total_strain) << ", previous strain = " << format(previous.strain)
            << ", previous plastic strain = " << format(previous.plastic_strain);
        return out.str();
      };
      if (!finite(total_strain))
        throw ReturnMappingError(describe("non-finite strain"));

      const ReturnMapping mapping(m);
      CamClayUpdate result;
      unsigned int n = 1;
      while (true)
        {
          if (integrate(m, mapping, previous, total_strain, n, result, chain))
            break;
          if (n > m.max_substeps / 2)
            throw ReturnMappingError(describe("no convergence with " + std::to_string(n) + " sub-steps"));
          n *= 2;
        }
      // The lock-up acts in parallel with the Cam-Clay part and has no history: it is added once,
      // at the final total strain, after the return (which never sees it).
      const LockUp lock = lock_up(m, total_strain);
      if (lock.engaged)
        {
          const SymmetricTensor<2, 3> I = dealii::unit_symmetric_tensor<3>();
          result.stress -= lock.pressure * I;
          result.densification_pressure = lock.pressure;
          if (chain) // + K_d I⊗I: the nine components (i i j j)
            for (unsigned int i = 0; i < 3; ++i)
              for (unsigned int j = 0; j < 3; ++j)
                chain->dstress[i][i][j][j] += m.densification_modulus;
        }
      if (chain && !finite(chain->dstress))
        throw ReturnMappingError(describe("singular local Jacobian, the consistent tangent is undefined"));
      return result;
    }
  } // namespace

  void CamClayParameters::set_elastic_moduli(double youngs_modulus, double poisson_ratio)
  {
    require(std::isfinite(youngs_modulus) && youngs_modulus > 0, "Young's modulus", youngs_modulus, "> 0 [Pa]");
    require(std::isfinite(poisson_ratio) && poisson_ratio > -1 && poisson_ratio < 0.5,
            "Poisson's ratio", poisson_ratio, "in (-1, 0.5)");
    bulk_modulus = youngs_modulus / (3 * (1 - 2 * poisson_ratio));
    shear_modulus = youngs_modulus / (2 * (1 + poisson_ratio));
  }

  void CamClayParameters::check() const
  {
    require(std::isfinite(bulk_modulus) && bulk_modulus > 0, "bulk_modulus", bulk_modulus, "> 0 [Pa]");
    require(std::isfinite(shear_modulus) && shear_modulus > 0, "shear_modulus", shear_modulus, "> 0 [Pa]");
    require(std::isfinite(M) && M > 0, "M", M, "> 0");
    require(std::isfinite(beta) && beta >= 0 && beta <= 1, "beta", beta,
            "in [0, 1] (beta > 1 puts the tensile tip beyond the compressive one)");
    require(std::isfinite(p0_floor) && p0_floor > 0, "p0_floor", p0_floor, "> 0 [Pa]");
    require(std::isfinite(p0_initial) && p0_initial >= p0_floor, "p0_initial", p0_initial, ">= p0_floor [Pa]");
    require(std::isfinite(hardening_factor) && hardening_factor >= 0, "hardening_factor", hardening_factor, ">= 0");
    require(hardening_factor == 0 || p0_initial <= bulk_modulus * std::sinh(max_sinh_argument), "p0_initial",
            p0_initial, "<= K sinh(max_sinh_argument) when hardening_factor > 0 [Pa]");
    require(law == HardeningLaw::signed_volumetric || law == HardeningLaw::collapse, "law", static_cast<int>(law),
            "signed_volumetric (0) or collapse (1)");
    require(std::isfinite(densification_strain) && densification_strain >= 0 && densification_strain < 1,
            "densification_strain", densification_strain,
            "in [0, 1) (the compaction -tr(strain) at lock-up; 0: no lock-up)");
    require(std::isfinite(densification_modulus) && densification_modulus >= 0, "densification_modulus",
            densification_modulus, ">= 0 [Pa]");
    require(densification_strain == 0 || densification_modulus > 0, "densification_modulus", densification_modulus,
            "> 0 [Pa] when densification_strain > 0");
    require(densification_strain > 0 || densification_modulus == 0, "densification_modulus", densification_modulus,
            "0 when densification_strain = 0 (lock-up off; set densification_strain to use it)");
    require(max_iterations >= 1, "max_iterations", max_iterations, ">= 1");
    require(max_substeps >= 1, "max_substeps", max_substeps, ">= 1");
  }

  double residual_p0_floor(double p0_initial, double residual_strength_ratio)
  {
    require(std::isfinite(p0_initial) && p0_initial > 0, "p0_initial", p0_initial, "> 0 [Pa]");
    require(std::isfinite(residual_strength_ratio) && residual_strength_ratio >= 0 && residual_strength_ratio <= 1,
            "residual strength ratio", residual_strength_ratio, "in [0, 1]");
    return std::max(residual_strength_ratio, min_residual_strength_ratio) * p0_initial;
  }

  CamClayState CamClayState::initial(const CamClayParameters &parameters)
  {
    parameters.check();
    CamClayState state;
    state.alpha = parameters.hardening_factor == 0 ?
                    0 :
                    -std::asinh(parameters.p0_initial / parameters.bulk_modulus) / parameters.hardening_factor;
    state.p0 = hardening_p0(state.alpha, parameters);
    return state;
  }

  CamClayUpdate update_stress(const CamClayParameters &parameters,
                              const CamClayState &previous,
                              const dealii::SymmetricTensor<2, 3> &total_strain)
  {
    return run(parameters, previous, total_strain, nullptr);
  }

  CamClayTangentUpdate update_stress_and_tangent(const CamClayParameters &parameters,
                                                 const CamClayState &previous,
                                                 const dealii::SymmetricTensor<2, 3> &total_strain)
  {
    TangentChain chain;
    CamClayTangentUpdate result;
    result.update = run(parameters, previous, total_strain, &chain);
    result.tangent = chain.dstress;
    return result;
  }

  double densification_pressure(const CamClayParameters &parameters,
                                const dealii::SymmetricTensor<2, 3> &total_strain)
  {
    return lock_up(parameters, total_strain).pressure;
  }

  double p_wave_modulus(const CamClayParameters &parameters, const dealii::SymmetricTensor<2, 3> &total_strain)
  {
    const double elastic = parameters.bulk_modulus + 4 * parameters.shear_modulus / 3;
    return lock_up(parameters, total_strain).engaged ? elastic + parameters.densification_modulus : elastic;
  }

  double mean_pressure(const dealii::SymmetricTensor<2, 3> &stress)
  {
    return -dealii::trace(stress) / 3;
  }

  double von_mises(const dealii::SymmetricTensor<2, 3> &stress)
  {
    return std::sqrt(1.5) * dealii::deviator(stress).norm();
  }

  double yield_function(double p, double q, double p0, const CamClayParameters &parameters)
  {
    const double beta = parameters.beta;
    return (1 + 2 * beta) * q * q + parameters.M * parameters.M * (p + beta * p0) * (p - p0);
  }

  double layer_plane_shear_strength(const double sigma, const double k, const double p0,
                                    const CamClayParameters &parameters)
  {
    const double p = (1 + 2 * k) * sigma / 3, beta = parameters.beta, M = parameters.M;
    const double tau_squared = (-M * M * (p + beta * p0) * (p - p0) / (1 + 2 * beta) - (1 - k) * (1 - k) * sigma * sigma) / 3;
    return tau_squared >= 0 ? std::sqrt(tau_squared) : std::numeric_limits<double>::quiet_NaN();
  }

  double layer_plane_compressive_strength(const double k, const double p0, const CamClayParameters &parameters)
  {
    const double a = (1 + 2 * k) / 3, beta = parameters.beta, M2 = parameters.M * parameters.M;
    const double A = M2 * a * a + (1 + 2 * beta) * (1 - k) * (1 - k), B = M2 * a * p0 * (beta - 1),
                 C = -M2 * beta * p0 * p0;
    // C <= 0 < A: one root >= 0; written so that it does not cancel when B > 0 is large.
    const double root = std::sqrt(B * B - 4 * A * C);
    return B <= 0 ? (-B + root) / (2 * A) : -2 * C / (B + root);
  }

  double confined_flow_normal_stress(const double p0, const CamClayParameters &parameters)
  {
    // The flow direction ∂y/∂σ ∝ −(2/3) M² (p − p_c) I + 3 (1 + 2β) s parallel to the imposed
    // compaction −n⊗n (vol 1/3 I, dev diag(2/3, −1/3, −1/3) in compression) gives, for a multiplier
    // λ: p − p_c = λ / (2 M²), q = λ / (3 (1 + 2β)); y = 0 then fixes λ.
    const double beta = parameters.beta, M2 = parameters.M * parameters.M;
    const double p_c = (1 - beta) * p0 / 2, a = (1 + beta) * p0 / 2;
    const double lambda = std::sqrt(M2 * a * a / (1 / (9 * (1 + 2 * beta)) + 1 / (4 * M2)));
    const double p = p_c + lambda / (2 * M2), q = lambda / (3 * (1 + 2 * beta));
    return p + 2 * q / 3;
  }

  double hardening_p0(double alpha, const CamClayParameters &parameters)
  {
    return strength(parameters, alpha).p0;
  }

  dealii::SymmetricTensor<2, 3> plane_strain(const dealii::SymmetricTensor<2, 2> &in_plane_strain)
  {
    dealii::SymmetricTensor<2, 3> strain;
    strain[0][0] = in_plane_strain[0][0];
    strain[1][1] = in_plane_strain[1][1];
    strain[0][1] = in_plane_strain[0][1];
    return strain;
  }
} // namespace anticrack::fem
