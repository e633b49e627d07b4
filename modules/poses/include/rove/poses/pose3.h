#pragma once
/// \file
/// Pose3: a 6-DoF pose stored as rotation matrix + translation, MRPT's
/// CPose3D (without its cached angles), with composition against every 2D/3D
/// point and pose type except Pose3Quat (see pose3_quat.h).

#include <cmath>
#include <iosfwd>
#include <string>
#include <string_view>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rove/poses/euler.h"
#include "rove/poses/point2.h"
#include "rove/poses/point3.h"
#include "rove/poses/pose2.h"
#include "rove/poses/pose_io.h"
#include "rove/poses/position.h"

namespace rove {

class Pose3Quat;

/// A 3D pose T_parent_child: rotation R (3x3, orthonormal) and translation t
/// in meters, mapping child coordinates to parent ones as p_parent = R p + t.
/// Euler angles follow MRPT: R = Rz(yaw) Ry(pitch) Rx(roll), radians; a
/// positive pitch points the x axis below the XY plane. The angles are not
/// stored; yaw(), pitch(), roll() recover them from R with MRPT's formula.
/// `A + B` composes, `A - B` is A seen from B (B^-1 + A).
/// Thread-safety: a value type.
class Pose3 {
 public:
  /// Default tolerance of the orthonormality check of a given rotation:
  /// max |R^T R - I| and |det R - 1|.
  static constexpr double kRotationTolerance = 1e-6;

  /// The identity pose.
  Pose3() noexcept : R_(Eigen::Matrix3d::Identity()), t_(Eigen::Vector3d::Zero()) {}
  /// From position (meters) and yaw, pitch, roll (radians, any finite value).
  /// Throws InvalidArgument if any value is NaN/Inf.
  Pose3(double x, double y, double z, double yaw, double pitch, double roll);
  /// From a rotation matrix and a translation (meters). Throws
  /// InvalidArgument on NaN/Inf, or if R is not a rotation within `tolerance`
  /// (max |R^T R - I| > tolerance or |det R - 1| > tolerance). R is stored as
  /// given (not re-orthonormalized).
  Pose3(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
        double tolerance = kRotationTolerance);
  /// From a 4x4 homogeneous matrix [R t; 0 0 0 1]. Throws InvalidArgument on
  /// NaN/Inf, a bottom row other than (0 0 0 1), or a non-rotation R (as above).
  explicit Pose3(const Eigen::Matrix4d& T, double tolerance = kRotationTolerance);
  /// Lossless 2D to 3D conversion: (x, y, 0, yaw = phi, 0, 0).
  Pose3(const Pose2& p) noexcept;  // NOLINT: implicit by design
  /// From a quaternion pose: R from the quaternion (MRPT's formula). Defined
  /// in pose3_quat.h.
  explicit Pose3(const Pose3Quat& p) noexcept;
  /// Internal: no validation.
  Pose3(detail::Unchecked, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) noexcept
      : R_(R), t_(t) {}

  /// The identity pose.
  static Pose3 identity() noexcept { return Pose3(); }

  /// x in meters.
  double x() const noexcept { return t_.x(); }
  /// y in meters.
  double y() const noexcept { return t_.y(); }
  /// z in meters.
  double z() const noexcept { return t_.z(); }
  /// The translation t, meters.
  const Eigen::Vector3d& translation() const noexcept { return t_; }
  /// The position as a point.
  Point3 position() const noexcept { return detail::make_point3(t_.x(), t_.y(), t_.z()); }
  /// The rotation matrix R.
  const Eigen::Matrix3d& rotation() const noexcept { return R_; }
  /// The 4x4 homogeneous matrix [R t; 0 0 0 1].
  Eigen::Matrix4d matrix() const noexcept;
  /// Yaw, pitch and roll from R (MRPT's formula, including its gimbal-lock
  /// branch: at pitch = +-90 deg roll is 0).
  YawPitchRoll yaw_pitch_roll() const noexcept { return ypr_from_rotation(R_); }
  /// Yaw in radians, (-pi, pi].
  double yaw() const noexcept { return yaw_pitch_roll().yaw; }
  /// Pitch in radians, [-pi/2, pi/2].
  double pitch() const noexcept { return yaw_pitch_roll().pitch; }
  /// Roll in radians, (-pi, pi].
  double roll() const noexcept { return yaw_pitch_roll().roll; }
  /// The rotation as a unit quaternion, computed from yaw/pitch/roll as MRPT's
  /// CPose3D::getAsQuaternion (w may be negative, as in MRPT).
  Eigen::Quaterniond quaternion() const noexcept;
  /// The vector (x, y, z, yaw, pitch, roll), MRPT's ordering.
  Eigen::Matrix<double, 6, 1> to_vector() const noexcept;

