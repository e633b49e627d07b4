#pragma once
/// \file
/// Pose2: a pose in the plane (x, y, phi), MRPT's CPose2D, with its
/// composition operators against 2D and 3D points.

#include <cmath>
#include <iosfwd>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "rove/poses/angle.h"
#include "rove/poses/point2.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose_io.h"
#include "rove/poses/position.h"

namespace rove {

class Pose3;
class Pose3Quat;

namespace detail {
/// Tag for the internal constructors that skip validation; used by the
/// composition operators on already valid operands.
struct Unchecked {
  explicit Unchecked() = default;
};
inline constexpr Unchecked kUnchecked{};
}  // namespace detail

/// A 2D pose: position (x, y) in meters and heading phi in radians, wrapped to
/// (-pi, pi]. `A + B` is B (given in A's frame) brought into A's parent frame;
/// `A - B` is A seen from B (B^-1 + A). Thread-safety: a value type.
class Pose2 {
 public:
  /// The identity pose (0, 0, 0).
  constexpr Pose2() noexcept = default;
  /// From x, y in meters and phi in radians (any finite value; wrapped to
  /// (-pi, pi]). Throws InvalidArgument if any is NaN/Inf.
  Pose2(double x, double y, double phi);
  /// A pose at `p` with phi = 0 (MRPT's CPose2D(CPoint2D)).
  explicit Pose2(const Point2& p) noexcept : x_(p.x), y_(p.y) {}
  /// The planar part of a 3D pose: x, y and yaw (drops z, pitch, roll).
  /// Defined in pose3.h.
  explicit Pose2(const Pose3& p);
  /// The planar part of a quaternion pose: x, y and yaw. Defined in
  /// pose3_quat.h.
  explicit Pose2(const Pose3Quat& p);
  /// Internal: no validation, phi must already be in (-pi, pi].
  constexpr Pose2(detail::Unchecked, double x, double y, double phi) noexcept
      : x_(x), y_(y), phi_(phi) {}

  /// The identity pose.
  static constexpr Pose2 identity() noexcept { return Pose2(); }

  /// x in meters.
  double x() const noexcept { return x_; }
  /// y in meters.
  double y() const noexcept { return y_; }
  /// Heading in radians, in (-pi, pi].
  double phi() const noexcept { return phi_; }
  /// The position as a point.
  Point2 position() const noexcept { return detail_point(x_, y_); }
  /// The position as an Eigen vector (x, y).
  Eigen::Vector2d translation() const noexcept { return {x_, y_}; }
  /// The 2x2 rotation matrix of phi.
  Eigen::Matrix2d rotation() const noexcept;
  /// The 3x3 homogeneous matrix [R t; 0 0 1].
  Eigen::Matrix3d matrix() const noexcept;
  /// The vector (x, y, phi).
  Eigen::Vector3d to_vector() const noexcept { return {x_, y_, phi_}; }

  /// The inverse pose: (-p) + p = identity.
  Pose2 inverse() const noexcept;
  /// this = this + b.
  Pose2& operator+=(const Pose2& b) noexcept;
  /// this = this - b.
  Pose2& operator-=(const Pose2& b) noexcept;

  /// Norm of the position sqrt(x^2 + y^2), meters (MRPT's norm()).
  double norm() const noexcept { return std::hypot(x_, y_); }
  /// Euclidean distance between positions (any point or pose, 2D at z = 0).
  template <HasPosition Other>
  double distance_to(const Other& other) const {
    return distance(*this, other);
  }
  /// Squared Euclidean distance between positions.
  template <HasPosition Other>
  double squared_distance_to(const Other& other) const {
    return squared_distance(*this, other);
  }

  /// MRPT's string form "[x y phi_deg]", written as "[%f %f %fdeg]" as
  /// MRPT's CPose2D::asString does (the "deg" suffix is accepted back).
  std::string as_string() const;
  /// Parses "[x y phi_deg]" (phi in degrees). Throws ParseError naming the
  /// field on malformed text.
  static Pose2 from_string(std::string_view text);

