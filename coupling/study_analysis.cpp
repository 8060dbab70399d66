#include "coupling/study_analysis.h"

#include <cmath>
#include <cstddef>

namespace anticrack::coupling
{
  std::vector<std::optional<double>> relative_errors(const std::vector<std::optional<double>> &y,
                                                     const std::optional<double> reference)
  {
    std::vector<std::optional<double>> error(y.size());
    if (!reference || *reference == 0 || !std::isfinite(*reference))
      return error;
    for (std::size_t k = 0; k < y.size(); ++k)
      if (y[k] && std::isfinite(*y[k]))
        error[k] = std::abs(*y[k] - *reference) / std::abs(*reference);
    return error;
  }

  std::vector<std::optional<double>> observed_orders_against_known(const std::vector<double> &h,
                                                                   const std::vector<std::optional<double>> &error)
  {
    std::vector<std::optional<double>> order;
    for (std::size_t k = 0; k + 1 < h.size() && k + 1 < error.size(); ++k)
    {
      const std::optional<double> e1 = error[k], e2 = error[k + 1];
      if (e1 && e2 && *e1 > 0 && *e2 > 0 && h[k] > h[k + 1])
        order.emplace_back(std::log(*e1 / *e2) / std::log(h[k] / h[k + 1]));
      else
        order.emplace_back();
    }
    return order;
  }

  std::vector<std::optional<double>> observed_orders_from_triples(const std::vector<double> &h,
                                                                  const std::vector<std::optional<double>> &y)
  {
    std::vector<std::optional<double>> order;
    for (std::size_t k = 0; k + 2 < h.size() && k + 2 < y.size(); ++k)
    {
      order.emplace_back();
      if (!y[k] || !y[k + 1] || !y[k + 2] || !(h[k] > h[k + 1] && h[k + 1] > h[k + 2]))
        continue;
      const double d12 = *y[k] - *y[k + 1], d23 = *y[k + 1] - *y[k + 2];
      if (d12 == 0 || d23 == 0 || (d12 > 0) != (d23 > 0))
        continue; // converged to round-off, or not in the asymptotic range
      const double ratio = d12 / d23;
      const auto g = [&](double p) {
        return (std::pow(h[k], p) - std::pow(h[k + 1], p)) / (std::pow(h[k + 1], p) - std::pow(h[k + 2], p)) - ratio;
      };
      double lo = 0.01, hi = 20;
      if (g(lo) > 0 || g(hi) < 0)
        continue; // the ratio asks for an order outside (0.01, 20)
      for (int iteration = 0; iteration < 200 && hi - lo > 1e-12; ++iteration)
      {
        const double mid = 0.5 * (lo + hi);
        (g(mid) < 0 ? lo : hi) = mid;
      }
      order.back() = 0.5 * (lo + hi);
    }
    return order;
  }

  std::optional<std::size_t> cheapest_within(const std::vector<double> &cost,
                                             const std::vector<std::optional<double>> &error, const double tolerance,
                                             const std::optional<std::size_t> excluded)
  {
    std::optional<std::size_t> best;
    for (std::size_t k = 0; k < cost.size() && k < error.size(); ++k)
      if (k != excluded && error[k] && *error[k] <= tolerance && (!best || cost[k] < cost[*best]))
        best = k;
    return best;
  }
} // namespace anticrack::coupling