  /// The inverse pose (R^T, -R^T t).
  Pose3 inverse() const noexcept { return Pose3(detail::kUnchecked, R_.transpose(), -(R_.transpose() * t_)); }
  /// this = this + b.
  Pose3& operator+=(const Pose3& b) noexcept;
  /// this = this - b.
  Pose3& operator-=(const Pose3& b) noexcept;
  /// this = this + b for a 2D right operand.
  Pose3& operator+=(const Pose2& b) noexcept;
  /// this = this - b for a 2D right operand.
  Pose3& operator-=(const Pose2& b) noexcept;

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

  /// MRPT's string form "[x y z yaw_deg pitch_deg roll_deg]" ("%f" each).
  std::string as_string() const;
  /// Parses "[x y z yaw_deg pitch_deg roll_deg]" (angles in degrees). Throws
  /// ParseError naming the field on malformed text.
  static Pose3 from_string(std::string_view text);

 private:
  /// Leaves R and t uninitialized; for the operators that fill them in place.
  explicit Pose3(detail::Unchecked) noexcept {}
  friend Pose3 operator+(const Pose3& a, const Pose3& b) noexcept;
  friend Pose3 operator-(const Pose3& a, const Pose3& b) noexcept;

  Eigen::Matrix3d R_;
  Eigen::Vector3d t_;
};

/// Position as a 3D vector.
inline Eigen::Vector3d position_3d(const Pose3& p) noexcept { return p.translation(); }

inline Pose3::Pose3(const Pose2& p) noexcept {
  const double c = std::cos(p.phi()), s = std::sin(p.phi());
  R_ << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  t_ << p.x(), p.y(), 0.0;
}

inline Pose2::Pose2(const Pose3& p) : x_(p.x()), y_(p.y()), phi_(p.yaw()) {}

inline Eigen::Matrix4d Pose3::matrix() const noexcept {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = R_;
  T.topRightCorner<3, 1>() = t_;
  return T;
}

inline Eigen::Quaterniond Pose3::quaternion() const noexcept {
  const YawPitchRoll a = yaw_pitch_roll();
  return quaternion_from_ypr(a.yaw, a.pitch, a.roll);
}

inline Eigen::Matrix<double, 6, 1> Pose3::to_vector() const noexcept {
  const YawPitchRoll a = yaw_pitch_roll();
  Eigen::Matrix<double, 6, 1> v;
  v << t_, a.yaw, a.pitch, a.roll;
  return v;
}

/// Composition a (+) b = (Ra Rb, ta + Ra tb).
inline Pose3 operator+(const Pose3& a, const Pose3& b) noexcept {
  // Written into the result's storage column by column: no temporaries, so
  // the compiler keeps everything in registers (this is the hot path).
  Pose3 c(detail::kUnchecked);
  for (int j = 0; j < 3; ++j) {
    c.R_.col(j) = a.R_.col(0) * b.R_(0, j) + a.R_.col(1) * b.R_(1, j) + a.R_.col(2) * b.R_(2, j);
  }
  c.t_ = a.t_ + a.R_.col(0) * b.t_.x() + a.R_.col(1) * b.t_.y() + a.R_.col(2) * b.t_.z();
  return c;
}
/// Inverse composition a (-) b = b^-1 (+) a = (Rb^T Ra, Rb^T (ta - tb)).
inline Pose3 operator-(const Pose3& a, const Pose3& b) noexcept {
  Pose3 c(detail::kUnchecked);
  c.R_.noalias() = b.R_.transpose().lazyProduct(a.R_);
  const Eigen::Vector3d d = a.t_ - b.t_;
  c.t_.noalias() = b.R_.transpose().lazyProduct(d);
  return c;
}
/// The inverse pose, -p = p^-1.
inline Pose3 operator-(const Pose3& p) noexcept { return p.inverse(); }

inline Pose3& Pose3::operator+=(const Pose3& b) noexcept { return *this = *this + b; }
inline Pose3& Pose3::operator-=(const Pose3& b) noexcept { return *this = *this - b; }

/// A 3D point given in a's frame, in a's parent frame: Ra p + ta.
inline Point3 operator+(const Pose3& a, const Point3& p) noexcept {
  const Eigen::Vector3d g = a.rotation() * Eigen::Vector3d(p.x, p.y, p.z) + a.translation();
  return detail::make_point3(g.x(), g.y(), g.z());
}
/// A 2D point (z = 0) given in a's frame, in a's parent frame.
inline Point3 operator+(const Pose3& a, const Point2& p) noexcept {
  const Eigen::Vector3d g = a.rotation().leftCols<2>() * Eigen::Vector2d(p.x, p.y) + a.translation();
  return detail::make_point3(g.x(), g.y(), g.z());
}
/// Point p (parent frame) as seen from b: Rb^T (p - tb).
inline Point3 operator-(const Point3& p, const Pose3& b) noexcept {
  const Eigen::Vector3d l =
      b.rotation().transpose() * (Eigen::Vector3d(p.x, p.y, p.z) - b.translation());
  return detail::make_point3(l.x(), l.y(), l.z());
}
/// 2D point p (z = 0, parent frame) as seen from b.
inline Point3 operator-(const Point2& p, const Pose3& b) noexcept {
  return Point3(p) - b;
}

/// Composition of a 2D and a 3D pose; the 2D operand is lifted losslessly.
inline Pose3 operator+(const Pose2& a, const Pose3& b) noexcept { return Pose3(a) + b; }
/// Composition of a 3D and a 2D pose.
inline Pose3 operator+(const Pose3& a, const Pose2& b) noexcept { return a + Pose3(b); }
/// Inverse composition, 2D pose seen from a 3D pose.
inline Pose3 operator-(const Pose2& a, const Pose3& b) noexcept { return Pose3(a) - b; }
/// Inverse composition, 3D pose seen from a 2D pose.
inline Pose3 operator-(const Pose3& a, const Pose2& b) noexcept { return a - Pose3(b); }

inline Pose3& Pose3::operator+=(const Pose2& b) noexcept { return *this = *this + b; }
inline Pose3& Pose3::operator-=(const Pose2& b) noexcept { return *this = *this - b; }

/// Exact equality of R and t (MRPT compares R within 1e-6; use an explicit
/// tolerance test where that is wanted).
inline bool operator==(const Pose3& a, const Pose3& b) noexcept {
  return a.translation() == b.translation() && a.rotation() == b.rotation();
}

/// MRPT's operator<< text:
/// "(x,y,z,yaw,pitch,roll)=(%.4f,%.4f,%.4f,%.2fdeg,%.2fdeg,%.2fdeg)".
std::ostream& operator<<(std::ostream& os, const Pose3& p);
/// The text of operator<<.
std::string to_string(const Pose3& p);

}  // namespace rove

/// fmt prints a Pose3 as its operator<< does.
template <>
struct fmt::formatter<rove::Pose3> : rove::detail::ToStringFormatter<rove::Pose3> {};
