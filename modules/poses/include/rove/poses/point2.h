#pragma once
/// \file
/// Point2: a point (or displacement) in the plane, in meters (MRPT's CPoint2D).

#include <cmath>
#include <iosfwd>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "rove/poses/pose_io.h"
#include "rove/poses/position.h"

namespace rove {

struct Point3;

/// A 2D point {x, y} in meters, in whatever frame the caller keeps it.
/// A plain value: the fields are public. `p + q`, `p - q` and `s * p` are
/// component-wise vector arithmetic; composing with a pose is done by the pose
/// operators (`pose + p`, `p - pose`). Thread-safety: a value type.
struct Point2 {
  double x = 0.0;  ///< meters
  double y = 0.0;  ///< meters

  /// The origin.
  constexpr Point2() noexcept = default;
  /// From coordinates in meters. Throws InvalidArgument if either is NaN/Inf.
  Point2(double x_m, double y_m);
  /// From an Eigen vector (x, y). Throws InvalidArgument on NaN/Inf.
  explicit Point2(const Eigen::Vector2d& v) : Point2(v.x(), v.y()) {}
  /// Drops z (explicit: loses information). Defined in point3.h.
  explicit Point2(const Point3& p);

  /// The coordinates as an Eigen vector (x, y).
  Eigen::Vector2d to_vector() const noexcept { return {x, y}; }
  /// Euclidean norm sqrt(x^2 + y^2), meters.
  double norm() const noexcept { return std::hypot(x, y); }
  /// x^2 + y^2, m^2.
  double squared_norm() const noexcept { return x * x + y * y; }

  /// Euclidean distance to the position of any point or pose (z = 0 here).
  template <HasPosition Other>
  double distance_to(const Other& other) const {
    return distance(*this, other);
  }
  /// Squared Euclidean distance to the position of any point or pose.
  template <HasPosition Other>
  double squared_distance_to(const Other& other) const {
    return squared_distance(*this, other);
  }

  /// Component-wise sums and differences, scaling.
  Point2& operator+=(const Point2& o) noexcept { x += o.x; y += o.y; return *this; }
  Point2& operator-=(const Point2& o) noexcept { x -= o.x; y -= o.y; return *this; }
  Point2& operator*=(double s) noexcept { x *= s; y *= s; return *this; }

  /// MRPT's string form "[x y]" (printf "%f").
  std::string as_string() const;
  /// Parses "[x y]"; throws ParseError naming the field on malformed text.
  static Point2 from_string(std::string_view text);
};

/// Position as a 3D vector (x, y, 0).
inline Eigen::Vector3d position_3d(const Point2& p) noexcept { return {p.x, p.y, 0.0}; }

/// Component-wise sum.
inline Point2 operator+(const Point2& a, const Point2& b) noexcept {
  Point2 r;
  r.x = a.x + b.x;
  r.y = a.y + b.y;
  return r;
}
/// Component-wise difference (a vector from b to a).
inline Point2 operator-(const Point2& a, const Point2& b) noexcept {
  Point2 r;
  r.x = a.x - b.x;
  r.y = a.y - b.y;
  return r;
}
/// Negation; also the inverse of a point seen as a pure translation.
inline Point2 operator-(const Point2& a) noexcept {
  Point2 r;
  r.x = -a.x;
  r.y = -a.y;
  return r;
}
/// Scaling by a dimensionless factor.
inline Point2 operator*(const Point2& a, double s) noexcept {
  Point2 r;
  r.x = a.x * s;
  r.y = a.y * s;
  return r;
}
/// Scaling by a dimensionless factor.
inline Point2 operator*(double s, const Point2& a) noexcept { return a * s; }
/// Exact component-wise equality.
inline bool operator==(const Point2& a, const Point2& b) noexcept {
  return a.x == b.x && a.y == b.y;
}

/// MRPT's operator<< text "(x,y)", each value printed with the stream's
/// current format (default: 6 significant digits).
std::ostream& operator<<(std::ostream& os, const Point2& p);
/// The text of operator<< with default stream formatting, e.g. "(1,2.5)".
std::string to_string(const Point2& p);

}  // namespace rove

/// fmt prints a Point2 as its operator<< does with default formatting.
template <>
struct fmt::formatter<rove::Point2> : rove::detail::ToStringFormatter<rove::Point2> {};
