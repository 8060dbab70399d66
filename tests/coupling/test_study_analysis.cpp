// The study's measures (coupling/study_analysis.h) and its variants (coupling/study_scene.h),
// against sequences whose order of convergence and errors are known in closed form.
#include "coupling/study_analysis.h"
#include "coupling/study_scene.h"
#include "util/parameter_files.h"
#include "util/problems.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace anticrack::coupling;

namespace
{
  /// y(h) = y* + C h^p (+ D h^(p+1)): a discretised answer with leading order p.
  std::vector<std::optional<double>> answers(const std::vector<double> &h, double p, double higher = 0)
  {
    std::vector<std::optional<double>> y;
    for (double x : h)
      y.emplace_back(3.0 + 0.7 * std::pow(x, p) + higher * std::pow(x, p + 1));
    return y;
  }
} // namespace

TEST(StudyAnalysis, RelativeErrorsAgainstAReference)
{
  const auto e = relative_errors({2.0, std::nullopt, 1.9}, 2.0);
  EXPECT_DOUBLE_EQ(*e[0], 0.0);
  EXPECT_FALSE(e[1]);
  EXPECT_NEAR(*e[2], 0.05, 1e-15);
  EXPECT_FALSE(relative_errors({1.0}, 0.0)[0]); // no relative error against zero
  EXPECT_FALSE(relative_errors({1.0}, std::nullopt)[0]);
}

TEST(StudyAnalysis, OrderFromTriplesWithAConstantRatio)
{
  // Richardson with r = 2 recovers p exactly for a pure power law.
  const std::vector<double> h{0.04, 0.02, 0.01, 0.005};
  for (double p : {0.5, 1.0, 2.0, 3.3})
  {
    const auto orders = observed_orders_from_triples(h, answers(h, p));
    ASSERT_EQ(orders.size(), 2u);
    for (const auto &order : orders)
      EXPECT_NEAR(*order, p, 1e-8) << "p = " << p;
  }
}

TEST(StudyAnalysis, OrderFromTriplesWithUnequalRatios)
{
  // h = 1, 0.6, 0.25: the bisection solves (h1^p - h2^p)/(h2^p - h3^p) = (y1 - y2)/(y2 - y3).
  const std::vector<double> h{1.0, 0.6, 0.25};
  for (double p : {0.8, 1.7, 4.0})
    EXPECT_NEAR(*observed_orders_from_triples(h, answers(h, p))[0], p, 1e-8) << "p = " << p;
}

TEST(StudyAnalysis, OrderApproachesTheLeadingOneWithAHigherTerm)
{
  // With a higher-order term D h^3 beside C h^2 the observed order is 2 + O((D/C) h) and tends
  // to 2 from above, monotonically: 2.19, 2.11, 2.06 for D/C = 0.71 and h = 0.4 ... 0.025.
  const std::vector<double> h{0.4, 0.2, 0.1, 0.05, 0.025};
  const auto orders = observed_orders_from_triples(h, answers(h, 2.0, 0.5));
  ASSERT_EQ(orders.size(), 3u);
  EXPECT_GT(*orders[0], *orders[1]);
  EXPECT_GT(*orders[1], *orders[2]);
  EXPECT_GT(*orders[2], 2.0);
  EXPECT_NEAR(*orders[2], 2.0566, 1e-3);
}

TEST(StudyAnalysis, NoOrderOutsideTheAsymptoticRange)
{
  // Differences of opposite sign (oscillation), or equal answers, give no order.
  EXPECT_FALSE(observed_orders_from_triples({0.04, 0.02, 0.01}, {1.0, 1.2, 1.1})[0]);
  EXPECT_FALSE(observed_orders_from_triples({0.04, 0.02, 0.01}, {1.0, 1.0, 1.0})[0]);
  EXPECT_FALSE(observed_orders_from_triples({0.04, 0.02, 0.01}, {1.0, std::nullopt, 1.1})[0]);
}

TEST(StudyAnalysis, OrderAgainstAKnownValue)
{
  const std::vector<double> h{0.04, 0.02, 0.01};
  const auto y = answers(h, 1.5);
  const auto orders = observed_orders_against_known(h, relative_errors(y, 3.0));
  ASSERT_EQ(orders.size(), 2u);
  EXPECT_NEAR(*orders[0], 1.5, 1e-10);
  EXPECT_NEAR(*orders[1], 1.5, 1e-10);
}

TEST(StudyAnalysis, CheapestWithinATolerance)
{
  const std::vector<double> cost{1, 4, 16, 64};
  const std::vector<std::optional<double>> error{0.2, 0.04, 0.008, 0.0};
  EXPECT_EQ(cheapest_within(cost, error, 0.05), 1u);
  EXPECT_EQ(cheapest_within(cost, error, 0.01), 2u);
  // The reference variant itself does not count: its error is zero by definition.
  EXPECT_FALSE(cheapest_within(cost, error, 0.001, 3u));
  EXPECT_EQ(cheapest_within(cost, error, 0.001), 3u);
}

