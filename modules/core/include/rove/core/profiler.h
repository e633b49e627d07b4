#pragma once
/// \file
/// Profiler: per-block call counts and min/mean/max/total times, the
/// counterpart of MRPT's CTimeLogger. Blocks are timed with ScopedTimer
/// (rove/core/timer.h) or reported with add():
///
///   rove::Profiler prof;
///   { rove::ScopedTimer t(prof, "icp.align"); align(...); }
///   std::cout << prof.report();

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/core/timer.h"

namespace rove {

/// Statistics of one profiled block; times in seconds.
struct ProfileStats {
  std::uint64_t calls = 0;
  double total = 0.0;
  double min = 0.0;
  double max = 0.0;
  /// total / calls (0 if no calls).
  double mean() const noexcept { return calls == 0 ? 0.0 : total / static_cast<double>(calls); }
};

/// A named block and its statistics.
struct ProfileEntry {
  std::string name;
  ProfileStats stats;
};

/// Accumulates timings per block name. Thread-safe. When disabled, add()
/// and ScopedTimer do nothing beyond one atomic load.
class Profiler {
 public:
  /// An empty profiler, enabled or not.
  explicit Profiler(bool enabled = true) noexcept : enabled_(enabled) {}
  Profiler(const Profiler&) = delete;
  Profiler& operator=(const Profiler&) = delete;

  /// Whether timings are recorded.
  bool enabled() const noexcept { return enabled_.load(std::memory_order_relaxed); }
  /// Turns recording on or off; collected statistics are kept.
  void set_enabled(bool on) noexcept { enabled_.store(on, std::memory_order_relaxed); }

  /// Records one call of `name` that took `seconds`. Precondition
  /// (InvalidArgument): seconds is finite and >= 0. No-op when disabled.
  void add(std::string_view name, double seconds);

  /// Statistics of one block, if it was recorded.
  std::optional<ProfileStats> stats(std::string_view name) const;
  /// All blocks, by decreasing total time (ties by name).
  std::vector<ProfileEntry> entries() const;
  /// A table of entries(): name, calls, min, mean, max, total, with times
  /// printed in s/ms/us/ns as fits; ends with a newline.
  std::string report() const;
  /// Forgets all statistics.
  void clear();

 private:
  std::atomic<bool> enabled_;
  mutable std::mutex mutex_;
  std::map<std::string, ProfileStats, std::less<>> blocks_;
};

/// A duration in seconds as text with 3 decimals in the largest unit of
/// s, ms, us, ns that keeps it >= 1 (e.g. 0.0123 -> "12.300 ms").
std::string format_duration(double seconds);

}  // namespace rove
