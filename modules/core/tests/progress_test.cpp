// Tests of rove/core/progress.h with an injected clock, so that the output
// is deterministic and can be checked exactly.

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>

#include "rove/core/error.h"
#include "rove/core/progress.h"

namespace {

using rove::Progress;
using rove::ProgressMode;
using rove::ProgressOptions;

ProgressOptions lines_at(const double* clock, double interval = 0.0) {
  ProgressOptions o;
  o.mode = ProgressMode::Lines;
  o.line_interval_seconds = interval;
  o.clock = [clock] { return *clock; };
  return o;
}

TEST(Progress, LinesEveryTenPercentThenFinalLine) {
  double t = 0.0;
  std::ostringstream os;
  Progress p(100, "scan", os, lines_at(&t));
  for (int i = 1; i <= 100; ++i) {
    t = i / 10.0;  // 10 steps per second
    p.advance();
  }
  p.finish();
  const std::string expected =
      "scan:  10% (10/100), 10.0 it/s, elapsed 1.0 s, ETA 9.0 s\n"
      "scan:  20% (20/100), 10.0 it/s, elapsed 2.0 s, ETA 8.0 s\n"
      "scan:  30% (30/100), 10.0 it/s, elapsed 3.0 s, ETA 7.0 s\n"
      "scan:  40% (40/100), 10.0 it/s, elapsed 4.0 s, ETA 6.0 s\n"
      "scan:  50% (50/100), 10.0 it/s, elapsed 5.0 s, ETA 5.0 s\n"
      "scan:  60% (60/100), 10.0 it/s, elapsed 6.0 s, ETA 4.0 s\n"
      "scan:  70% (70/100), 10.0 it/s, elapsed 7.0 s, ETA 3.0 s\n"
      "scan:  80% (80/100), 10.0 it/s, elapsed 8.0 s, ETA 2.0 s\n"
      "scan:  90% (90/100), 10.0 it/s, elapsed 9.0 s, ETA 1.0 s\n"
      "scan: done, 100/100 it in 10.0 s (10.0 it/s)\n";
  EXPECT_EQ(os.str(), expected);
  EXPECT_EQ(p.mode(), ProgressMode::Lines);
  EXPECT_EQ(p.done(), 100u);
}

TEST(Progress, JumpsPrintOneLineAndLongEtaUsesHours) {
  double t = 0.0;
  std::ostringstream os;
  Progress p(1000, "map", os, lines_at(&t));
  t = 60.0;
  p.set(5);  // 0%: nothing
  t = 120.0;
  p.set(550);  // crosses 10%..50% at once: one line
  t = 121.0;
  p.set(590);  // still below 60%: nothing
  const std::string expected = "map:  55% (550/1000), 4.6 it/s, elapsed 0:02:00, ETA 0:01:38\n";
  EXPECT_EQ(os.str(), expected);
  t = 130.0;
  p.set(600);
  const std::string out = os.str();
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 2);
}

TEST(Progress, IntervalLinesForUnknownTotal) {
  double t = 0.0;
  std::ostringstream os;
  Progress p(std::nullopt, "frames", os, lines_at(&t, 5.0));
  for (int i = 1; i <= 12; ++i) {
    t = i;
    p.advance(2);
  }
  p.finish();
  const std::string expected =
      "frames: 10 it, 2.0 it/s, elapsed 5.0 s\n"
      "frames: 20 it, 2.0 it/s, elapsed 10.0 s\n"
      "frames: done, 24 it in 12.0 s (2.0 it/s)\n";
  EXPECT_EQ(os.str(), expected);
}

TEST(Progress, IntervalAlsoAppliesToKnownTotalButNotWithoutProgress) {
  double t = 0.0;
  std::ostringstream os;
  ProgressOptions o = lines_at(&t, 30.0);
  o.unit = "scans";
  Progress p(1000, "slow", os, o);
  t = 10.0;
  p.advance();
  t = 31.0;
  p.advance();  // 30 s since start: a line although only 0.2%
  t = 62.0;
  p.advance(0);  // no progress since the last line: nothing
  EXPECT_EQ(os.str(), "slow:   0% (2/1000), 0.1 scans/s, elapsed 31.0 s, ETA 4:17:49\n");
}