TEST(StudyScene, VariantsAndLines)
{
  StudyScene study;
  StudyEntry length;
  length.path = "Mesh/Element length [m]";
  length.values = {"0.01", "0.04", "0.02"};
  length.refinement = Refinement::size;
  StudyEntry rows;
  rows.path = "Mesh/Weak layer elements";
  rows.values = {"1", "2"};
  rows.refinement = Refinement::count;
  study.entries = {length, rows};

  // One at a time: 3 + 2 variants, each line sorted coarsest first.
  auto variants = study_variants(study);
  ASSERT_EQ(variants.size(), 5u);
  EXPECT_EQ(variants[3].changes, (std::vector<anticrack::EntryChange>{{"Mesh/Weak layer elements", "1"}}));
  EXPECT_EQ(line_of_entry(study, variants, 0), (std::vector<std::size_t>{1, 2, 0})); // 0.04, 0.02, 0.01
  EXPECT_EQ(line_of_entry(study, variants, 1), (std::vector<std::size_t>{3, 4}));

  // Product: 6 variants; an entry's line holds the other at its finest value.
  study.product = true;
  variants = study_variants(study);
  ASSERT_EQ(variants.size(), 6u);
  EXPECT_EQ(variants.back().id, "v005");
  const auto line = line_of_entry(study, variants, 0);
  ASSERT_EQ(line.size(), 3u);
  for (std::size_t v : line)
    EXPECT_EQ(*variants[v].level[1], 1u); // two rows, the finest count
  EXPECT_EQ(*study.entries[0].finest(), 0u);
  EXPECT_EQ(*study.entries[1].finest(), 1u);
}

// Values that are not numbers (entry changes of a pipeline's weak layer) are ordered and measured by
// their Measures: the line runs from the fewest particles to the most, whatever the written order.
TEST(StudyScene, MeasuresOrderValuesThatAreNotNumbers)
{
  StudyScene study;
  StudyEntry count;
  count.path = "Pipeline/Weak layer scene changes";
  count.values = {"DEM/Sample/Particle count = 4096", "DEM/Sample/Particle count = 1024",
                  "DEM/Sample/Particle count = 2048"};
  count.measures = {4096, 1024, 2048};
  count.refinement = Refinement::count;
  study.entries = {count};
  const auto variants = study_variants(study);
  EXPECT_EQ(variants[0].changes, (std::vector<anticrack::EntryChange>{{count.path, count.values[0]}}));
  EXPECT_EQ(line_of_entry(study, variants, 0), (std::vector<std::size_t>{1, 2, 0}));
  EXPECT_EQ(*study.entries[0].finest(), 0u);
  EXPECT_EQ(study.entries[0].numbers(), count.measures);
}

TEST(StudyScene, ResultLabelsAreTheShortestUniqueEndings)
{
  const std::vector<std::string> pointers = {"/c/m/0/surface/p0/value", "/c/m/0/surface/M/value",
                                             "/c/m/0/surface/p0/interval/0", "/results/critical_cut_length_m"};
  EXPECT_EQ(result_label(pointers[0], pointers), "p0_value");
  EXPECT_EQ(result_label(pointers[1], pointers), "M_value");
  EXPECT_EQ(result_label(pointers[2], pointers), "interval_0");
  EXPECT_EQ(result_label(pointers[3], pointers), "critical_cut_length_m");
  const std::vector<std::string> same_ending = {"/a/x/y", "/b/x/y"};
  EXPECT_EQ(result_label(same_ending[0], same_ending), "a_x_y");
  EXPECT_EQ(result_label("/a/x/y", {"/a/x/y"}), "y");
}

// Base scene changes (and every other `path = value` list): an item without `=` continues the
// value before it, so list values can be set; a list that starts without one is refused.
TEST(StudyScene, EntryChangeListsCarryListValues)
{
  anticrack::Problems problems("test");
  const auto changes = anticrack::entry_changes_in_list(
    "Campaign/Loading angles [deg] = 0, 45, 90, Campaign/Realizations = 1", "Study/Base scene changes", problems);
  EXPECT_TRUE(problems.empty());
  EXPECT_EQ(changes, (std::vector<anticrack::EntryChange>{{"Campaign/Loading angles [deg]", "0, 45, 90"},
                                                          {"Campaign/Realizations", "1"}}));
  // The writer gives back the text the reader read, list value included.
  EXPECT_EQ(anticrack::entry_changes_text(changes),
            "Campaign/Loading angles [deg] = 0, 45, 90, Campaign/Realizations = 1");
  anticrack::entry_changes_in_list("45, Campaign/Realizations = 1", "Study/Base scene changes", problems);
  EXPECT_EQ(problems.count(), 1u);
}
