#pragma once
/// \file
/// Pose3Quat: a 6-DoF pose as translation + unit quaternion, MRPT's
/// CPose3DQuat, with composition against every point and pose type.

#include <iosfwd>
#include <string>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/poses/euler.h"
#include "rove/poses/point2.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"
#include "rove/poses/pose_io.h"
#include "rove/poses/position.h"

namespace rove {

/// A 3D pose T_parent_child as translation t (meters) and unit quaternion
/// q = (w, x, y, z) (Hamilton convention, p_parent = q p q* + t).
///
/// Sign of q, as MRPT: a quaternion given by components is normalized and,
/// if w < 0, negated (MRPT's CQuaternion convention w >= 0); composition
/// results are normalized the same way. The conversion from a Pose3 uses
/// MRPT's Euler-to-quaternion formula unchanged, which may leave w < 0, and
/// inverse() conjugates without changing the sign of w, both as in MRPT.
/// Thread-safety: a value type.
class Pose3Quat {
 public:
  /// The identity pose.
  Pose3Quat() noexcept : t_(Eigen::Vector3d::Zero()), q_(Eigen::Quaterniond::Identity()) {}
  /// From position (meters) and quaternion components. The quaternion is
  /// normalized (any non-zero norm accepted) and made w >= 0. Throws
  /// InvalidArgument on NaN/Inf or a zero quaternion.
  Pose3Quat(double x, double y, double z, double qw, double qx, double qy, double qz);
  /// From translation and quaternion, normalized as above. Throws
  /// InvalidArgument on NaN/Inf or a zero quaternion.
  Pose3Quat(const Eigen::Vector3d& t, const Eigen::Quaterniond& q);
  /// From a Pose3: q from its yaw/pitch/roll with MRPT's formula (see the
  /// class comment about the sign).
  explicit Pose3Quat(const Pose3& p) noexcept;
  /// Lossless 2D to 3D conversion: q = (cos(phi/2), 0, 0, sin(phi/2)).
  Pose3Quat(const Pose2& p) noexcept;  // NOLINT: implicit by design
  /// From a 4x4 homogeneous matrix, via Pose3 (same checks and tolerance).
  explicit Pose3Quat(const Eigen::Matrix4d& T, double tolerance = Pose3::kRotationTolerance);
  /// Internal: no validation; q must be unit.
  Pose3Quat(detail::Unchecked, const Eigen::Vector3d& t, const Eigen::Quaterniond& q) noexcept
      : t_(t), q_(q) {}

  /// The identity pose.
  static Pose3Quat identity() noexcept { return Pose3Quat(); }

  /// x in meters.
  double x() const noexcept { return t_.x(); }
  /// y in meters.
  double y() const noexcept { return t_.y(); }
  /// z in meters.
  double z() const noexcept { return t_.z(); }
  /// Quaternion real part.
  double qw() const noexcept { return q_.w(); }
  /// Quaternion i part.
  double qx() const noexcept { return q_.x(); }
  /// Quaternion j part.
  double qy() const noexcept { return q_.y(); }
  /// Quaternion k part.
  double qz() const noexcept { return q_.z(); }
  /// The translation, meters.
  const Eigen::Vector3d& translation() const noexcept { return t_; }
  /// The position as a point.
  Point3 position() const noexcept { return detail::make_point3(t_.x(), t_.y(), t_.z()); }
  /// The unit quaternion.
  const Eigen::Quaterniond& quaternion() const noexcept { return q_; }
  /// The rotation matrix (MRPT's formula).
  Eigen::Matrix3d rotation() const noexcept { return rotation_from_quaternion(q_); }
  /// The 4x4 homogeneous matrix.
  Eigen::Matrix4d matrix() const noexcept;
  /// Yaw, pitch, roll of the rotation (MRPT's formula on the matrix).
  YawPitchRoll yaw_pitch_roll() const noexcept { return ypr_from_rotation(rotation()); }
  /// The vector (x, y, z, qw, qx, qy, qz), MRPT's ordering.
  Eigen::Matrix<double, 7, 1> to_vector() const noexcept;

  /// The inverse pose: (-(q* t q), q*).
  Pose3Quat inverse() const noexcept;
  /// this = this + b.
  Pose3Quat& operator+=(const Pose3Quat& b) noexcept;
  /// this = this - b.
  Pose3Quat& operator-=(const Pose3Quat& b) noexcept;
  /// this = this + b for a 2D right operand.
  Pose3Quat& operator+=(const Pose2& b) noexcept;
  /// this = this - b for a 2D right operand.
  Pose3Quat& operator-=(const Pose2& b) noexcept;

  /// Norm of the position, meters.
  double norm() const noexcept { return t_.norm(); }
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

