// A vector-valued load history F(t), piecewise linear between (time, value) samples and held
// constant after the last one. A ramp F(t) = Fdot t d is the two-sample history {(0, 0), (T, Fdot T d)}
// extended linearly: set `extrapolate_linearly`.
#pragma once

#include "dem/common/types.h"

#include <vector>

namespace anticrack::dem
{
  struct ForceHistory
  {
    std::vector<double> time;  ///< strictly increasing [s]
    std::vector<Vec3> value;   ///< [N]
    bool extrapolate_linearly = false;

    [[nodiscard]] bool empty() const { return time.empty(); }

    /// Constant-rate ramp F(t) = rate * t * direction (direction need not be unit).
    static ForceHistory ramp(double rate, const Vec3 &direction)
    {
      ForceHistory h;
      h.time = {0.0, 1.0};
      h.value = {Vec3::Zero(), rate * direction};
      h.extrapolate_linearly = true;
      return h;
    }

    [[nodiscard]] Vec3 operator()(double t) const
    {
      if (time.empty())
        return Vec3::Zero();
      if (t <= time.front())
        return value.front();
      std::size_t k = 1;
      while (k < time.size() && time[k] < t)
        ++k;
      if (k == time.size())
      {
        if (!extrapolate_linearly || time.size() < 2)
          return value.back();
        k = time.size() - 1;
      }
      const double w = (t - time[k - 1]) / (time[k] - time[k - 1]);
      return (1 - w) * value[k - 1] + w * value[k];
    }
  };
} // namespace anticrack::dem
