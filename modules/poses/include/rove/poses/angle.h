#pragma once
/// \file
/// Angle helpers shared by the pose types: wrapping to (-pi, pi] and
/// degree/radian conversion with the same operation order as MRPT
/// (`x * pi / 180`, `x * 180 / pi`), so converted values match MRPT's bits.

#include <cmath>
#include <numbers>

namespace rove {

/// pi as a double.
inline constexpr double kPi = std::numbers::pi;

/// Degrees to radians, computed as `deg * pi / 180` (MRPT's DEG2RAD).
constexpr double deg_to_rad(double deg) noexcept { return deg * kPi / 180.0; }

/// Radians to degrees, computed as `rad * 180 / pi` (MRPT's RAD2DEG).
constexpr double rad_to_deg(double rad) noexcept { return rad * 180.0 / kPi; }

/// Wraps an angle in radians into (-pi, pi]. Angles already in that range are
/// returned unchanged (bit for bit); others are reduced with fmod as MRPT's
/// wrapToPi does, except that the result -pi is mapped to +pi so the range is
/// half-open on the negative side. A non-finite input gives NaN.
inline double wrap_to_pi(double angle) noexcept {
  if (angle > -kPi && angle <= kPi) [[likely]] {
    return angle;
  }
  constexpr double kTwoPi = 2.0 * kPi;
  double r = std::fmod(angle + kPi, kTwoPi);  // (-2pi, 2pi), NaN for non-finite input
  if (r < 0.0) r += kTwoPi;                   // [0, 2pi]
  r -= kPi;                                   // [-pi, pi]
  if (r <= -kPi) r = kPi;
  return r;
}

}  // namespace rove
