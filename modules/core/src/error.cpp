#include "rove/core/error.h"

#include <fmt/format.h>

#include <utility>

namespace rove {

Error::Error(std::string message) : message_(std::move(message)) { rebuild_what(); }

Error::Error(std::string message, SourceFrame origin) : message_(std::move(message)) {
  trace_.push_back(std::move(origin));
  rebuild_what();
}

void Error::add_frame(SourceFrame frame) {
  trace_.push_back(std::move(frame));
  rebuild_what();
}

void Error::rebuild_what() {
  what_ = message_;
  for (const auto& f : trace_) {
    what_ += fmt::format("\n  at {} ({}:{})", f.function, f.file, f.line);
  }
}

IoError::IoError(std::string path, std::string what_failed)
    : Error(fmt::format("{}: {}", path, what_failed)), path_(std::move(path)) {}

namespace {
std::string format_location(const ParseError::Location& w, const std::string& problem) {
  std::string s = w.source.empty() ? std::string("<input>") : w.source;
  if (w.line) s += fmt::format(":{}", *w.line);
  if (w.offset) s += fmt::format(" (byte offset {})", *w.offset);
  if (!w.field.empty()) s += fmt::format(" [{}]", w.field);
  return s + ": " + problem;
}
}  // namespace

ParseError::ParseError(Location where, std::string problem)
    : Error(format_location(where, problem)), where_(std::move(where)), problem_(std::move(problem)) {}

ConfigError::ConfigError(std::string file, std::string section, std::string key,
                         std::string problem)
    : Error(fmt::format("{}: [{}] {}: {}", file.empty() ? "<config>" : file, section, key,
                        problem)),
      file_(std::move(file)),
      section_(std::move(section)),
      key_(std::move(key)) {}

namespace detail {
void rethrow_with_frame(SourceFrame frame) {
  try {
    throw;
  } catch (Error& e) {
    e.add_frame(std::move(frame));
    throw;
  } catch (const std::exception& e) {
    throw Error(e.what(), std::move(frame));
  }
}
}  // namespace detail

}  // namespace rove
