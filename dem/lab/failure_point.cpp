// Failure-point analysis of a test history; see failure_point.h for the definitions and sources.
#include "dem/lab/failure_point.h"

#include "dem/lab/compaction_curve.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace anticrack::dem
{
  namespace
  {
    [[noreturn]] void fail(const std::string &where, const std::string &what)
    {
      throw std::invalid_argument(where + ": " + what);
    }

    template <class T>
    void check_optional_length(const std::vector<T> &series, std::size_t n, const char *name)
    {
      if (!series.empty() && series.size() != n)
      {
        std::ostringstream msg;
        msg << "TestHistory::" << name << " has " << series.size() << " samples but time has " << n
            << " (each optional series must be empty or as long as time)";
        fail("TestHistory", msg.str());
      }
    }

    FailurePoint point_at(const TestHistory &h, Index i, Index window_begin, Index window_end)
    {
      FailurePoint fp;
      fp.index = i;
      fp.time = h.time[i];
      fp.stress = h.stress[i];
      const StressInvariants inv = stress_invariants(fp.stress);
      fp.p = inv.p;
      fp.q = inv.q;
      if (!h.base_normal_stress.empty())
        fp.sigma = h.base_normal_stress[i];
      if (!h.base_shear_stress.empty())
        fp.tau = h.base_shear_stress[i];
      fp.window_begin = window_begin;
      fp.window_end = window_end;
      return fp;
    }

    void check_index(Index i, std::size_t n, const char *where, const char *name)
    {
      if (i < 0 || static_cast<std::size_t>(i) >= n)
      {
        std::ostringstream msg;
        msg << name << " = " << i << " is outside the series of " << n << " samples";
        fail(where, msg.str());
      }
    }
  } // namespace

  void validate(const TestHistory &h)
  {
    const std::size_t n = h.time.size();
    if (n == 0)
      fail("TestHistory", "the history is empty (time has no samples)");
    if (h.stress.size() != n)
    {
      std::ostringstream msg;
      msg << "TestHistory::stress has " << h.stress.size() << " samples but time has " << n;
      fail("TestHistory", msg.str());
    }
    for (std::size_t i = 1; i < n; ++i)
      if (!(h.time[i] > h.time[i - 1]))
      {
        std::ostringstream msg;
        msg << "time must be strictly increasing, but time[" << i << "] = " << h.time[i] << " <= time["
            << i - 1 << "] = " << h.time[i - 1];
        fail("TestHistory", msg.str());
      }
    check_optional_length(h.clump_velocity, n, "clump_velocity");
    check_optional_length(h.clump_displacement, n, "clump_displacement");
    check_optional_length(h.strain, n, "strain");
    check_optional_length(h.base_normal_stress, n, "base_normal_stress");
    check_optional_length(h.base_shear_stress, n, "base_shear_stress");
  }

  std::vector<double> von_mises_series(const TestHistory &h)
  {
    std::vector<double> q(h.stress.size());
    for (std::size_t i = 0; i < q.size(); ++i)
      q[i] = stress_invariants(h.stress[i]).q;
    return q;
  }

  FailurePoint failure_by_kinetic_energy_window(const TestHistory &h, double zeta)
  {
    const char *where = "failure_by_kinetic_energy_window";
    validate(h);
    if (!(zeta > 0 && zeta <= 1))
      fail(where, "zeta = " + std::to_string(zeta) + " must lie in (0, 1]");
    if (h.clump_velocity.empty())
      fail(where, "the history has no clump_velocity (use failure_by_peak for wall-driven tests)");
    const std::size_t n = h.time.size();

    std::vector<double> v2(n);
    for (std::size_t i = 0; i < n; ++i)
      v2[i] = h.clump_velocity[i].squaredNorm();
    if (!std::all_of(v2.begin(), v2.end(), [](double x) { return std::isfinite(x); }))
      fail(where, "clump_velocity contains non-finite values");
    const auto max_it = std::max_element(v2.begin(), v2.end()); // first maximum
    const double v2_max = *max_it;
    if (!(v2_max > 0))
      fail(where, "the clump velocity is zero at every sample, so E_k* = |v|^2/max|v|^2 is undefined");
    const Index m = max_it - v2.begin();

    // E_k*(i) < zeta  <=>  v2[i] < zeta * v2_max
    const auto quiet = [&](Index i) { return v2[i] < zeta * v2_max; };
    Index e = m - 1;
    while (e >= 0 && !quiet(e))
      --e;
    if (e < 0)
    {
      std::ostringstream msg;
      msg << "no sample before the kinetic-energy maximum (index " << m << ") has E_k* < zeta = " << zeta
          << ": the test has no quasi-static part to search";
      fail(where, msg.str());
    }

    const std::vector<double> q = von_mises_series(h);
    Index best = -1;
    for (Index i = 0; i <= e; ++i)
      if (quiet(i) && (best < 0 || q[i] > q[best]))
        best = i;
    return point_at(h, best, 0, e);
  }

  std::vector<double> measure_series(const TestHistory &h, Measure measure)
  {
    switch (measure)
    {
      case Measure::von_mises:
        return von_mises_series(h);
      case Measure::base_shear:
      {
        if (h.base_shear_stress.empty())
          fail("measure_series", "Measure::base_shear needs base_shear_stress, which is empty");
        std::vector<double> s(h.base_shear_stress.size());
        std::transform(h.base_shear_stress.begin(), h.base_shear_stress.end(), s.begin(),
                       [](double t) { return std::abs(t); });
        return s;
      }
      case Measure::base_normal:
        if (h.base_normal_stress.empty())
          fail("measure_series", "Measure::base_normal needs base_normal_stress, which is empty");
        return h.base_normal_stress;
    }
    fail("measure_series", "unknown Measure");
  }

  FailurePoint failure_by_peak(const TestHistory &h, Measure measure)
  {
    validate(h);
    const std::vector<double> s = measure_series(h, measure);
    // The base normal stress peaks in compression (> 0) or, in a tension test, in tension (< 0).
    const Index best = std::max_element(s.begin(), s.end(), [&](double a, double b) {
                         return measure == Measure::base_normal ? std::abs(a) < std::abs(b) : a < b;
                       }) - s.begin();
    return point_at(h, best, 0, static_cast<Index>(s.size()) - 1);
  }

  double secant_modulus(const std::vector<double> &strain, const std::vector<double> &stress_measure,
                        Index peak_index, double fraction)
  {
    const char *where = "secant_modulus";
    if (strain.empty())
      fail(where, "the strain series is empty");
    if (strain.size() != stress_measure.size())
      fail(where, "strain has " + std::to_string(strain.size()) + " samples but the stress has " +
                    std::to_string(stress_measure.size()));
    check_index(peak_index, strain.size(), where, "peak_index");
    if (!(fraction > 0 && fraction <= 1))
      fail(where, "fraction = " + std::to_string(fraction) + " must lie in (0, 1]");
    const double peak = stress_measure[peak_index];
    if (!(peak != 0) || !std::isfinite(peak))
      fail(where, "the stress at peak_index is zero or not finite");
    const double sign = peak > 0 ? 1.0 : -1.0;
    const double target = fraction * std::abs(peak);

    Index i = 0;
    while (sign * stress_measure[i] < target)
      ++i; // terminates at the latest at peak_index
    double eps_f, sig_f;
    if (i == 0)
    {
      eps_f = strain[0];
      sig_f = stress_measure[0];
    }
    else
    {
      const double s0 = sign * stress_measure[i - 1], s1 = sign * stress_measure[i];
      const double w = (target - s0) / (s1 - s0); // s0 < target <= s1
      eps_f = strain[i - 1] + w * (strain[i] - strain[i - 1]);
      sig_f = sign * target;
    }
    if (!(eps_f != 0))
      fail(where, "the strain is zero where the stress reaches " + std::to_string(fraction) +
                    " of the peak: the secant from the origin is undefined");
    return sig_f / eps_f;
  }

  double softening_ratio(const std::vector<double> &stress_measure, Index peak_index)
  {
    const char *where = "softening_ratio";
    const std::size_t n = stress_measure.size();
    if (n == 0)
      fail(where, "the stress series is empty");
    check_index(peak_index, n, where, "peak_index");
    const double peak = stress_measure[peak_index];
    if (!(peak != 0) || !std::isfinite(peak))
      fail(where, "the stress at peak_index is zero or not finite");
    const auto after_peak = static_cast<Index>(n) - 1 - peak_index;
    if (after_peak < min_post_peak_samples)
      fail(where, "only " + std::to_string(after_peak) + " sample(s) follow the peak at index " +
                    std::to_string(peak_index) + " (at least " + std::to_string(min_post_peak_samples) +
                    " are needed)");
    const auto tail = static_cast<std::size_t>((after_peak + 1) / 2); // the last half, rounded up
    double sum = 0;
    for (std::size_t i = n - tail; i < n; ++i)
      sum += stress_measure[i];
    return sum / static_cast<double>(tail) / peak;
  }


  double flow_angle(const TestHistory &h, Index failure_index, Index window)
  {
    const char *where = "flow_angle";
    validate(h);
    if (h.clump_displacement.empty())
      fail(where, "the history has no clump_displacement");
    if (window < 1)
      fail(where, "window = " + std::to_string(window) + " must be at least 1 sample");
    const std::size_t n = h.clump_displacement.size();
    check_index(failure_index, n, where, "failure_index");
    if (failure_index + window >= static_cast<Index>(n))
    {
      std::ostringstream msg;
      msg << "failure_index + window = " << failure_index + window << " is past the last sample ("
          << n - 1 << ")";
      fail(where, msg.str());
    }
    const Vec3 du = h.clump_displacement[failure_index + window] - h.clump_displacement[failure_index];
    if (du.x() == 0 && du.z() == 0)
      fail(where, "the clump does not move in the x-z plane after failure: the flow angle is undefined");
    return std::atan2(du.z(), du.x());
  }

  FailureAnalysis analyse_failure(const TestHistory &h, const FailureAnalysisOptions &options)
  {
    validate(h);
    FailureAnalysis a;
    a.peak_q = failure_by_peak(h, Measure::von_mises);
    a.failure = h.clump_velocity.empty() ? a.peak_q : failure_by_kinetic_energy_window(h, options.zeta);

    const bool has_loading = options.loading_measure == Measure::von_mises ||
                             (options.loading_measure == Measure::base_normal && !h.base_normal_stress.empty()) ||
                             (options.loading_measure == Measure::base_shear && !h.base_shear_stress.empty());
    if (has_loading)
    {
      a.peak_loading = failure_by_peak(h, options.loading_measure);
      const std::vector<double> s = measure_series(h, options.loading_measure);
      if (options.peak_before_lock_up)
      {
        if (options.loading_measure != Measure::base_normal || h.strain.empty())
          throw std::invalid_argument("analyse_failure: peak_before_lock_up needs the base normal stress and the strain");
        a.compaction_curve = fit_compaction_curve(h.strain, s);
        a.peak_loading = point_at(h, a.compaction_curve->peak_index, 0, static_cast<Index>(s.size()) - 1);
      }
      const Index peak = a.peak_loading->index;
      if (!h.strain.empty())
        a.secant_modulus = secant_modulus(h.strain, s, peak, options.secant_fraction);
      // A history that ends (almost) at its peak has no softening ratio.
      if (static_cast<Index>(s.size()) - 1 - peak >= min_post_peak_samples)
        a.softening_ratio = softening_ratio(s, peak);
    }
    if (options.failure_at_loading_peak)
    {
      if (!a.peak_loading)
        throw std::invalid_argument("analyse_failure: failure_at_loading_peak needs the loading measure's series");
      a.failure = *a.peak_loading;
    }
    if (!h.clump_displacement.empty() &&
        a.failure.index + options.flow_window < static_cast<Index>(h.clump_displacement.size()))
      a.flow_angle = flow_angle(h, a.failure.index, options.flow_window);
    return a;
  }
} // namespace anticrack::dem
