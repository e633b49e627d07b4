#pragma once
/// \file
/// Point3: a point (or displacement) in space, in meters (MRPT's CPoint3D).

#include <cmath>
#include <iosfwd>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "rove/poses/point2.h"
#include "rove/poses/pose_io.h"
#include "rove/poses/position.h"

namespace rove {

/// A 3D point {x, y, z} in meters. A plain value: the fields are public.
/// `p + q`, `p - q` and `s * p` are component-wise; composing with a pose is
/// done by the pose operators. A Point2 converts implicitly (z = 0).
/// Thread-safety: a value type.
struct Point3 {
  double x = 0.0;  ///< meters
  double y = 0.0;  ///< meters
  double z = 0.0;  ///< meters

  /// The origin.
  constexpr Point3() noexcept = default;
  /// From coordinates in meters. Throws InvalidArgument if any is NaN/Inf.
  Point3(double x_m, double y_m, double z_m);
  /// Lossless 2D to 3D conversion: (p.x, p.y, 0).
  Point3(const Point2& p) noexcept : x(p.x), y(p.y), z(0.0) {}  // NOLINT: implicit by design
  /// From an Eigen vector (x, y, z). Throws InvalidArgument on NaN/Inf.
  explicit Point3(const Eigen::Vector3d& v) : Point3(v.x(), v.y(), v.z()) {}

  /// The coordinates as an Eigen vector (x, y, z).
  Eigen::Vector3d to_vector() const noexcept { return {x, y, z}; }
  /// Euclidean norm, meters.
  double norm() const noexcept { return std::sqrt(squared_norm()); }
  /// x^2 + y^2 + z^2, m^2.
  double squared_norm() const noexcept { return x * x + y * y + z * z; }

  /// Euclidean distance to the position of any point or pose (2D ones at z = 0).
  template <HasPosition Other>
  double distance_to(const Other& other) const {
    return distance(*this, other);
  }
  /// Squared Euclidean distance to the position of any point or pose.
  template <HasPosition Other>
  double squared_distance_to(const Other& other) const {
    return squared_distance(*this, other);
  }

  /// Component-wise sums and differences (a Point2 adds with z = 0), scaling.
  Point3& operator+=(const Point3& o) noexcept { x += o.x; y += o.y; z += o.z; return *this; }
  Point3& operator-=(const Point3& o) noexcept { x -= o.x; y -= o.y; z -= o.z; return *this; }
  Point3& operator*=(double s) noexcept { x *= s; y *= s; z *= s; return *this; }

  /// MRPT's string form "[x y z]" (printf "%f").
  std::string as_string() const;
  /// Parses "[x y z]"; throws ParseError naming the field on malformed text.
  static Point3 from_string(std::string_view text);
};

inline Point2::Point2(const Point3& p) : x(p.x), y(p.y) {}

/// Position as a 3D vector.
inline Eigen::Vector3d position_3d(const Point3& p) noexcept { return {p.x, p.y, p.z}; }

namespace detail {
inline Point3 make_point3(double x, double y, double z) noexcept {
  Point3 r;
  r.x = x;
  r.y = y;
  r.z = z;
  return r;
}
}  // namespace detail

/// Component-wise sum.
inline Point3 operator+(const Point3& a, const Point3& b) noexcept {
  return detail::make_point3(a.x + b.x, a.y + b.y, a.z + b.z);
}
/// Component-wise sum, the 2D operand at z = 0.
inline Point3 operator+(const Point3& a, const Point2& b) noexcept {
  return detail::make_point3(a.x + b.x, a.y + b.y, a.z);
}
/// Component-wise sum, the 2D operand at z = 0.
inline Point3 operator+(const Point2& a, const Point3& b) noexcept {
  return detail::make_point3(a.x + b.x, a.y + b.y, b.z);
}
/// Component-wise difference.
inline Point3 operator-(const Point3& a, const Point3& b) noexcept {
  return detail::make_point3(a.x - b.x, a.y - b.y, a.z - b.z);
}
/// Component-wise difference, the 2D operand at z = 0.
inline Point3 operator-(const Point3& a, const Point2& b) noexcept {
  return detail::make_point3(a.x - b.x, a.y - b.y, a.z);
}
/// Component-wise difference, the 2D operand at z = 0.
inline Point3 operator-(const Point2& a, const Point3& b) noexcept {
  return detail::make_point3(a.x - b.x, a.y - b.y, -b.z);
}
/// Negation; also the inverse of a point seen as a pure translation.
inline Point3 operator-(const Point3& a) noexcept { return detail::make_point3(-a.x, -a.y, -a.z); }
/// Scaling by a dimensionless factor.
inline Point3 operator*(const Point3& a, double s) noexcept {
  return detail::make_point3(a.x * s, a.y * s, a.z * s);
}
/// Scaling by a dimensionless factor.
inline Point3 operator*(double s, const Point3& a) noexcept { return a * s; }
/// Exact component-wise equality.
inline bool operator==(const Point3& a, const Point3& b) noexcept {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

/// MRPT's operator<< text "(x,y,z)", each value printed with the stream's
/// current format (default: 6 significant digits).
std::ostream& operator<<(std::ostream& os, const Point3& p);
/// The text of operator<< with default stream formatting, e.g. "(0,4,2)".
std::string to_string(const Point3& p);

}  // namespace rove

/// fmt prints a Point3 as its operator<< does with default formatting.
template <>
struct fmt::formatter<rove::Point3> : rove::detail::ToStringFormatter<rove::Point3> {};
