#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "porter/runtime/periodic.hpp"

namespace porter::runtime {
namespace {

TEST(LatenessStats, QuantilesOfKnownSamples) {
  LatenessStats stats(0.01);
  for (int i = 1; i <= 100; ++i) stats.add(i * 1e-6);  // 1..100 µs
  EXPECT_EQ(stats.count(), 100u);
  EXPECT_NEAR(stats.quantile_s(0.5), 50e-6, 1.01e-6);
  EXPECT_NEAR(stats.quantile_s(0.99), 99e-6, 1.01e-6);
  EXPECT_NEAR(stats.quantile_s(1.0), 100e-6, 1e-12);
  EXPECT_NEAR(stats.max_s(), 100e-6, 1e-12);
  EXPECT_NEAR(stats.mean_s(), 50.5e-6, 1e-9);
}

TEST(LatenessStats, BeyondRangeReportsTrueMaximum) {
  LatenessStats stats(0.001);
  stats.add(1e-6);
  stats.add(0.5);  // far past the 1 ms histogram
  EXPECT_DOUBLE_EQ(stats.quantile_s(1.0), 0.5);
  EXPECT_DOUBLE_EQ(stats.max_s(), 0.5);
}

TEST(LatenessStats, NegativeAndNanCountAsOnTime) {
  LatenessStats stats;
  stats.add(-1.0);
  stats.add(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(stats.count(), 2u);
  EXPECT_DOUBLE_EQ(stats.max_s(), 0.0);
}

TEST(PeriodicLoop, RejectsNonPositivePeriod) {
  EXPECT_THROW(PeriodicLoop(0.0), std::invalid_argument);
  EXPECT_THROW(PeriodicLoop(-1.0), std::invalid_argument);
  EXPECT_THROW(PeriodicLoop(std::numeric_limits<double>::infinity()), std::invalid_argument);
}

TEST(PeriodicLoop, CountsCyclesAndSkipsMissedDeadlines) {
  PeriodicLoop loop(0.002);
  for (int i = 0; i < 5; ++i) loop.wait();
  EXPECT_EQ(loop.cycles(), 5u);
  const auto before = loop.overruns();
  // A step that sleeps past at least three whole periods must be counted as >= 3 overruns.
  std::this_thread::sleep_for(std::chrono::milliseconds(9));
  loop.wait();
  EXPECT_GE(loop.overruns() - before, 3u);
  EXPECT_EQ(loop.lateness().count(), 6u);
}

}  // namespace
}  // namespace porter::runtime
