// The critical-cut search alone (fem/analysis/critical_cut_search.h), against a known threshold:
// every bracket contains it and is no wider than the resolution, the trials are the ones the rule
// says, and a seed near the answer costs fewer trials than a bisection from the longest cut.
#include "fem/analysis/critical_cut_search.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <stdexcept>

using anticrack::fem::bracket_critical_cut;
using anticrack::fem::CutBracket;

namespace
{
  /// The search for a test that ends from `threshold` on, with the trial count.
  CutBracket search(double threshold, std::optional<double> seed, double longest = 1.0, double resolution = 0.02)
  {
    return bracket_critical_cut(seed, longest, resolution, [&](double cut) { return cut >= threshold; });
  }

  void expect_bracket(const CutBracket &b, double threshold, double resolution)
  {
    ASSERT_TRUE(b.shortest_ending.has_value());
    EXPECT_LT(b.longest_holding, threshold);
    EXPECT_GE(*b.shortest_ending, threshold);
    EXPECT_LE(*b.shortest_ending - b.longest_holding, resolution * (1 + 1e-9));
    for (const auto &trial : b.trials)
      EXPECT_EQ(trial.ends_test, trial.cut_length >= threshold) << trial.cut_length;
  }
} // namespace

TEST(CriticalCutSearch, BisectionFromTheLongestCutBracketsEveryThreshold)
{
  for (const double threshold : {0.013, 0.2, 0.4371, 0.5, 0.99})
  {
    const CutBracket b = search(threshold, std::nullopt);
    expect_bracket(b, threshold, 0.02);
    EXPECT_DOUBLE_EQ(b.trials.front().cut_length, 1.0);
    // (0, 1] halved to 0.02: 1 + ceil(log2(1 / 0.02)) = 7 trials.
    EXPECT_EQ(b.trials.size(), 7u) << threshold;
  }
}

TEST(CriticalCutSearch, SeededSearchStepsAwayFromTheSeedThenBisects)
{
  // The seed ends the test: 0.43, then 0.41 (ends), 0.37 (ends), 0.29 (holds), then bisection of
  // [0.29, 0.37]: 0.33 (holds), 0.35: the trials of the default pipeline's flat PST.
  const CutBracket below = search(0.345, 0.43);
  expect_bracket(below, 0.345, 0.02);
  const double expected[] = {0.43, 0.41, 0.37, 0.29, 0.33, 0.35};
  ASSERT_EQ(below.trials.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k)
    EXPECT_NEAR(below.trials[k].cut_length, expected[k], 1e-12) << k;
  // The seed holds: steps up.
  const CutBracket above = search(0.52, 0.43);
  expect_bracket(above, 0.52, 0.02);
  EXPECT_NEAR(above.trials[1].cut_length, 0.45, 1e-12);
  // A seed one step from the answer: two trials.
  EXPECT_EQ(search(0.42, 0.43).trials.size(), 2u);
  // Whatever the seed (an advancing saw's answer depends on its speed), the same threshold is found.
  for (const double seed : {0.05, 0.3, 0.6, 0.95, 2.0})
    expect_bracket(search(0.4371, seed), 0.4371, 0.02);
}

TEST(CriticalCutSearch, EndsAtZeroOrAtTheLongestCut)
{
  // Every cut ends the test: the bracket reaches down to the intact column.
  const CutBracket all = search(0.0, 0.3);
  ASSERT_TRUE(all.shortest_ending.has_value());
  EXPECT_EQ(all.longest_holding, 0.0);
  EXPECT_LE(*all.shortest_ending, 0.02 * (1 + 1e-9));
  // No cut up to the longest ends it: no bracket, and the longest was tried.
  for (const std::optional<double> seed : {std::optional<double>(), std::optional<double>(0.4)})
  {
    const CutBracket none = search(1.5, seed);
    EXPECT_FALSE(none.shortest_ending.has_value());
    EXPECT_DOUBLE_EQ(none.trials.back().cut_length, 1.0);
    EXPECT_DOUBLE_EQ(none.longest_holding, 1.0);
  }
}

TEST(CriticalCutSearch, RefusesANonPositiveResolutionOrLength)
{
  EXPECT_THROW(search(0.4, 0.4, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(search(0.4, 0.4, 0.0, 0.02), std::invalid_argument);
  EXPECT_THROW(search(0.4, 0.4, 1.0, std::nan("")), std::invalid_argument);
}