  /// MRPT's string form "[x y z qw qx qy qz]" ("%f" each).
  std::string as_string() const;
  /// Parses "[x y z qw qx qy qz]"; the quaternion is normalized. Throws
  /// ParseError naming the field on malformed text or a zero quaternion.
  static Pose3Quat from_string(std::string_view text);

 private:
  Eigen::Vector3d t_;
  Eigen::Quaterniond q_;
};

namespace detail {

/// v rotated by unit quaternion q: v + 2w (u x v) + 2 u x (u x v), u = vec(q).
inline Eigen::Vector3d quat_rotate(const Eigen::Quaterniond& q, const Eigen::Vector3d& v) noexcept {
  const Eigen::Vector3d u = q.vec();
  const Eigen::Vector3d uv = u.cross(v);
  return v + 2.0 * (q.w() * uv + u.cross(uv));
}
/// v rotated by the conjugate of unit quaternion q.
inline Eigen::Vector3d quat_inverse_rotate(const Eigen::Quaterniond& q,
                                           const Eigen::Vector3d& v) noexcept {
  const Eigen::Vector3d u = q.vec();
  const Eigen::Vector3d uv = u.cross(v);
  return v + 2.0 * (-q.w() * uv + u.cross(uv));
}
/// Hamilton product a * b, normalized and made w >= 0 (MRPT's
/// CQuaternion::crossProduct).
inline Eigen::Quaterniond quat_product_normalized(const Eigen::Quaterniond& a,
                                                  const Eigen::Quaterniond& b) noexcept {
  double w = a.w() * b.w() - a.x() * b.x() - a.y() * b.y() - a.z() * b.z();
  double x = a.w() * b.x() + b.w() * a.x() + a.y() * b.z() - b.y() * a.z();
  double y = a.w() * b.y() + b.w() * a.y() + a.z() * b.x() - b.z() * a.x();
  double z = a.w() * b.z() + b.w() * a.z() + a.x() * b.y() - b.x() * a.y();
  double k = 1.0 / std::sqrt(w * w + x * x + y * y + z * z);
  if (w < 0) k = -k;
  return Eigen::Quaterniond(w * k, x * k, y * k, z * k);
}

}  // namespace detail

/// Position as a 3D vector.
inline Eigen::Vector3d position_3d(const Pose3Quat& p) noexcept { return p.translation(); }

inline Pose3Quat::Pose3Quat(const Pose3& p) noexcept : t_(p.translation()), q_(p.quaternion()) {}

inline Pose3Quat::Pose3Quat(const Pose2& p) noexcept
    : t_(p.x(), p.y(), 0.0), q_(std::cos(0.5 * p.phi()), 0.0, 0.0, std::sin(0.5 * p.phi())) {}

inline Pose3::Pose3(const Pose3Quat& p) noexcept
    : R_(rotation_from_quaternion(p.quaternion())), t_(p.translation()) {}

inline Pose2::Pose2(const Pose3Quat& p) : Pose2(Pose3(p)) {}

inline Eigen::Matrix4d Pose3Quat::matrix() const noexcept {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = rotation();
  T.topRightCorner<3, 1>() = t_;
  return T;
}

inline Eigen::Matrix<double, 7, 1> Pose3Quat::to_vector() const noexcept {
  Eigen::Matrix<double, 7, 1> v;
  v << t_, q_.w(), q_.x(), q_.y(), q_.z();
  return v;
}

inline Pose3Quat Pose3Quat::inverse() const noexcept {
  return Pose3Quat(detail::kUnchecked, -detail::quat_inverse_rotate(q_, t_), q_.conjugate());
}

/// Composition a (+) b = (ta + qa tb qa*, normalized qa qb).
inline Pose3Quat operator+(const Pose3Quat& a, const Pose3Quat& b) noexcept {
  return Pose3Quat(detail::kUnchecked,
                   a.translation() + detail::quat_rotate(a.quaternion(), b.translation()),
                   detail::quat_product_normalized(a.quaternion(), b.quaternion()));
}
/// Inverse composition a (-) b = b^-1 (+) a.
inline Pose3Quat operator-(const Pose3Quat& a, const Pose3Quat& b) noexcept {
  return Pose3Quat(
      detail::kUnchecked,
      detail::quat_inverse_rotate(b.quaternion(), a.translation() - b.translation()),
      detail::quat_product_normalized(b.quaternion().conjugate(), a.quaternion()));
}
/// The inverse pose, -p = p^-1.
inline Pose3Quat operator-(const Pose3Quat& p) noexcept { return p.inverse(); }

inline Pose3Quat& Pose3Quat::operator+=(const Pose3Quat& b) noexcept { return *this = *this + b; }
inline Pose3Quat& Pose3Quat::operator-=(const Pose3Quat& b) noexcept { return *this = *this - b; }

/// A 3D point given in a's frame, in a's parent frame.
inline Point3 operator+(const Pose3Quat& a, const Point3& p) noexcept {
  const Eigen::Vector3d g =
      detail::quat_rotate(a.quaternion(), Eigen::Vector3d(p.x, p.y, p.z)) + a.translation();
  return detail::make_point3(g.x(), g.y(), g.z());
}
/// A 2D point (z = 0) given in a's frame, in a's parent frame.
inline Point3 operator+(const Pose3Quat& a, const Point2& p) noexcept { return a + Point3(p); }
/// Point p (parent frame) as seen from b.
inline Point3 operator-(const Point3& p, const Pose3Quat& b) noexcept {
  const Eigen::Vector3d l =
      detail::quat_inverse_rotate(b.quaternion(), Eigen::Vector3d(p.x, p.y, p.z) - b.translation());
  return detail::make_point3(l.x(), l.y(), l.z());
}
/// 2D point p (z = 0, parent frame) as seen from b.
inline Point3 operator-(const Point2& p, const Pose3Quat& b) noexcept { return Point3(p) - b; }

// Mixed quaternion / Euler / 2D poses. Rule: the result has the 3D
// representation of the left operand (so `a = a + b` and `a += b` agree);
// a 2D left operand takes the right operand's representation.

/// Pose3Quat (+) Pose3 -> Pose3Quat (b converted with MRPT's formula).
inline Pose3Quat operator+(const Pose3Quat& a, const Pose3& b) noexcept { return a + Pose3Quat(b); }
/// Pose3 (+) Pose3Quat -> Pose3 (b's rotation matrix from its quaternion).
inline Pose3 operator+(const Pose3& a, const Pose3Quat& b) noexcept { return a + Pose3(b); }
/// Pose3Quat (+) Pose2 -> Pose3Quat.
inline Pose3Quat operator+(const Pose3Quat& a, const Pose2& b) noexcept { return a + Pose3Quat(b); }
/// Pose2 (+) Pose3Quat -> Pose3Quat.
inline Pose3Quat operator+(const Pose2& a, const Pose3Quat& b) noexcept { return Pose3Quat(a) + b; }
/// Pose3Quat (-) Pose3 -> Pose3Quat.
inline Pose3Quat operator-(const Pose3Quat& a, const Pose3& b) noexcept { return a - Pose3Quat(b); }
/// Pose3 (-) Pose3Quat -> Pose3.
inline Pose3 operator-(const Pose3& a, const Pose3Quat& b) noexcept { return a - Pose3(b); }
/// Pose3Quat (-) Pose2 -> Pose3Quat.
inline Pose3Quat operator-(const Pose3Quat& a, const Pose2& b) noexcept { return a - Pose3Quat(b); }
/// Pose2 (-) Pose3Quat -> Pose3Quat.
inline Pose3Quat operator-(const Pose2& a, const Pose3Quat& b) noexcept { return Pose3Quat(a) - b; }

inline Pose3Quat& Pose3Quat::operator+=(const Pose2& b) noexcept { return *this = *this + b; }
inline Pose3Quat& Pose3Quat::operator-=(const Pose2& b) noexcept { return *this = *this - b; }

/// this = this + b for a Pose3 right operand.
inline Pose3Quat& operator+=(Pose3Quat& a, const Pose3& b) noexcept { return a = a + b; }
/// this = this - b for a Pose3 right operand.
inline Pose3Quat& operator-=(Pose3Quat& a, const Pose3& b) noexcept { return a = a - b; }
/// this = this + b for a Pose3Quat right operand.
inline Pose3& operator+=(Pose3& a, const Pose3Quat& b) noexcept { return a = a + b; }
/// this = this - b for a Pose3Quat right operand.
inline Pose3& operator-=(Pose3& a, const Pose3Quat& b) noexcept { return a = a - b; }

/// Exact equality of t and of the quaternion components (q and -q differ).
inline bool operator==(const Pose3Quat& a, const Pose3Quat& b) noexcept {
  return a.translation() == b.translation() && a.quaternion().coeffs() == b.quaternion().coeffs();
}

/// MRPT's operator<< text "(x,y,z,qr,qx,qy,qz)=(%.4f,...,%.4f)".
std::ostream& operator<<(std::ostream& os, const Pose3Quat& p);
/// The text of operator<<.
std::string to_string(const Pose3Quat& p);

}  // namespace rove

/// fmt prints a Pose3Quat as its operator<< does.
template <>
struct fmt::formatter<rove::Pose3Quat> : rove::detail::ToStringFormatter<rove::Pose3Quat> {};
