#include "dem/scene/failure_analysis.h"

#include "dem/lab/failure_point.h"

#include <cmath>
#include <stdexcept>

namespace anticrack::dem
{
  namespace
  {
    const std::vector<double> &column(const TimeSeries &history, const std::string &name)
    {
      const TimeSeries::Column *c = history.find(name);
      if (!c)
        throw std::invalid_argument("history has no column '" + name + "'");
      return c->values;
    }

    nlohmann::json point_json(const dem::FailurePoint &f, const std::vector<double> &steps)
    {
      nlohmann::json j;
      j["step"] = steps.at(static_cast<std::size_t>(f.index));
      j["time_s"] = f.time;
      j["mean_pressure_p_Pa"] = f.p;
      j["von_mises_q_Pa"] = f.q;
      if (f.sigma)
        j["base_normal_stress_sigma_Pa"] = *f.sigma;
      if (f.tau)
        j["base_shear_stress_tau_Pa"] = *f.tau;
      j["love_stress_Pa"] = {{f.stress(0, 0), f.stress(0, 1), f.stress(0, 2)},
                             {f.stress(1, 0), f.stress(1, 1), f.stress(1, 2)},
                             {f.stress(2, 0), f.stress(2, 1), f.stress(2, 2)}};
      return j;
    }
  } // namespace

  nlohmann::json analyse_test_history(const TimeSeries &history, double sample_height, const bool shear_controlled)
  {
    nlohmann::json result;
    try
    {
      dem::TestHistory h;
      h.time = column(history, "time");
      const std::size_t n = h.time.size();
      const char *components[6] = {"xx", "yy", "zz", "xy", "xz", "yz"};
      std::vector<const std::vector<double> *> stress;
      for (const char *c : components)
        stress.push_back(&column(history, std::string("love_stress_") + c));
      h.stress.resize(n);
      for (std::size_t i = 0; i < n; ++i)
      {
        dem::Mat3 &s = h.stress[i];
        s(0, 0) = (*stress[0])[i], s(1, 1) = (*stress[1])[i], s(2, 2) = (*stress[2])[i];
        s(0, 1) = s(1, 0) = (*stress[3])[i];
        s(0, 2) = s(2, 0) = (*stress[4])[i];
        s(1, 2) = s(2, 1) = (*stress[5])[i];
      }
      const auto &vx = column(history, "clump_velocity_x"), &vy = column(history, "clump_velocity_y"),
                 &vz = column(history, "clump_velocity_z");
      const auto &ux = column(history, "clump_displacement_x"), &uy = column(history, "clump_displacement_y"),
                 &uz = column(history, "clump_displacement_z");
      for (std::size_t i = 0; i < n; ++i)
      {
        if (!shear_controlled)
          h.clump_velocity.emplace_back(vx[i], vy[i], vz[i]);
        h.clump_displacement.emplace_back(ux[i], uy[i], uz[i]);
        // Compression positive like sigma; shear strain along +x like tau.
        h.strain.push_back(shear_controlled ? ux[i] / sample_height : -uz[i] / sample_height);
      }
      if (history.find("base_normal_stress"))
      {
        h.base_normal_stress = column(history, "base_normal_stress");
        h.base_shear_stress = column(history, "base_shear_stress");
      }
      dem::FailureAnalysisOptions options;
      if (shear_controlled)
      {
        options.loading_measure = dem::Measure::base_shear;
        options.failure_at_loading_peak = true;
      }
      const dem::FailureAnalysis a = dem::analyse_failure(h, options);
      const auto &steps = column(history, "step");
      result["criterion"] = shear_controlled ?
                              "peak of the base shear stress tau (displacement-controlled simple shear)" :
                              "Ritter et al. (2020): max q inside the window where E_k* = |v_c|^2/max|v_c|^2 < 0.3";
      result["failure"] = point_json(a.failure, steps);
      result["peak_q"] = point_json(a.peak_q, steps);
      if (a.peak_loading)
        result[shear_controlled ? "peak_base_shear_stress" : "peak_base_normal_stress"] =
          point_json(*a.peak_loading, steps);
      if (a.secant_modulus)
        result[shear_controlled ? "secant_shear_modulus_70_percent_Pa" : "secant_modulus_70_percent_Pa"] =
          *a.secant_modulus;
      if (a.softening_ratio)
        result["softening_ratio"] = *a.softening_ratio;
      if (a.flow_angle)
        result["flow_angle_deg"] = *a.flow_angle * 180 / M_PI;
    }
    catch (const std::exception &e)
    {
      result["error"] = e.what();
    }
    return result;
  }
} // namespace anticrack::dem
