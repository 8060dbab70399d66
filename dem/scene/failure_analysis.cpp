#include "dem/scene/failure_analysis.h"

#include "dem/lab/failure_point.h"
#include "dem/scene/history_columns.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace anticrack::dem
{
  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();

    // The keys of summary.json's dem.failure_analysis, written and read here only.
    namespace key
    {
      constexpr const char *error = "error", *criterion = "criterion", *failure = "failure", *peak_q = "peak_q";
      constexpr const char *peak_base_normal = "peak_base_normal_stress", *peak_base_shear = "peak_base_shear_stress";
      constexpr const char *secant = "secant_modulus_70_percent_Pa",
                           *secant_shear = "secant_shear_modulus_70_percent_Pa";
      constexpr const char *softening_ratio = "softening_ratio", *flow_angle = "flow_angle_deg";
      constexpr const char *step = "step", *time = "time_s", *p = "mean_pressure_p_Pa", *q = "von_mises_q_Pa";
      constexpr const char *sigma = "base_normal_stress_sigma_Pa", *tau = "base_shear_stress_tau_Pa";
      constexpr const char *love_stress = "love_stress_Pa";
      constexpr const char *compaction_curve = "compaction_curve";
    } // namespace key

    /// summary.json's criterion of each control (also how a resumed campaign reads the control back).
    const char *criterion_text(const ActuatorControl control)
    {
      switch (control)
      {
        case ActuatorControl::shear_displacement:
          return "peak of the base shear stress tau (displacement-controlled simple shear)";
        case ActuatorControl::normal_displacement:
          return "first peak of the base normal stress sigma before the lock-up (displacement-controlled "
                 "compaction, dem/lab/compaction_curve.h)";
        case ActuatorControl::force:
          break;
      }
      return "Ritter et al. (2020): max q inside the window where E_k* = |v_c|^2/max|v_c|^2 < 0.3";
    }

    const std::vector<double> &column(const TimeSeries &history, const std::string &name)
    {
      const TimeSeries::Column *c = history.find(name);
      if (!c)
        throw std::invalid_argument("history has no column '" + name + "'");
      return c->values;
    }

    RecordedFailurePoint recorded(const dem::FailurePoint &f, const std::vector<double> &steps)
    {
      return {steps.at(static_cast<std::size_t>(f.index)), f.time, f.p, f.q, f.sigma, f.tau, f.stress};
    }

    nlohmann::json point_json(const RecordedFailurePoint &f)
    {
      nlohmann::json j;
      j[key::step] = f.step;
      j[key::time] = f.time;
      j[key::p] = f.p;
      j[key::q] = f.q;
      if (f.sigma)
        j[key::sigma] = *f.sigma;
      if (f.tau)
        j[key::tau] = *f.tau;
      const Mat3 &s = f.love_stress;
      j[key::love_stress] = {{s(0, 0), s(0, 1), s(0, 2)}, {s(1, 0), s(1, 1), s(1, 2)}, {s(2, 0), s(2, 1), s(2, 2)}};
      return j;
    }

    /// A number of `j` at `name`, NaN when absent or not a number (JSON writes NaN as null).
    double number(const nlohmann::ordered_json &j, const char *name)
    {
      return j.contains(name) && j[name].is_number() ? j[name].get<double>() : nan;
    }

    std::optional<double> optional_number(const nlohmann::ordered_json &j, const char *name)
    {
      return j.contains(name) ? std::optional<double>(number(j, name)) : std::nullopt;
    }

    RecordedFailurePoint point_from_json(const nlohmann::ordered_json &j)
    {
      RecordedFailurePoint f;
      f.step = number(j, key::step);
      f.time = number(j, key::time);
      f.p = number(j, key::p);
      f.q = number(j, key::q);
      f.sigma = optional_number(j, key::sigma);
      f.tau = optional_number(j, key::tau);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
        {
          const nlohmann::ordered_json::json_pointer entry("/" + std::string(key::love_stress) + "/" + std::to_string(r) +
                                                   "/" + std::to_string(c));
          f.love_stress(r, c) = j.contains(entry) && j[entry].is_number() ? j[entry].get<double>() : nan;
        }
      return f;
    }
  } // namespace

  TestFailureAnalysis analyse_test_history(const TimeSeries &history, double layer_thickness,
                                           const ActuatorControl control)
  {
    TestFailureAnalysis result;
    result.control = control;
    const bool shear_controlled = control == ActuatorControl::shear_displacement;
    try
    {
      dem::TestHistory h;
      h.time = column(history, history_column::time);
      const std::size_t n = h.time.size();
      const char *components[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
      std::vector<const std::vector<double> *> stress;
      for (const char *c : components)
        stress.push_back(&column(history, history_column::love_stress(c)));
      h.stress.resize(n);
      for (std::size_t i = 0; i < n; ++i)
      {
        dem::Mat3 &s = h.stress[i];
        s(0, 0) = (*stress[0])[i], s(1, 1) = (*stress[1])[i], s(2, 2) = (*stress[2])[i];
        s(0, 1) = s(1, 0) = (*stress[3])[i];
        s(0, 2) = s(2, 0) = (*stress[4])[i];
        s(1, 2) = s(2, 1) = (*stress[5])[i];
      }
      using history_column::clump_displacement, history_column::clump_velocity;
      const auto &vx = column(history, clump_velocity('x')), &vy = column(history, clump_velocity('y')),
                 &vz = column(history, clump_velocity('z'));
      const auto &ux = column(history, clump_displacement('x')), &uy = column(history, clump_displacement('y')),
                 &uz = column(history, clump_displacement('z'));
      for (std::size_t i = 0; i < n; ++i)
      {
        if (control == ActuatorControl::force)
          h.clump_velocity.emplace_back(vx[i], vy[i], vz[i]);
        h.clump_displacement.emplace_back(ux[i], uy[i], uz[i]);
        // Compression positive like sigma; shear strain along +x like tau.
        h.strain.push_back(shear_controlled ? ux[i] / layer_thickness : -uz[i] / layer_thickness);
      }
      if (history.find(history_column::base_normal_stress))
      {
        h.base_normal_stress = column(history, history_column::base_normal_stress);
        h.base_shear_stress = column(history, history_column::base_shear_stress);
      }
      dem::FailureAnalysisOptions options;
      if (shear_controlled)
      {
        options.loading_measure = dem::Measure::base_shear;
        options.failure_at_loading_peak = true;
      }
      else if (control == ActuatorControl::normal_displacement)
      {
        options.loading_measure = dem::Measure::base_normal;
        options.failure_at_loading_peak = true;
        options.peak_before_lock_up = true;
      }
      const dem::FailureAnalysis a = dem::analyse_failure(h, options);
      const auto &steps = column(history, history_column::step);
      result.failure = recorded(a.failure, steps);
      result.peak_q = recorded(a.peak_q, steps);
      if (a.peak_loading)
        result.peak_loading = recorded(*a.peak_loading, steps);
      result.secant_modulus = a.secant_modulus;
      result.softening_ratio = a.softening_ratio;
      if (a.flow_angle)
        result.flow_angle_deg = *a.flow_angle * 180 / M_PI;
      result.compaction_curve = a.compaction_curve;
      const auto *q = history.find("von_mises_stress"), *inertial = history.find("inertial_number");
      if (q && inertial)
        result.max_inertial_number = max_inertial_number_before_failure(steps, q->values, inertial->values,
                                                                        result.failure.step, result.failure.q);
    }
    catch (const std::exception &e)
    {
      result = TestFailureAnalysis{};
      result.control = control;
      result.error = e.what();
    }
    return result;
  }

  double max_inertial_number_before_failure(const std::vector<double> &step, const std::vector<double> &von_mises,
                                            const std::vector<double> &inertial_number, double failure_step,
                                            double failure_q)
  {
    double largest = 0;
    for (std::size_t k = 0; k < step.size() && step[k] <= failure_step; ++k)
      if (von_mises[k] >= 0.5 * failure_q && std::isfinite(inertial_number[k]))
        largest = std::max(largest, inertial_number[k]);
    return largest;
  }

  nlohmann::json failure_analysis_json(const TestFailureAnalysis &a)
  {
    nlohmann::json result;
    if (!a.error.empty())
    {
      result[key::error] = a.error;
      return result;
    }
    const bool shear_controlled = a.control == ActuatorControl::shear_displacement;
    result[key::criterion] = criterion_text(a.control);
    result[key::failure] = point_json(a.failure);
    result[key::peak_q] = point_json(a.peak_q);
    if (a.peak_loading)
      result[shear_controlled ? key::peak_base_shear : key::peak_base_normal] = point_json(*a.peak_loading);
    if (a.secant_modulus)
      result[shear_controlled ? key::secant_shear : key::secant] = *a.secant_modulus;
    if (a.softening_ratio)
      result[key::softening_ratio] = *a.softening_ratio;
    if (a.flow_angle_deg)
      result[key::flow_angle] = *a.flow_angle_deg;
    if (a.compaction_curve)
    {
      result[key::compaction_curve] = compaction_curve_json(*a.compaction_curve);
      result[key::compaction_curve]["axial_modulus_source"] = "the curve's secant to 70 % of its peak (a calibration "
                                                              "reads the curve again with the campaign's M)";
    }
    return result;
  }

  TestFailureAnalysis failure_analysis_from_json(const nlohmann::ordered_json &j)
  {
    TestFailureAnalysis a;
    if (j.contains(key::error))
    {
      a.error = j[key::error].get<std::string>();
      return a;
    }
    a.control = ActuatorControl::force;
    for (const ActuatorControl c : {ActuatorControl::shear_displacement, ActuatorControl::normal_displacement})
      if (j.contains(key::criterion) && j[key::criterion] == criterion_text(c))
        a.control = c;
    const bool shear_controlled = a.control == ActuatorControl::shear_displacement;
    // A point the file lacks reads as NaN throughout.
    const auto member = [&](const char *name) { return j.contains(name) ? j[name] : nlohmann::ordered_json::object(); };
    a.failure = point_from_json(member(key::failure));
    a.peak_q = point_from_json(member(key::peak_q));
    const char *peak_loading = shear_controlled ? key::peak_base_shear : key::peak_base_normal;
    if (j.contains(peak_loading))
      a.peak_loading = point_from_json(j[peak_loading]);
    a.secant_modulus = optional_number(j, shear_controlled ? key::secant_shear : key::secant);
    a.softening_ratio = optional_number(j, key::softening_ratio);
    a.flow_angle_deg = optional_number(j, key::flow_angle);
    return a;
  }
} // namespace anticrack::dem
