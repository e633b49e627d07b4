#include "rove/core/profiler.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "rove/core/check.h"

namespace rove {

ScopedTimer::ScopedTimer(Profiler& profiler, std::string_view name)
    : profiler_(&profiler), name_(name), active_(profiler.enabled()) {
  if (active_) start_ = Stopwatch::Clock::now();
}

ScopedTimer::ScopedTimer(double& out_seconds) noexcept
    : out_(&out_seconds), active_(true), start_(Stopwatch::Clock::now()) {}

double ScopedTimer::elapsed() const noexcept {
  if (!active_) return 0.0;
  return std::chrono::duration<double>(Stopwatch::Clock::now() - start_).count();
}

ScopedTimer::~ScopedTimer() {
  if (!active_) return;
  const double s = elapsed();
  if (out_ != nullptr) {
    *out_ = s;
  } else {
    profiler_->add(name_, s);
  }
}

void Profiler::add(std::string_view name, double seconds) {
  if (!enabled()) return;
  ROVE_CHECK_FINITE(seconds);
  ROVE_CHECK_GE(seconds, 0.0);
  std::lock_guard lock(mutex_);
  auto it = blocks_.find(name);
  if (it == blocks_.end()) it = blocks_.emplace(std::string(name), ProfileStats{}).first;
  ProfileStats& s = it->second;
  if (s.calls == 0) {
    s.min = s.max = seconds;
  } else {
    s.min = std::min(s.min, seconds);
    s.max = std::max(s.max, seconds);
  }
  ++s.calls;
  s.total += seconds;
}

std::optional<ProfileStats> Profiler::stats(std::string_view name) const {
  std::lock_guard lock(mutex_);
  const auto it = blocks_.find(name);
  if (it == blocks_.end()) return std::nullopt;
  return it->second;
}

std::vector<ProfileEntry> Profiler::entries() const {
  std::vector<ProfileEntry> out;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [name, s] : blocks_) out.push_back({name, s});
  }
  std::stable_sort(out.begin(), out.end(), [](const ProfileEntry& a, const ProfileEntry& b) {
    return a.stats.total > b.stats.total;
  });
  return out;
}

void Profiler::clear() {
  std::lock_guard lock(mutex_);
  blocks_.clear();
}

std::string format_duration(double seconds) {
  const double a = std::fabs(seconds);
  if (a >= 1.0 || a == 0.0 || !std::isfinite(a)) return fmt::format("{:.3f} s", seconds);
  if (a >= 1e-3) return fmt::format("{:.3f} ms", seconds * 1e3);
  if (a >= 1e-6) return fmt::format("{:.3f} us", seconds * 1e6);
  return fmt::format("{:.3f} ns", seconds * 1e9);
}

std::string Profiler::report() const {
  const auto rows = entries();
  std::size_t width = 5;
  for (const auto& r : rows) width = std::max(width, r.name.size());
  std::string out = fmt::format("{:<{}}  {:>8}  {:>12}  {:>12}  {:>12}  {:>12}\n", "block", width,
                                "calls", "min", "mean", "max", "total");
  for (const auto& r : rows) {
    out += fmt::format("{:<{}}  {:>8}  {:>12}  {:>12}  {:>12}  {:>12}\n", r.name, width, r.stats.calls,
                       format_duration(r.stats.min), format_duration(r.stats.mean()),
                       format_duration(r.stats.max), format_duration(r.stats.total));
  }
  return out;
}

}  // namespace rove
