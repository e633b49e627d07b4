// Tests of rove/core/timer.h and profiler.h. No assertion depends on how
// long anything takes: only on counts, on explicit add() values, and on the
// ordering of readings of the monotonic clock.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <thread>
#include <vector>

#include "rove/core/error.h"
#include "rove/core/profiler.h"
#include "rove/core/timer.h"

namespace {

using rove::Profiler;
using rove::ScopedTimer;
using rove::Stopwatch;

TEST(Stopwatch, IsMonotonicAndLapRestarts) {
  Stopwatch sw;
  double prev = sw.elapsed();
  EXPECT_GE(prev, 0.0);
  for (int i = 0; i < 1000; ++i) {
    const double now = sw.elapsed();
    EXPECT_GE(now, prev);
    prev = now;
  }
  Stopwatch inner;  // started after sw, so it can never show more
  const double a = inner.elapsed();
  const double b = sw.elapsed();
  EXPECT_LE(a, b);
  const double lap = sw.lap();
  EXPECT_GE(lap, b);
  // sw restarted after inner started. Each pair of readings is taken in
  // named order: the order in which a macro's arguments are evaluated is
  // unspecified, and reading inner first would let sw gain the time between.
  const double sw_after_lap = sw.elapsed();
  const double inner_after_lap = inner.elapsed();
  EXPECT_LE(sw_after_lap, inner_after_lap);
  sw.reset();
  const double sw_after_reset = sw.elapsed();
  const double inner_after_reset = inner.elapsed();
  EXPECT_LE(sw_after_reset, inner_after_reset);
}

TEST(Profiler, AccumulatesCallsMinMeanMaxTotal) {
  Profiler p;
  p.add("icp", 0.003);
  p.add("icp", 0.001);
  p.add("icp", 0.002);
  const auto s = p.stats("icp");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->calls, 3u);
  EXPECT_DOUBLE_EQ(s->min, 0.001);
  EXPECT_DOUBLE_EQ(s->max, 0.003);
  EXPECT_DOUBLE_EQ(s->total, 0.006);
  EXPECT_DOUBLE_EQ(s->mean(), 0.002);
  EXPECT_FALSE(p.stats("other").has_value());
  p.clear();
  EXPECT_FALSE(p.stats("icp").has_value());
}

TEST(Profiler, EntriesSortedByTotalThenName) {
  Profiler p;
  p.add("b", 1.0);
  p.add("a", 1.0);
  p.add("c", 0.5);
  p.add("c", 2.0);
  const auto e = p.entries();
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[0].name, "c");
  EXPECT_EQ(e[1].name, "a");
  EXPECT_EQ(e[2].name, "b");
}

TEST(Profiler, ReportIsATableSortedByTotal) {
  Profiler p;
  p.add("load", 0.5);
  p.add("icp.align", 0.002);
  p.add("icp.align", 0.004);
  const std::string expected =
      "block         calls           min          mean           max         total\n"
      "load              1    500.000 ms    500.000 ms    500.000 ms    500.000 ms\n"
      "icp.align         2      2.000 ms      3.000 ms      4.000 ms      6.000 ms\n";
  EXPECT_EQ(p.report(), expected);
}

TEST(Profiler, DisabledRecordsNothing) {
  Profiler p(false);
  EXPECT_FALSE(p.enabled());
  p.add("x", 1.0);
  {
    ScopedTimer t(p, "y");
    EXPECT_EQ(t.elapsed(), 0.0);
  }
  EXPECT_TRUE(p.entries().empty());
  p.set_enabled(true);
  p.add("x", 1.0);
  EXPECT_EQ(p.stats("x")->calls, 1u);
}

TEST(Profiler, RejectsNegativeAndNonFiniteTimes) {
  Profiler p;
  EXPECT_THROW(p.add("x", -1e-9), rove::InvalidArgument);
  EXPECT_THROW(p.add("x", std::numeric_limits<double>::quiet_NaN()), rove::InvalidArgument);
  EXPECT_THROW(p.add("x", std::numeric_limits<double>::infinity()), rove::InvalidArgument);
  EXPECT_TRUE(p.entries().empty());
}

TEST(ScopedTimer, AddsItsLifetimeToTheProfiler) {
  Profiler p;
  double inside = 0.0;
  {
    ScopedTimer t(p, "block");
    Stopwatch sw;  // started after t and read before t stops
    for (int i = 0; i < 3; ++i) inside = sw.elapsed();
  }
  const auto s = p.stats("block");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->calls, 1u);
  EXPECT_GE(s->total, inside);
}

TEST(ScopedTimer, WritesToADouble) {
  double seconds = -1.0;
  double inside = 0.0;
  {
    ScopedTimer t(seconds);
    Stopwatch sw;
    inside = sw.elapsed();
    EXPECT_GE(t.elapsed(), inside);
  }
  EXPECT_GE(seconds, inside);
}

TEST(Profiler, ConcurrentAddsAreAllCounted) {
  Profiler p;
  constexpr int kThreads = 4;
  constexpr int kPerThread = 5000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&p] {
      for (int i = 0; i < kPerThread; ++i) p.add("shared", 0.25);  // exact in binary
    });
  }
  for (auto& th : threads) th.join();
  const auto s = p.stats("shared");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->calls, static_cast<std::uint64_t>(kThreads * kPerThread));
  EXPECT_EQ(s->total, 0.25 * kThreads * kPerThread);
}

TEST(FormatDuration, PicksTheUnit) {
  EXPECT_EQ(rove::format_duration(2.5), "2.500 s");
  EXPECT_EQ(rove::format_duration(0.0123), "12.300 ms");
  EXPECT_EQ(rove::format_duration(4.2e-6), "4.200 us");
  EXPECT_EQ(rove::format_duration(3e-9), "3.000 ns");
  EXPECT_EQ(rove::format_duration(0.0), "0.000 s");
}

}  // namespace
