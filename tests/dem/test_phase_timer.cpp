// util/phase_timer.h and util/console.h: the phases of summary.json's timing and the rank-0 stream.
#include "util/console.h"
#include "util/phase_timer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <sstream>
#include <thread>

using anticrack::ConditionalStream;
using anticrack::PhaseTimer;

TEST(PhaseTimer, PhasesAccumulateInTheOrderTheyFirstRan)
{
  PhaseTimer timer;
  timer.add("output", 0.25);
  timer.add("time stepping", 1.0);
  timer.add("output", 0.5);
  const auto json = timer.to_json();
  ASSERT_EQ(json.size(), 2u);
  EXPECT_EQ(json.begin().key(), "output"); // first entered, first listed
  EXPECT_DOUBLE_EQ(json["output"]["wall_s"].get<double>(), 0.75);
  EXPECT_EQ(json["output"]["calls"].get<long>(), 2);
  EXPECT_DOUBLE_EQ(timer.seconds("time stepping"), 1.0);
  EXPECT_DOUBLE_EQ(timer.seconds("never entered"), 0.0);
}

TEST(PhaseTimer, ScopeMeasuresItsLifetime)
{
  PhaseTimer timer;
  const auto start = std::chrono::steady_clock::now();
  {
    const auto phase = timer.scope("sleep");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const double outside = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // At least the 20 ms slept, at most the time measured around the scope.
  EXPECT_GE(timer.seconds("sleep"), 0.020);
  EXPECT_LE(timer.seconds("sleep"), outside);
}

TEST(ConditionalStream, OnlyTheActiveStreamWrites)
{
  std::ostringstream out;
  ConditionalStream(&out, false) << "rank 1 " << 42 << std::endl;
  ConditionalStream(&out, true).line("rank ", 0, ": t = ", 0.5, " s");
  ConditionalStream(nullptr, true) << "quiet";
  EXPECT_EQ(out.str(), "rank 0: t = 0.5 s\n");
}
