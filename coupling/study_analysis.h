// What a study measures along one entry's line of variants (coupling/study_scene.h), coarsest
// first: the error of each answer, the observed order of convergence, and the cheapest setting
// that reaches a tolerance. Pure functions of numbers, so they are tested against closed forms.
//
// Error: |y − y_ref| / |y_ref|, with y_ref a value the scene gives (a closed form, a measurement)
// or the finest variant's answer.
//
// Observed order p of y(h) = y* + C h^p + ...:
//  - against a known y*: from consecutive pairs, p = ln(e_1/e_2) / ln(h_1/h_2);
//  - without it: from consecutive triples h_1 > h_2 > h_3 (Richardson),
//      (y_1 − y_2)/(y_2 − y_3) = (h_1^p − h_2^p)/(h_2^p − h_3^p),
//    which for a constant ratio r = h_1/h_2 = h_2/h_3 is p = ln((y_1 − y_2)/(y_2 − y_3))/ln r, and
//    otherwise is solved for p in (0.01, 20) by bisection (the right side grows monotonically with p).
//    Differences of opposite sign (not in the asymptotic range) give no order.
#pragma once

#include <optional>
#include <vector>

namespace anticrack::coupling
{
  /// |y − reference| / |reference| for each y (none where y or a nonzero reference is missing).
  std::vector<std::optional<double>> relative_errors(const std::vector<std::optional<double>> &y,
                                                     std::optional<double> reference);

  /// Orders from consecutive pairs of errors against a known value; h decreasing.
  std::vector<std::optional<double>> observed_orders_against_known(const std::vector<double> &h,
                                                                   const std::vector<std::optional<double>> &error);

  /// Orders from consecutive triples of answers (Richardson); h decreasing.
  std::vector<std::optional<double>> observed_orders_from_triples(const std::vector<double> &h,
                                                                  const std::vector<std::optional<double>> &y);

  /// The index of the point of least cost whose error is at most `tolerance` (errors of none do
  /// not count), skipping `excluded` (the reference variant itself, whose error is 0 by
  /// definition); none if no point reaches it.
  std::optional<std::size_t> cheapest_within(const std::vector<double> &cost,
                                             const std::vector<std::optional<double>> &error, double tolerance,
                                             std::optional<std::size_t> excluded = std::nullopt);
} // namespace anticrack::coupling
