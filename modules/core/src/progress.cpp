#include "rove/core/progress.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "rove/core/check.h"

namespace rove {
namespace {

bool stream_is_terminal(const std::ostream& os) {
  if (&os == &std::cerr || &os == &std::clog) return ::isatty(STDERR_FILENO) == 1;
  if (&os == &std::cout) return ::isatty(STDOUT_FILENO) == 1;
  return false;
}

}  // namespace

std::string format_elapsed(double seconds) {
  if (!std::isfinite(seconds)) return "?";
  if (seconds < 60.0) return fmt::format("{:.1f} s", seconds);
  const auto total = static_cast<std::uint64_t>(seconds);
  return fmt::format("{}:{:02}:{:02}", total / 3600, (total / 60) % 60, total % 60);
}

Progress::Progress(std::optional<std::uint64_t> total, std::string label, std::ostream& os,
                   ProgressMode mode)
    : Progress(total, std::move(label), os, [mode] {
        ProgressOptions o;
        o.mode = mode;
        return o;
      }()) {}

Progress::Progress(std::optional<std::uint64_t> total, std::string label, std::ostream& os,
                   ProgressOptions options)
    : total_(total), label_(std::move(label)), os_(os), options_(std::move(options)) {
  ROVE_CHECK_MSG(options_.line_percent_step > 0.0 && options_.line_percent_step <= 100.0,
                 "line_percent_step = {}", options_.line_percent_step);
  ROVE_CHECK_MSG(options_.line_interval_seconds >= 0.0 && std::isfinite(options_.line_interval_seconds),
                 "line_interval_seconds = {}", options_.line_interval_seconds);
  ROVE_CHECK_MSG(options_.bar_interval_seconds >= 0.0 && std::isfinite(options_.bar_interval_seconds),
                 "bar_interval_seconds = {}", options_.bar_interval_seconds);
  ROVE_CHECK_GE(options_.bar_width, 1);
  if (options_.mode == ProgressMode::Auto)
    options_.mode = stream_is_terminal(os_) ? ProgressMode::Bar : ProgressMode::Lines;
  start_ = now();
  last_output_ = start_;
  next_percent_ = options_.line_percent_step;
}

Progress::~Progress() {
  try {
    finish();
  } catch (...) {
    // a destructor must not throw; the stream failing is not worth a crash
  }
}

double Progress::now() const {
  if (options_.clock) return options_.clock();
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void Progress::advance(std::uint64_t n) {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  ROVE_CHECK_LE(n, UINT64_MAX - done_);
  update(done_ + n);
}

void Progress::set(std::uint64_t done) {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  update(done);
}

std::uint64_t Progress::done() const {
  std::lock_guard lock(mutex_);
  return done_;
}

void Progress::update(std::uint64_t done) {
  if (total_) ROVE_CHECK_LE(done, *total_);
  done_ = done;
  const double t = now();
  if (options_.mode == ProgressMode::Bar) {
    if (!drawn_ || t - last_output_ >= options_.bar_interval_seconds) draw_bar(t, false);
    return;
  }
  bool due = false;
  if (total_ && *total_ > 0) {
    const double pct = 100.0 * static_cast<double>(done_) / static_cast<double>(*total_);
    if (pct >= next_percent_ && pct < 100.0) {
      due = true;
      next_percent_ = (std::floor(pct / options_.line_percent_step) + 1.0) * options_.line_percent_step;
    }
  }
  if (options_.line_interval_seconds > 0.0 && t - last_output_ >= options_.line_interval_seconds &&
      done_ != done_at_last_line_)
    due = true;
  if (due) emit_line(t);
}

std::string Progress::stats_text(double t) const {
  const double elapsed = t - start_;
  const double rate = elapsed > 0.0 ? static_cast<double>(done_) / elapsed : 0.0;
  const std::string rate_text =
      elapsed > 0.0 ? fmt::format("{:.1f} {}/s", rate, options_.unit) : fmt::format("- {}/s", options_.unit);
  if (!total_) return fmt::format("{} {}, {}, elapsed {}", done_, options_.unit, rate_text, format_elapsed(elapsed));
  const std::uint64_t total = *total_;
  const int pct = total == 0 ? 100 : static_cast<int>(100 * static_cast<double>(done_) / static_cast<double>(total));
  const std::string eta =
      rate > 0.0 ? format_elapsed(static_cast<double>(total - done_) / rate) : std::string("?");
  return fmt::format("{:3}% ({}/{}), {}, elapsed {}, ETA {}", pct, done_, total, rate_text,
                     format_elapsed(elapsed), eta);
}

void Progress::emit_line(double t) {
  os_ << label_ << ": " << stats_text(t) << '\n';
  os_.flush();
  last_output_ = t;
  done_at_last_line_ = done_;
}

void Progress::draw_bar(double t, bool final) {
  std::string line = label_;
  line += ' ';
  if (total_) {
    const std::uint64_t total = *total_;
    const double frac = total == 0 ? 1.0 : static_cast<double>(done_) / static_cast<double>(total);
    const auto width = static_cast<std::size_t>(options_.bar_width);
    const auto filled = std::min(width, static_cast<std::size_t>(frac * static_cast<double>(width)));
    line += '[';
    line.append(filled, '#');
    line.append(width - filled, '.');
    line += "] ";
  }
  line += stats_text(t);
  const std::size_t length = line.size();
  if (length < last_bar_length_) line.append(last_bar_length_ - length, ' ');
  os_ << '\r' << line;
  if (final) os_ << '\n';
  os_.flush();
  last_bar_length_ = length;
  last_output_ = t;
  drawn_ = true;
}

void Progress::finish() {
  std::lock_guard lock(mutex_);
  if (finished_) return;
  finished_ = true;
  const double t = now();
  if (options_.mode == ProgressMode::Bar) {
    draw_bar(t, true);
    return;
  }
  const double elapsed = t - start_;
  const std::string rate =
      elapsed > 0.0 ? fmt::format("{:.1f} {}/s", static_cast<double>(done_) / elapsed, options_.unit)
                    : fmt::format("- {}/s", options_.unit);
  if (total_) {
    os_ << fmt::format("{}: done, {}/{} {} in {} ({})\n", label_, done_, *total_, options_.unit,
                       format_elapsed(elapsed), rate);
  } else {
    os_ << fmt::format("{}: done, {} {} in {} ({})\n", label_, done_, options_.unit,
                       format_elapsed(elapsed), rate);
  }
  os_.flush();
}

}  // namespace rove
