// Tests of util/entry_table.h, the one table that declares and reads a subsection's entries (the
// snowpack scene's Mesh and Output, the dynamic PST's Explicit): every field gets the value the
// file sets, or the default; each kind gets its own deal.II pattern with the table's range, so a
// value out of range, a fraction for a count or a word for a flag is refused by the
// ParameterHandler; an open side of a range admits any value on that side.
#include "util/entry_table.h"

#include <deal.II/base/parameter_handler.h>

#include <gtest/gtest.h>

namespace
{
  using anticrack::BoundEntry;
  using anticrack::no_upper_bound;

  struct Settings
  {
    double length = 0;
    unsigned int rows = 0;
    bool flag = false;
    unsigned int interval = 0;
  };

  const std::vector<BoundEntry<Settings>> &table()
  {
    static const std::vector<BoundEntry<Settings>> entries = {
      {"Length [m]", "0.5", &Settings::length, 0, 2, "a length in [0, 2]. Units: m."},
      {"Rows", "4", &Settings::rows, 1, 64, "a count in [1, 64]."},
      {"Flag", "true", &Settings::flag, 0, 0, "a flag."},
      {"Interval", "1000", &Settings::interval, 0, no_upper_bound, "a count of at least 0."}};
    return entries;
  }

  Settings read(const std::string &text)
  {
    dealii::ParameterHandler prm;
    prm.enter_subsection("Block");
    anticrack::declare_entries(prm, table());
    prm.leave_subsection();
    prm.parse_input_from_string(text);
    Settings settings;
    prm.enter_subsection("Block");
    anticrack::parse_entries(prm, table(), settings);
    prm.leave_subsection();
    return settings;
  }
} // namespace

TEST(EntryTable, EveryFieldGetsTheDefaultOrTheValueSet)
{
  const Settings defaults = read("");
  EXPECT_EQ(defaults.length, 0.5);
  EXPECT_EQ(defaults.rows, 4u);
  EXPECT_TRUE(defaults.flag);
  EXPECT_EQ(defaults.interval, 1000u);

  const Settings set = read("subsection Block\n  set Length [m] = 1.25\n  set Rows = 64\n  set Flag = false\n"
                            "  set Interval = 2000000000\nend\n");
  EXPECT_EQ(set.length, 1.25);
  EXPECT_EQ(set.rows, 64u);
  EXPECT_FALSE(set.flag);
  EXPECT_EQ(set.interval, 2000000000u); // an open upper side admits the largest int
}

TEST(EntryTable, EachKindIsRefusedOutsideItsPatternAndRange)
{
  EXPECT_ANY_THROW(read("subsection Block\n  set Length [m] = 2.5\nend\n"));  // above the range
  EXPECT_ANY_THROW(read("subsection Block\n  set Length [m] = -0.1\nend\n")); // below it
  EXPECT_ANY_THROW(read("subsection Block\n  set Rows = 0\nend\n"));          // a count below 1
  EXPECT_ANY_THROW(read("subsection Block\n  set Rows = 65\nend\n"));         // above 64
  EXPECT_ANY_THROW(read("subsection Block\n  set Rows = 2.5\nend\n"));        // not a count
  EXPECT_ANY_THROW(read("subsection Block\n  set Flag = maybe\nend\n"));      // not a flag
  EXPECT_ANY_THROW(read("subsection Block\n  set Interval = -1\nend\n"));     // the closed lower side
}
