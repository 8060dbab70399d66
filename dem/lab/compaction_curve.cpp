#include "dem/lab/compaction_curve.h"

#include "dem/lab/failure_point.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace anticrack::dem
{
  namespace
  {
    [[noreturn]] void fail(const std::string &what)
    {
      throw std::invalid_argument("compaction curve: " + what);
    }

    /// ∫ σ dε by the trapezoidal rule over the samples [first, last], plus the partial interval up
    /// to strain `end` (end between the strains of samples last and last + 1, or at last).
    double integral_to(const std::vector<double> &e, const std::vector<double> &s, std::size_t first, double end)
    {
      double w = 0;
      for (std::size_t i = first; i + 1 < e.size() && e[i] < end; ++i)
      {
        const double right = std::min(e[i + 1], end);
        const double s_right = s[i] + (s[i + 1] - s[i]) * (right - e[i]) / (e[i + 1] - e[i]);
        w += 0.5 * (s[i] + s_right) * (right - e[i]);
      }
      return w;
    }

    /// Weighted sums over a run of samples, for least squares of a straight line σ = A + B ε:
    /// Σw, Σwε, Σwε², Σwσ, Σwεσ, Σwσ² as prefix sums (the sums over [i, j) are the differences).
    struct PrefixSums
    {
      std::vector<double> w, we, wee, ws, wes, wss;

      PrefixSums(const std::vector<double> &e, const std::vector<double> &s, const std::vector<double> &weight)
        : w(e.size() + 1, 0.0), we(w), wee(w), ws(w), wes(w), wss(w)
      {
        for (std::size_t i = 0; i < e.size(); ++i)
        {
          const double c = weight[i];
          w[i + 1] = w[i] + c, we[i + 1] = we[i] + c * e[i], wee[i + 1] = wee[i] + c * e[i] * e[i];
          ws[i + 1] = ws[i] + c * s[i], wes[i + 1] = wes[i] + c * e[i] * s[i], wss[i + 1] = wss[i] + c * s[i] * s[i];
        }
      }
    };

    /// The misfit Σ w (σ − A − B ε)² over the samples [first, last) of a piece whose line depends
    /// linearly on σ_r, A = A0 + A1 σ_r and B = B0 + B1 σ_r, as the quadratic q0 + q1 σ_r + q2 σ_r².
    struct Quadratic
    {
      double q0 = 0, q1 = 0, q2 = 0;

      void add(const PrefixSums &p, std::size_t first, std::size_t last, double A0, double B0, double A1, double B1)
      {
        if (last <= first)
          return;
        const double w = p.w[last] - p.w[first], we = p.we[last] - p.we[first], wee = p.wee[last] - p.wee[first];
        const double ws = p.ws[last] - p.ws[first], wes = p.wes[last] - p.wes[first], wss = p.wss[last] - p.wss[first];
        // residual d − σ_r g with d = σ − A0 − B0 ε, g = A1 + B1 ε
        q0 += wss - 2 * A0 * ws - 2 * B0 * wes + A0 * A0 * w + 2 * A0 * B0 * we + B0 * B0 * wee;
        q1 -= 2 * (A1 * ws + B1 * wes - A0 * A1 * w - (A0 * B1 + A1 * B0) * we - B0 * B1 * wee);
        q2 += A1 * A1 * w + 2 * A1 * B1 * we + B1 * B1 * wee;
      }
    };

    struct PieceFit
    {
      double misfit = std::numeric_limits<double>::infinity(); ///< weighted sum of squares
      double softening_end = 0, densification_onset = 0, residual = 0;
    };

    /// The drop, the plateau and the densification for given ε_s and ε_d over the samples
    /// (peak, end]: each piece is a line whose ends are σ_p or σ_r, so the model is linear in σ_r
    /// and its least-squares value is one quotient, clamped to [0, σ_p].
    PieceFit fit_pieces(const std::vector<double> &e, const PrefixSums &sums, std::size_t peak, std::size_t end,
                        double peak_stress, double regain_strain, double softening_end, double densification_onset)
    {
      const auto first_at_or_after = [&](double x) {
        return static_cast<std::size_t>(std::lower_bound(e.begin() + peak + 1, e.begin() + end + 1, x) - e.begin());
      };
      const std::size_t plateau = first_at_or_after(softening_end), densification = first_at_or_after(densification_onset);
      const double e_p = e[peak], L = softening_end - e_p, D = regain_strain - densification_onset;
      Quadratic q;
      // drop: σ = σ_p (1 − t) + σ_r t, t = (ε − ε_p)/L
      q.add(sums, peak + 1, plateau, peak_stress * (1 + e_p / L), -peak_stress / L, -e_p / L, 1 / L);
      // plateau: σ = σ_r
      q.add(sums, plateau, densification, 0, 0, 1, 0);
      // densification: σ = σ_r (1 − u) + σ_p u, u = (ε − ε_d)/D
      q.add(sums, densification, end + 1, -peak_stress * densification_onset / D, peak_stress / D,
            1 + densification_onset / D, -1 / D);
      PieceFit fit;
      fit.softening_end = softening_end, fit.densification_onset = densification_onset;
      fit.residual = q.q2 > 0 ? std::clamp(-q.q1 / (2 * q.q2), 0.0, peak_stress) : peak_stress;
      fit.misfit = std::max(q.q0 + fit.residual * (q.q1 + fit.residual * q.q2), 0.0);
      return fit;
    }
  } // namespace

  double CompactionCurveFit::model_stress(const double e) const
  {
    if (e < softening_end_strain)
      return peak_stress - (peak_stress - residual_stress) * (e - peak_strain) / (softening_end_strain - peak_strain);
    return residual_stress + (e > lock_up_strain ? lock_up_modulus * (e - lock_up_strain) : 0.0);
  }

  CompactionCurveFit fit_compaction_curve(const std::vector<double> &strain, const std::vector<double> &stress,
                                          const double axial_modulus)
  {
    if (stress.size() != strain.size())
      fail("the stress has " + std::to_string(stress.size()) + " samples, the strain " +
           std::to_string(strain.size()));
    // Samples at the strain of the one before (the history's rows before the platen moves) carry
    // no strain: they are left out. A strain that decreases is not a compaction test.
    std::vector<double> e, s;
    std::vector<std::size_t> sample; // of each kept sample in the input
    for (std::size_t i = 0; i < strain.size(); ++i)
    {
      if (!e.empty() && strain[i] < e.back())
        fail("the strain decreases at sample " + std::to_string(i) + " (" + std::to_string(e.back()) + " then " +
             std::to_string(strain[i]) + ")");
      if (e.empty() || strain[i] > e.back())
        e.push_back(strain[i]), s.push_back(stress[i]), sample.push_back(i);
    }
    const std::size_t n = e.size();
    if (n < compaction_minimum_samples)
      fail("fewer than " + std::to_string(compaction_minimum_samples) + " samples of increasing strain (" +
           std::to_string(n) + ")");

    // The first peak: the running maximum when the stress first falls below collapse_fraction of it.
    std::size_t peak = 0, collapse = n, above_cap = n;
    CompactionStages stages;
    for (std::size_t i = 0; i < n && above_cap == n; ++i)
    {
      if (stages.add(s[i]))
        peak = i;
      if (stages.collapsed && collapse == n)
        collapse = i;
      if (stages.locked_up)
        above_cap = i;
    }
    if (!(s[peak] > 0))
      fail("no positive (compressive) stress");
    if (collapse == n)
      fail("the stress never falls below " + std::to_string(compaction_collapse_fraction) +
           " of its running maximum: no collapse (the layer hardens under compaction; largest stress " +
           std::to_string(s[peak]) + " Pa at strain " + std::to_string(e[peak]) + ")");
    if (peak < compaction_elastic_samples)
      fail("the peak (" + std::to_string(s[peak]) + " Pa at strain " + std::to_string(e[peak]) + ") is sample " +
           std::to_string(peak) + ": fewer than " + std::to_string(compaction_elastic_samples) +
           " samples resolve the rise to it; sample the curve more finely (Campaign/Compaction curve strain "
           "interval, or DEM/Loading/Curve strain interval of a compaction scene)");
    const double peak_stress = s[peak];
    // Lock-up: the locked-up layer carries the peak again, for good, before it reaches
    // lock_up_stress_ratio times it.
    const double cap = compaction_lock_up_stress_ratio * peak_stress;
    if (above_cap == n)
      fail("the curve ends (strain " + std::to_string(e[n - 1]) + ", stress " + std::to_string(s[n - 1]) +
           " Pa) before the collapsed layer locks up and carries " + std::to_string(compaction_lock_up_stress_ratio) +
           " times its peak " + std::to_string(peak_stress) + " Pa: run the test further (its final strain)");
    auto crossing = [&](std::size_t last_below, double level) {
      const std::size_t i = last_below;
      return e[i] + (e[i + 1] - e[i]) * (level - s[i]) / (s[i + 1] - s[i]);
    };
    std::size_t below_peak = above_cap - 1;
    while (below_peak > collapse && s[below_peak] >= peak_stress)
      --below_peak;
    std::size_t below_cap = above_cap - 1;
    const double regain_strain = crossing(below_peak, peak_stress), cap_strain = crossing(below_cap, cap);

    // The drop, the plateau and the densification, by least squares from the peak to the regain,
    // weighted by the strain each sample stands for, so that the fit is one of the curve, not of the
    // output interval: ε_s on a logarithmic grid of the window (the drop is short), ε_d on a linear
    // grid from ε_s to the regain, σ_r the quotient of each pair.
    const double e_p = e[peak];
    const std::size_t end = below_peak;
    if (end - peak < 10)
      fail("fewer than 10 samples between the peak at strain " + std::to_string(e_p) +
           " and the regain of the peak stress at strain " + std::to_string(regain_strain));
    std::vector<double> weight(n, 0.0);
    for (std::size_t i = peak + 1; i <= end; ++i)
      weight[i] = 0.5 * (e[std::min(i + 1, end)] - e[i - 1]);
    const PrefixSums sums(e, s, weight);
    const double window = regain_strain - e_p;
    constexpr int drop_points = 400, onset_points = 400;
    const double shortest = std::max(e[peak + 1] - e_p, 1e-6 * window);
    const double drop_ratio = std::pow(window / shortest, 1 / double(drop_points - 1));
    PieceFit best;
    for (int a = 0; a < drop_points; ++a)
    {
      const double e_s = e_p + 0.999 * shortest * std::pow(drop_ratio, a);
      for (int b = 0; b < onset_points; ++b)
      {
        const double e_d = e_s + (regain_strain - e_s) * b / double(onset_points);
        const PieceFit c = fit_pieces(e, sums, peak, end, peak_stress, regain_strain, e_s, e_d);
        if (c.misfit < best.misfit)
          best = c;
      }
    }
    // Then finer, within a step of the grid either side of the best pair: the answer to a hundredth
    // of the grid's steps (0.02 % of the drop, 4e-6 of the window in ε_d).
    const PieceFit coarse = best;
    const double onset_step = (regain_strain - coarse.softening_end) / onset_points;
    for (int a = -100; a <= 100; ++a)
    {
      const double e_s = e_p + (coarse.softening_end - e_p) * std::pow(drop_ratio, a / 100.0);
      for (int b = -100; b <= 100; ++b)
      {
        const double e_d = std::max(e_s, coarse.densification_onset + onset_step * b / 100.0);
        if (!(e_d < regain_strain) || !(e_s < regain_strain))
          continue;
        const PieceFit c = fit_pieces(e, sums, peak, end, peak_stress, regain_strain, e_s, e_d);
        if (c.misfit < best.misfit)
          best = c;
      }
    }
    best.misfit /= (e[end] - e_p);
    CompactionCurveFit fit;
    fit.peak_index = static_cast<Index>(sample[peak]);
    fit.peak_strain = e_p, fit.peak_stress = peak_stress;
    fit.residual_stress = best.residual, fit.softening_end_strain = best.softening_end;
    fit.regain_strain = regain_strain;
    fit.lock_up_strain = best.densification_onset;
    // The FE's densification spring starts at ε_d and regains σ_p at the DEM's strain.
    fit.lock_up_modulus = (peak_stress - fit.residual_stress) / (regain_strain - fit.lock_up_strain);
    fit.cap_modulus = (cap - peak_stress) / (cap_strain - regain_strain);
    fit.rms_misfit = std::sqrt(best.misfit) / peak_stress;
    fit.axial_modulus =
      std::isnan(axial_modulus) ? secant_modulus(e, s, static_cast<Index>(peak), 0.7) : axial_modulus;
    if (!(fit.axial_modulus > 0))
      fail("the axial modulus must be positive (is " + std::to_string(fit.axial_modulus) + " Pa)");
    const double M = fit.axial_modulus;
    fit.fracture_energy_density = 0.5 * (fit.peak_stress - fit.residual_stress) * fit.plastic_softening_strain();
    fit.collapse_energy_density =
      integral_to(e, s, 0, fit.lock_up_strain) - fit.residual_stress * fit.residual_stress / (2 * M);
    return fit;
  }

  nlohmann::json compaction_curve_json(const CompactionCurveFit &f)
  {
    return {{"peak_strain", f.peak_strain},
            {"peak_stress_Pa", f.peak_stress},
            {"axial_modulus_Pa", f.axial_modulus},
            {"residual_stress_Pa", f.residual_stress},
            {"residual_ratio", f.residual_ratio()},
            {"softening_end_strain", f.softening_end_strain},
            {"plastic_softening_strain", f.plastic_softening_strain()},
            {"regain_strain", f.regain_strain},
            {"lock_up_strain", f.lock_up_strain},
            {"lock_up_modulus_Pa", f.lock_up_modulus},
            {"cap_modulus_Pa", f.cap_modulus},
            {"fracture_energy_density_J_per_m3", f.fracture_energy_density},
            {"collapse_energy_density_J_per_m3", f.collapse_energy_density},
            {"rms_misfit_over_peak", f.rms_misfit}};
  }
} // namespace anticrack::dem
