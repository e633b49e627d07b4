#include "rove/obs/timestamp.h"

#include <cmath>
#include <cstdint>
#include <limits>

#include "rove/core/check.h"

namespace rove {
namespace {

constexpr std::int64_t kNsPerSecond = 1000000000;
constexpr std::int64_t kNsPerTick = 100;
constexpr std::uint64_t kMaxTicksMagnitude =
    static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max() / kNsPerTick);

// Seconds from a nanosecond count, splitting off whole seconds first so the
// integer part is exact before the conversion to double.
double ns_to_seconds(std::int64_t ns) {
  const std::int64_t whole = ns / kNsPerSecond;
  const std::int64_t rest = ns % kNsPerSecond;
  return static_cast<double>(whole) + static_cast<double>(rest) * 1e-9;
}

}  // namespace

Timestamp Timestamp::from_seconds(double seconds) {
  ROVE_CHECK_FINITE(seconds);
  // ±9.2e9 s is the int64 nanosecond range; stay a little inside it.
  ROVE_CHECK_MSG(std::abs(seconds) < 9.2e9,
                 "{} s since 1970 is outside the range of a Timestamp (about ±292 years)",
                 seconds);
  const double whole = std::floor(seconds);
  const double frac = seconds - whole;  // [0, 1)
  const auto ns = static_cast<std::int64_t>(whole) * kNsPerSecond +
                  static_cast<std::int64_t>(std::llround(frac * 1e9));
  ROVE_CHECK_NE(ns, kInvalidNs);
  return Timestamp{ns};
}

Timestamp Timestamp::from_mrpt(std::uint64_t ticks) {
  if (ticks == 0) return invalid();
  if (ticks >= kMrptEpochOffsetTicks) {
    const std::uint64_t d = ticks - kMrptEpochOffsetTicks;
    ROVE_CHECK_MSG(d <= kMaxTicksMagnitude,
                   "MRPT timestamp {} ticks is after 2262 and cannot be represented", ticks);
    return Timestamp{static_cast<std::int64_t>(d) * kNsPerTick};
  }
  const std::uint64_t d = kMrptEpochOffsetTicks - ticks;
  ROVE_CHECK_MSG(d <= kMaxTicksMagnitude,
                 "MRPT timestamp {} ticks is before 1677 and cannot be represented", ticks);
  return Timestamp{-static_cast<std::int64_t>(d) * kNsPerTick};
}

double Timestamp::to_seconds() const {
  ROVE_CHECK_MSG(valid(), "to_seconds() of an invalid timestamp");
  return ns_to_seconds(ns);
}

std::uint64_t Timestamp::to_mrpt() const noexcept {
  if (!valid()) return 0;
  std::int64_t q = ns / kNsPerTick;
  if (ns % kNsPerTick < 0) --q;  // floor toward -inf
  // |q| <= 9.3e16 < offset (1.16e17): the sum is positive.
  return static_cast<std::uint64_t>(static_cast<std::int64_t>(kMrptEpochOffsetTicks) + q);
}

double seconds_between(Timestamp a, Timestamp b) {
  ROVE_CHECK_MSG(a.valid() && b.valid(), "seconds_between needs two valid timestamps");
  std::int64_t d = 0;
  if (__builtin_sub_overflow(b.ns, a.ns, &d)) {
    // Only for spans beyond ±292 years; double precision is all that is left.
    return (static_cast<double>(b.ns) - static_cast<double>(a.ns)) * 1e-9;
  }
  return ns_to_seconds(d);
}

}  // namespace rove
