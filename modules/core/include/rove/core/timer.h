#pragma once
/// \file
/// Wall-clock timing on the monotonic clock: Stopwatch, and ScopedTimer,
/// which measures its own lifetime and hands the result to a Profiler
/// (rove/core/profiler.h) or to a double.

#include <chrono>
#include <string_view>

namespace rove {

class Profiler;

/// Measures elapsed time on std::chrono::steady_clock (never jumps back).
/// Starts running on construction. Not synchronized: one thread at a time.
class Stopwatch {
 public:
  using Clock = std::chrono::steady_clock;

  Stopwatch() noexcept : start_(Clock::now()) {}
  /// Restarts from zero.
  void reset() noexcept { start_ = Clock::now(); }
  /// Seconds since construction or the last reset()/lap().
  double elapsed() const noexcept {
    return std::chrono::duration<double>(Clock::now() - start_).count();
  }
  /// Returns elapsed() and restarts, in one clock reading.
  double lap() noexcept {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return s;
  }

 private:
  Clock::time_point start_;
};

/// Measures the time from its construction to its destruction, then either
/// adds it to a Profiler under a block name or assigns it (seconds) to a
/// double. Constructed on a disabled Profiler it does not read the clock.
class ScopedTimer {
 public:
  /// Times into `profiler` under `name`. `name` must outlive the timer (a
  /// string literal, typically); `profiler` too.
  ScopedTimer(Profiler& profiler, std::string_view name);
  /// Assigns the elapsed seconds to `out_seconds` on destruction.
  explicit ScopedTimer(double& out_seconds) noexcept;
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;
  ~ScopedTimer();

  /// Seconds since construction (0 if the profiler was disabled).
  double elapsed() const noexcept;

 private:
  Profiler* profiler_ = nullptr;
  std::string_view name_;
  double* out_ = nullptr;
  bool active_ = false;
  Stopwatch::Clock::time_point start_{};
};

}  // namespace rove
