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

    struct DropFit
    {
      double misfit = std::numeric_limits<double>::infinity(); ///< weighted sum of squares
      double softening_end = 0, residual = 0;
    };

    /// The drop and the plateau for a given end of the drop ε_s over the samples (peak, end]: the
    /// model is linear in σ_r, σ = c_i + a_i σ_r (a = t, c = σ_p (1 − t) on the drop, t its fraction;
    /// a = 1, c = 0 on the plateau), so σ_r is one weighted least-squares quotient, clamped to
    /// [0, σ_p].
    DropFit fit_drop(const std::vector<double> &e, const std::vector<double> &s, const std::vector<double> &w,
                     std::size_t peak, std::size_t end, double peak_stress, double softening_end)
    {
      const double e_p = e[peak];
      auto coefficients = [&](std::size_t i, double &a, double &c) {
        const double t = e[i] < softening_end ? (e[i] - e_p) / (softening_end - e_p) : 1.0;
        a = t, c = peak_stress * (1 - t);
      };
      double aa = 0, ar = 0;
      for (std::size_t i = peak + 1; i <= end; ++i)
      {
        double a, c;
        coefficients(i, a, c);
        aa += w[i] * a * a, ar += w[i] * a * (s[i] - c);
      }
      DropFit fit;
      fit.softening_end = softening_end;
      fit.residual = aa > 0 ? std::clamp(ar / aa, 0.0, peak_stress) : peak_stress;
      fit.misfit = 0;
      for (std::size_t i = peak + 1; i <= end; ++i)
      {
        double a, c;
        coefficients(i, a, c);
        const double d = s[i] - (c + a * fit.residual);
        fit.misfit += w[i] * d * d;
      }
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

    // The drop and the plateau, by least squares up to the onset of the lock-up ε_d, weighted by the
    // strain each sample stands for, so that the fit is one of the curve, not of the output interval.
    // ε_d depends on σ_r (header), so the window's end is iterated from ε_x: a few rounds settle it
    // to the sample.
    const double lock_up_modulus = (cap - peak_stress) / (cap_strain - regain_strain);
    const double e_p = e[peak];
    DropFit best;
    std::size_t end = below_peak;
    for (int round = 0; round < 8; ++round)
    {
      if (end - peak < 10)
        fail("fewer than 10 samples between the peak at strain " + std::to_string(e_p) +
             " and the lock-up at strain " + std::to_string(e[end]));
      std::vector<double> weight(n, 0.0);
      for (std::size_t i = peak + 1; i <= end; ++i)
        weight[i] = 0.5 * (e[std::min(i + 1, end)] - e[i - 1]);
      const double e_end = e[end];
      constexpr int drop_points = 400; // ε_s on a logarithmic grid of the drop's length
      const double shortest = std::max(e[peak + 1] - e_p, 1e-6 * (e_end - e_p));
      best = DropFit{};
      for (int a = 0; a < drop_points; ++a)
      {
        const double e_s = e_p + 0.999 * shortest * std::pow((e_end - e_p) / shortest, a / double(drop_points - 1));
        const DropFit c = fit_drop(e, s, weight, peak, end, peak_stress, e_s);
        if (c.misfit < best.misfit)
          best = c;
      }
      best.misfit /= (e_end - e_p);
      const double onset = regain_strain - (peak_stress - best.residual) / lock_up_modulus;
      std::size_t next = peak + 1;
      while (next + 1 < n && e[next + 1] <= onset)
        ++next;
      if (next == end)
        break;
      end = next;
    }
    CompactionCurveFit fit;
    fit.peak_index = static_cast<Index>(sample[peak]);
    fit.peak_strain = e_p, fit.peak_stress = peak_stress;
    fit.residual_stress = best.residual, fit.softening_end_strain = best.softening_end;
    fit.regain_strain = regain_strain;
    fit.lock_up_modulus = lock_up_modulus;
    // The FE's lock-up spring starts at ε_d so that the residual plus it regains σ_p at the DEM's strain.
    fit.lock_up_strain = regain_strain - (peak_stress - fit.residual_stress) / fit.lock_up_modulus;
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
            {"fracture_energy_density_J_per_m3", f.fracture_energy_density},
            {"collapse_energy_density_J_per_m3", f.collapse_energy_density},
            {"rms_misfit_over_peak", f.rms_misfit}};
  }
} // namespace anticrack::dem