 private:
  static Point2 detail_point(double x, double y) noexcept {
    Point2 p;
    p.x = x;
    p.y = y;
    return p;
  }
  double x_ = 0.0;
  double y_ = 0.0;
  double phi_ = 0.0;
};

/// Position as a 3D vector (x, y, 0).
inline Eigen::Vector3d position_3d(const Pose2& p) noexcept { return {p.x(), p.y(), 0.0}; }

inline Eigen::Matrix2d Pose2::rotation() const noexcept {
  const double c = std::cos(phi_), s = std::sin(phi_);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  return R;
}

inline Eigen::Matrix3d Pose2::matrix() const noexcept {
  const double c = std::cos(phi_), s = std::sin(phi_);
  Eigen::Matrix3d T;
  T << c, -s, x_, s, c, y_, 0.0, 0.0, 1.0;
  return T;
}

/// Composition a (+) b: b, given in a's frame, brought into a's parent frame.
inline Pose2 operator+(const Pose2& a, const Pose2& b) noexcept {
  const double c = std::cos(a.phi()), s = std::sin(a.phi());
  return Pose2(detail::kUnchecked, a.x() + b.x() * c - b.y() * s, a.y() + b.x() * s + b.y() * c,
               wrap_to_pi(a.phi() + b.phi()));
}

/// Inverse composition a (-) b = b^-1 (+) a: pose a as seen from pose b.
inline Pose2 operator-(const Pose2& a, const Pose2& b) noexcept {
  const double c = std::cos(b.phi()), s = std::sin(b.phi());
  const double dx = a.x() - b.x(), dy = a.y() - b.y();
  return Pose2(detail::kUnchecked, dx * c + dy * s, -dx * s + dy * c,
               wrap_to_pi(a.phi() - b.phi()));
}

/// The inverse pose, -p = p^-1.
inline Pose2 operator-(const Pose2& p) noexcept {
  const double c = std::cos(p.phi()), s = std::sin(p.phi());
  return Pose2(detail::kUnchecked, -p.x() * c - p.y() * s, p.x() * s - p.y() * c,
               wrap_to_pi(-p.phi()));
}

inline Pose2 Pose2::inverse() const noexcept { return -*this; }
inline Pose2& Pose2::operator+=(const Pose2& b) noexcept { return *this = *this + b; }
inline Pose2& Pose2::operator-=(const Pose2& b) noexcept { return *this = *this - b; }

/// A point given in pose a's frame, brought into a's parent frame.
inline Point2 operator+(const Pose2& a, const Point2& p) noexcept {
  const double c = std::cos(a.phi()), s = std::sin(a.phi());
  Point2 r;
  r.x = a.x() + p.x * c - p.y * s;
  r.y = a.y() + p.x * s + p.y * c;
  return r;
}

/// A 3D point given in pose a's frame, brought into a's parent frame; z is
/// unchanged (MRPT's CPose2D + CPoint3D).
inline Point3 operator+(const Pose2& a, const Point3& p) noexcept {
  const double c = std::cos(a.phi()), s = std::sin(a.phi());
  return detail::make_point3(a.x() + p.x * c - p.y * s, a.y() + p.x * s + p.y * c, p.z);
}

/// Point p (in the parent frame) as seen from pose b: b^-1 (+) p.
inline Point2 operator-(const Point2& p, const Pose2& b) noexcept {
  const double c = std::cos(b.phi()), s = std::sin(b.phi());
  const double dx = p.x - b.x(), dy = p.y - b.y();
  Point2 r;
  r.x = dx * c + dy * s;
  r.y = -dx * s + dy * c;
  return r;
}

/// 3D point p as seen from the 2D pose b (z unchanged).
inline Point3 operator-(const Point3& p, const Pose2& b) noexcept {
  const double c = std::cos(b.phi()), s = std::sin(b.phi());
  const double dx = p.x - b.x(), dy = p.y - b.y();
  return detail::make_point3(dx * c + dy * s, -dx * s + dy * c, p.z);
}

/// Exact equality of x, y and phi (as MRPT's CPose2D ==).
inline bool operator==(const Pose2& a, const Pose2& b) noexcept {
  return a.x() == b.x() && a.y() == b.y() && a.phi() == b.phi();
}

/// MRPT's operator<< text, printf "(%.3f,%.3f,%.2fdeg)", e.g.
/// "(2.000,1.000,45.00deg)"; independent of the stream's format flags.
std::ostream& operator<<(std::ostream& os, const Pose2& p);
/// The text of operator<<.
std::string to_string(const Pose2& p);

}  // namespace rove

/// fmt prints a Pose2 as its operator<< does.
template <>
struct fmt::formatter<rove::Pose2> : rove::detail::ToStringFormatter<rove::Pose2> {};
