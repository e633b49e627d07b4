#pragma once
/// \file
/// Timestamp: a point in time as signed 64-bit nanoseconds since the Unix
/// epoch (1970-01-01T00:00:00 UTC), with conversions to and from MRPT's
/// TTimeStamp (unsigned 100-ns ticks since 1601-01-01T00:00:00 UTC, the
/// Windows FILETIME epoch).
///
/// Nanoseconds cover 1677-09-21 .. 2262-04-11, enough for any sensor log,
/// and keep the full resolution of ROS and of hardware clocks. MRPT's ticks
/// map exactly (one tick is 100 ns); MRPT's "no timestamp" value 0 maps to
/// Timestamp::invalid().

#include <compare>
#include <cstdint>
#include <limits>

namespace rove {

/// A time point, nanoseconds since the Unix epoch (UTC, leap seconds not
/// counted, as POSIX time). A plain value; thread-compatible.
struct Timestamp {
  /// 100-ns ticks between MRPT's epoch 1601-01-01 and the Unix epoch
  /// (11644473600 s; in nanoseconds it would not fit in 64 bits).
  static constexpr std::uint64_t kMrptEpochOffsetTicks = 116444736000000000ULL;
  /// The value that stands for "no time known" (MRPT's INVALID_TIMESTAMP).
  static constexpr std::int64_t kInvalidNs = std::numeric_limits<std::int64_t>::min();

  /// Nanoseconds since 1970-01-01T00:00:00 UTC; kInvalidNs if unknown.
  std::int64_t ns = kInvalidNs;

  /// The "unknown time" timestamp (also the default).
  static constexpr Timestamp invalid() noexcept { return Timestamp{}; }
  /// From nanoseconds since the Unix epoch. kInvalidNs gives invalid().
  static constexpr Timestamp from_ns(std::int64_t ns_since_epoch) noexcept {
    return Timestamp{ns_since_epoch};
  }
  /// From seconds since the Unix epoch, rounded to the nearest nanosecond.
  /// Throws InvalidArgument if `seconds` is not finite or outside the range
  /// a Timestamp holds (about ±292 years around 1970).
  static Timestamp from_seconds(double seconds);
  /// From MRPT's TTimeStamp: 100-ns ticks since 1601-01-01 UTC. Tick 0
  /// (MRPT's INVALID_TIMESTAMP) gives invalid(). Throws InvalidArgument if
  /// the time lies outside 1677..2262 (not representable here).
  static Timestamp from_mrpt(std::uint64_t ticks);

  /// True unless this is invalid().
  constexpr bool valid() const noexcept { return ns != kInvalidNs; }
  /// Seconds since the Unix epoch (double: ~0.2 µs resolution today).
  /// Throws InvalidArgument if invalid().
  double to_seconds() const;
  /// MRPT's TTimeStamp for this time: 100-ns ticks since 1601-01-01,
  /// rounded down (floor) to a whole tick; invalid() gives 0.
  std::uint64_t to_mrpt() const noexcept;

  /// Ordering by time; invalid() sorts before every valid time.
  constexpr auto operator<=>(const Timestamp&) const noexcept = default;
};

/// b - a in seconds. Throws InvalidArgument if either is invalid().
double seconds_between(Timestamp a, Timestamp b);

}  // namespace rove
