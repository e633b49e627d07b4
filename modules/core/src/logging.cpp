#include "rove/core/logging.h"

#include <fmt/chrono.h>

#include <ctime>
#include <iostream>

namespace rove {

std::string_view to_string(LogLevel level) {
  switch (level) {
    case LogLevel::Trace: return "trace";
    case LogLevel::Debug: return "debug";
    case LogLevel::Info: return "info";
    case LogLevel::Warn: return "warn";
    case LogLevel::Error: return "error";
    case LogLevel::Off: return "off";
  }
  return "unknown";
}

std::optional<LogLevel> parse_log_level(std::string_view text) {
  std::string l(text);
  for (char& c : l) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  if (l == "warning") return LogLevel::Warn;
  for (auto lv : {LogLevel::Trace, LogLevel::Debug, LogLevel::Info, LogLevel::Warn, LogLevel::Error,
                  LogLevel::Off}) {
    if (l == to_string(lv)) return lv;
  }
  return std::nullopt;
}

std::string format_log_record(const LogRecord& r) {
  static constexpr char kLetters[] = {'T', 'D', 'I', 'W', 'E', 'O'};
  const auto since_epoch = r.time.time_since_epoch();
  const auto secs = std::chrono::floor<std::chrono::seconds>(since_epoch);
  const auto millis = std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch - secs);
  const std::time_t t = static_cast<std::time_t>(secs.count());
  std::tm utc{};
  gmtime_r(&t, &utc);
  return fmt::format("{:%Y-%m-%d %H:%M:%S}.{:03} [{}] {}: {}", utc, millis.count(),
                     kLetters[static_cast<int>(r.level)], r.logger, r.message);
}

LogSink ostream_sink(std::ostream& os) {
  return [&os](const LogRecord& r) {
    os << format_log_record(r) << '\n';
    os.flush();
  };
}

LogSink stderr_sink() { return ostream_sink(std::cerr); }

Logger::Logger(std::string name, LogLevel min_level, LogSink sink)
    : name_(std::move(name)), level_(min_level), sink_(sink ? std::move(sink) : stderr_sink()) {}

void Logger::set_sink(LogSink sink) {
  std::lock_guard lock(mutex_);
  sink_ = sink ? std::move(sink) : stderr_sink();
}

void Logger::log(LogLevel level, std::string_view message, const char* file, int line) const {
  if (!enabled(level)) return;
  const LogRecord record{level, name_, message, std::chrono::system_clock::now(), file, line};
  std::lock_guard lock(mutex_);
  sink_(record);
}

Logger& default_logger() {
  static Logger logger("rove");
  return logger;
}

}  // namespace rove
