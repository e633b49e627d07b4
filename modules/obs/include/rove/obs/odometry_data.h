#pragma once
/// \file
/// Extra odometry data some robots report with a pose: wheel encoder ticks
/// and the robot's planar velocity (MRPT's encoder and TTwist2D fields).

#include <cstdint>

#include "rove/serialization/archive.h"

namespace rove {

/// Wheel encoder counts since the previous reading.
struct EncoderTicks {
  /// Left wheel ticks (positive: forward).
  std::int32_t left = 0;
  /// Right wheel ticks (positive: forward).
  std::int32_t right = 0;
  /// Exact equality.
  friend bool operator==(const EncoderTicks&, const EncoderTicks&) = default;
};

/// A planar velocity in the robot frame (x forward, y left).
struct Twist2 {
  /// Forward velocity, m/s.
  double vx = 0.0;
  /// Lateral velocity, m/s.
  double vy = 0.0;
  /// Angular velocity about z, rad/s (counter-clockwise positive).
  double omega = 0.0;
  /// Exact equality.
  friend bool operator==(const Twist2&, const Twist2&) = default;
};

/// Writes EncoderTicks (versioned record).
void save(OutArchive& ar, const EncoderTicks& t);
/// Reads EncoderTicks written by save.
void load(InArchive& ar, EncoderTicks& t);
/// Writes a Twist2 (versioned record).
void save(OutArchive& ar, const Twist2& t);
/// Reads a Twist2 written by save.
void load(InArchive& ar, Twist2& t);

}  // namespace rove