TEST(Progress, FinishTwiceAndDestructorPrintOnce) {
  double t = 0.0;
  std::ostringstream os;
  {
    Progress p(4, "x", os, lines_at(&t));
    t = 2.0;
    p.advance(4);
  }  // destructor finishes
  EXPECT_EQ(os.str(), "x: done, 4/4 it in 2.0 s (2.0 it/s)\n");
  std::ostringstream os2;
  Progress q(0, "empty", os2, lines_at(&t));
  q.finish();
  q.finish();
  q.advance(0);
  EXPECT_EQ(os2.str(), "empty: done, 0/0 it in 0.0 s (- it/s)\n");
}

TEST(Progress, BarRedrawsInPlaceWithThrottle) {
  double t = 0.0;
  std::ostringstream os;
  ProgressOptions o;
  o.mode = ProgressMode::Bar;
  o.bar_width = 10;
  o.bar_interval_seconds = 1.0;
  o.clock = [&t] { return t; };
  Progress p(10, "bar", os, o);
  t = 0.5;
  p.advance(5);  // first draw
  t = 0.9;
  p.advance(1);  // throttled
  p.finish();
  const std::string out = os.str();
  const std::string first = "\rbar [#####.....]  50% (5/10), 10.0 it/s, elapsed 0.5 s, ETA 0.5 s";
  // One character shorter than the first draw: padded with one space.
  const std::string last = "\rbar [######....]  60% (6/10), 6.7 it/s, elapsed 0.9 s, ETA 0.6 s \n";
  EXPECT_EQ(out, first + last) << out;
}

TEST(Progress, BarPadsOverALongerPreviousLine) {
  double t = 0.0;
  std::ostringstream os;
  ProgressOptions o;
  o.mode = ProgressMode::Bar;
  o.bar_interval_seconds = 0.0;
  o.clock = [&t] { return t; };
  Progress p(std::nullopt, "n", os, o);
  t = 100.0;
  p.advance(123456);
  t = 200.0;
  p.set(1);
  p.finish();
  const std::string out = os.str();
  const std::string a = "\rn 123456 it, 1234.6 it/s, elapsed 0:01:40";
  const std::string b = "\rn 1 it, 0.0 it/s, elapsed 0:03:20";
  ASSERT_EQ(out.substr(0, a.size()), a);
  const std::string second = out.substr(a.size(), b.size() + (a.size() - b.size()));
  EXPECT_EQ(second, b + std::string(a.size() - b.size(), ' '));
  EXPECT_EQ(out.back(), '\n');
}

TEST(Progress, AutoOnAStringStreamUsesLines) {
  std::ostringstream os;
  Progress p(3, "a", os);
  EXPECT_EQ(p.mode(), ProgressMode::Lines);
}

TEST(Progress, RejectsCountsBeyondTotalAndBadOptions) {
  double t = 0.0;
  std::ostringstream os;
  Progress p(3, "a", os, lines_at(&t));
  p.advance(3);
  EXPECT_THROW(p.advance(), rove::InvalidArgument);
  EXPECT_THROW(p.set(4), rove::InvalidArgument);
  ProgressOptions bad = lines_at(&t);
  bad.line_percent_step = 0.0;
  EXPECT_THROW(Progress(3, "b", os, bad), rove::InvalidArgument);
  bad = lines_at(&t);
  bad.bar_width = 0;
  EXPECT_THROW(Progress(3, "b", os, bad), rove::InvalidArgument);
}

TEST(FormatElapsed, SecondsThenHours) {
  EXPECT_EQ(rove::format_elapsed(0.04), "0.0 s");
  EXPECT_EQ(rove::format_elapsed(59.94), "59.9 s");
  EXPECT_EQ(rove::format_elapsed(60.0), "0:01:00");
  EXPECT_EQ(rove::format_elapsed(3725.0), "1:02:05");
  EXPECT_EQ(rove::format_elapsed(360000.0), "100:00:00");
}

}  // namespace
