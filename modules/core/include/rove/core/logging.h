#pragma once
/// \file
/// Leveled logging. A Logger has a name, a minimum level and a sink; the
/// ROVE_LOG_* macros format their message (fmt syntax) only when the level
/// is enabled, so a disabled debug line costs one atomic load:
///
///   rove::Logger log("icp", rove::LogLevel::Debug);
///   ROVE_LOG_INFO(log, "converged after {} iterations", n);
///
/// Algorithms receive the logger to use through their options (a pointer,
/// null meaning silent); default_logger() is the process-wide logger for
/// command-line tools.

#include <atomic>
#include <chrono>
#include <functional>
#include <iosfwd>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

#include <fmt/format.h>

namespace rove {

/// Severity of a log record, from most verbose to most severe. `Off` as a
/// minimum level disables a logger.
enum class LogLevel { Trace = 0, Debug, Info, Warn, Error, Off };

/// "trace", "debug", "info", "warn", "error", "off".
std::string_view to_string(LogLevel level);
/// Parses the names above (case-insensitive; also "warning"); nullopt if
/// `text` is none of them.
std::optional<LogLevel> parse_log_level(std::string_view text);

/// One message handed to a sink. The views are valid only during the call.
struct LogRecord {
  LogLevel level = LogLevel::Info;
  std::string_view logger;   ///< name of the logger
  std::string_view message;  ///< formatted text, no trailing newline
  std::chrono::system_clock::time_point time;
  const char* file = nullptr;  ///< source file of the log statement, or null
  int line = 0;                ///< source line, 0 if unknown
};

/// Receives records. A Logger calls its sink under its lock, so a sink
/// needs no locking of its own unless it is shared between loggers.
using LogSink = std::function<void(const LogRecord&)>;

/// `"2026-01-31 12:34:56.789 [W] name: message"` (UTC), no newline.
std::string format_log_record(const LogRecord& record);
/// A sink writing format_log_record() lines to stderr.
LogSink stderr_sink();
/// A sink writing format_log_record() lines to `os`, which must outlive the
/// sink and not be written by others concurrently.
LogSink ostream_sink(std::ostream& os);

/// A named logger with a minimum level and a sink. Thread-safe: any thread
/// may log, change the level or replace the sink at any time; records from
/// one logger reach its sink one at a time. Not copyable.
class Logger {
 public:
  /// A logger called `name` that passes records at `min_level` or above to
  /// `sink` (stderr_sink() if empty).
  explicit Logger(std::string name, LogLevel min_level = LogLevel::Info, LogSink sink = {});
  Logger(const Logger&) = delete;
  Logger& operator=(const Logger&) = delete;

  /// The name given at construction.
  const std::string& name() const noexcept { return name_; }
  /// The minimum level that reaches the sink.
  LogLevel level() const noexcept { return level_.load(std::memory_order_relaxed); }
  /// Changes the minimum level.
  void set_level(LogLevel level) noexcept { level_.store(level, std::memory_order_relaxed); }
  /// True if a record at `level` would reach the sink.
  bool enabled(LogLevel level) const noexcept {
    return level != LogLevel::Off && level >= this->level();
  }
  /// Replaces the sink (stderr_sink() if empty).
  void set_sink(LogSink sink);

  /// Sends `message` at `level` if enabled. `file`/`line` name the call site.
  void log(LogLevel level, std::string_view message, const char* file = nullptr,
           int line = 0) const;
  /// Formats with fmt and logs, if enabled.
  template <typename... Args>
  void logf(LogLevel level, fmt::format_string<Args...> format, Args&&... args) const {
    if (enabled(level)) log(level, fmt::format(format, std::forward<Args>(args)...));
  }

 private:
  std::string name_;
  std::atomic<LogLevel> level_;
  mutable std::mutex mutex_;
  LogSink sink_;
};

/// The process-wide logger ("rove", level Info, stderr) for command-line
/// tools. Library code logs through the logger passed in its options.
Logger& default_logger();

}  // namespace rove

/// Logs at `level` through `logger` (a Logger or a reference to one). The
/// format arguments are evaluated only when the level is enabled.
#define ROVE_LOG(logger, level, ...)                                                   \
  do {                                                                                 \
    const ::rove::Logger& rove_log_logger_ = (logger);                                 \
    if (rove_log_logger_.enabled(level))                                               \
      rove_log_logger_.log((level), ::fmt::format(__VA_ARGS__), __FILE__, __LINE__);   \
  } while (false)

/// Leveled shorthands for ROVE_LOG.
#define ROVE_LOG_TRACE(logger, ...) ROVE_LOG(logger, ::rove::LogLevel::Trace, __VA_ARGS__)
#define ROVE_LOG_DEBUG(logger, ...) ROVE_LOG(logger, ::rove::LogLevel::Debug, __VA_ARGS__)
#define ROVE_LOG_INFO(logger, ...) ROVE_LOG(logger, ::rove::LogLevel::Info, __VA_ARGS__)
#define ROVE_LOG_WARN(logger, ...) ROVE_LOG(logger, ::rove::LogLevel::Warn, __VA_ARGS__)
#define ROVE_LOG_ERROR(logger, ...) ROVE_LOG(logger, ::rove::LogLevel::Error, __VA_ARGS__)
