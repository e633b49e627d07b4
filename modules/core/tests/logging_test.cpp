// Tests of rove/core/logging.h with an injected sink.

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rove/core/logging.h"

namespace {

using rove::LogLevel;
using rove::Logger;
using rove::LogRecord;

struct Captured {
  LogLevel level;
  std::string logger;
  std::string message;
  int line;
};

// A sink that stores records; it relies on the Logger's lock.
struct Capture {
  std::vector<Captured> records;
  rove::LogSink sink() {
    return [this](const LogRecord& r) {
      records.push_back({r.level, std::string(r.logger), std::string(r.message), r.line});
    };
  }
};

// Counts how many times it is formatted.
struct Counted {
  int* formats;
};

}  // namespace

template <>
struct fmt::formatter<Counted> : fmt::formatter<int> {
  auto format(const Counted& c, fmt::format_context& ctx) const {
    ++*c.formats;
    return fmt::formatter<int>::format(*c.formats, ctx);
  }
};

namespace {

TEST(Logging, LevelsBelowTheMinimumAreDropped) {
  Capture cap;
  Logger log("icp", LogLevel::Warn, cap.sink());
  ROVE_LOG_TRACE(log, "t");
  ROVE_LOG_DEBUG(log, "d");
  ROVE_LOG_INFO(log, "i");
  ROVE_LOG_WARN(log, "w {}", 1);
  ROVE_LOG_ERROR(log, "e {}", 2);
  ASSERT_EQ(cap.records.size(), 2u);
  EXPECT_EQ(cap.records[0].level, LogLevel::Warn);
  EXPECT_EQ(cap.records[0].message, "w 1");
  EXPECT_EQ(cap.records[0].logger, "icp");
  EXPECT_EQ(cap.records[1].level, LogLevel::Error);
  EXPECT_EQ(cap.records[1].message, "e 2");

  log.set_level(LogLevel::Trace);
  ROVE_LOG_TRACE(log, "now {}", "visible");
  ASSERT_EQ(cap.records.size(), 3u);
  EXPECT_EQ(cap.records[2].message, "now visible");

  log.set_level(LogLevel::Off);
  ROVE_LOG_ERROR(log, "silenced");
  EXPECT_EQ(cap.records.size(), 3u);
  EXPECT_FALSE(log.enabled(LogLevel::Off));
}

TEST(Logging, DisabledLevelsDoNotFormatOrEvaluateArguments) {
  Capture cap;
  Logger log("x", LogLevel::Info, cap.sink());
  int formats = 0;
  int evaluations = 0;
  auto expensive = [&] {
    ++evaluations;
    return 1;
  };
  ROVE_LOG_DEBUG(log, "{} {}", Counted{&formats}, expensive());
  EXPECT_EQ(formats, 0);
  EXPECT_EQ(evaluations, 0);
  EXPECT_TRUE(cap.records.empty());
  ROVE_LOG_INFO(log, "{} {}", Counted{&formats}, expensive());
  EXPECT_EQ(formats, 1);
  EXPECT_EQ(evaluations, 1);
  ASSERT_EQ(cap.records.size(), 1u);
  EXPECT_EQ(cap.records[0].message, "1 1");
}

TEST(Logging, MacroRecordsTheCallSite) {
  Capture cap;
  Logger log("x", LogLevel::Info, cap.sink());
  const int line = __LINE__ + 1;
  ROVE_LOG_INFO(log, "here");
  ASSERT_EQ(cap.records.size(), 1u);
  EXPECT_EQ(cap.records[0].line, line);
}

TEST(Logging, LogfAndSetSink) {
  Capture a;
  Capture b;
  Logger log("x", LogLevel::Info, a.sink());
  log.logf(LogLevel::Info, "{:.2f}", 0.125);
  log.set_sink(b.sink());
  log.logf(LogLevel::Error, "{}", "to b");
  log.logf(LogLevel::Debug, "{}", "dropped");
  ASSERT_EQ(a.records.size(), 1u);
  EXPECT_EQ(a.records[0].message, "0.12");
  ASSERT_EQ(b.records.size(), 1u);
  EXPECT_EQ(b.records[0].message, "to b");
}

TEST(Logging, FormatsRecordsWithUtcTimeLevelAndName) {
  LogRecord r;
  r.level = LogLevel::Warn;
  r.logger = "rawlog";
  r.message = "skipping frame 7";
  r.time = std::chrono::system_clock::time_point(std::chrono::milliseconds(86400000LL + 3723042));
  EXPECT_EQ(rove::format_log_record(r), "1970-01-02 01:02:03.042 [W] rawlog: skipping frame 7");
  std::ostringstream os;
  Logger log("s", LogLevel::Info, rove::ostream_sink(os));
  log.log(LogLevel::Info, "hello");
  const std::string out = os.str();
  EXPECT_EQ(out.back(), '\n');
  EXPECT_NE(out.find(" [I] s: hello"), std::string::npos) << out;
}

TEST(Logging, LevelNamesRoundTrip) {
  for (auto lv : {LogLevel::Trace, LogLevel::Debug, LogLevel::Info, LogLevel::Warn, LogLevel::Error,
                  LogLevel::Off}) {
    EXPECT_EQ(rove::parse_log_level(rove::to_string(lv)), lv);
  }
  EXPECT_EQ(rove::parse_log_level("WARNING"), LogLevel::Warn);
  EXPECT_EQ(rove::parse_log_level("Debug"), LogLevel::Debug);
  EXPECT_FALSE(rove::parse_log_level("verbose").has_value());
}

TEST(Logging, ConcurrentLoggingDeliversEveryRecordWhole) {
  Capture cap;  // not synchronized itself: the logger must serialize calls
  Logger log("mt", LogLevel::Info, cap.sink());
  constexpr int kThreads = 4;
  constexpr int kPerThread = 2000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&log, t] {
      for (int i = 0; i < kPerThread; ++i) ROVE_LOG_INFO(log, "thread {} item {}", t, i);
    });
  }
  for (auto& th : threads) th.join();
  ASSERT_EQ(cap.records.size(), static_cast<std::size_t>(kThreads * kPerThread));
  std::vector<int> next(kThreads, 0);
  for (const auto& r : cap.records) {
    int t = -1;
    int i = -1;
    ASSERT_EQ(std::sscanf(r.message.c_str(), "thread %d item %d", &t, &i), 2) << r.message;
    ASSERT_GE(t, 0);
    ASSERT_LT(t, kThreads);
    EXPECT_EQ(i, next[t]++);  // per-thread order is kept
  }
}

TEST(Logging, DefaultLoggerIsShared) {
  EXPECT_EQ(&rove::default_logger(), &rove::default_logger());
  EXPECT_EQ(rove::default_logger().name(), "rove");
}

}  // namespace
