#include "rove/poses/pose3.h"

#include <cmath>
#include <ostream>

#include <Eigen/LU>
#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {
namespace {

void check_rotation(const Eigen::Matrix3d& R, double tolerance) {
  ROVE_CHECK_GE(tolerance, 0.0);
  ROVE_CHECK_FINITE(R);
  const double ortho_error = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  ROVE_CHECK_MSG(ortho_error <= tolerance,
                 "rotation matrix is not orthonormal: max |R^T R - I| = {:.3g} > tolerance {:.3g}",
                 ortho_error, tolerance);
  const double det = R.determinant();
  ROVE_CHECK_MSG(std::abs(det - 1.0) <= tolerance,
                 "rotation matrix has determinant {:.6g}, expected 1 (tolerance {:.3g})", det,
                 tolerance);
}

}  // namespace

Pose3::Pose3(double x, double y, double z, double yaw, double pitch, double roll) {
  ROVE_CHECK_FINITE(x);
  ROVE_CHECK_FINITE(y);
  ROVE_CHECK_FINITE(z);
  ROVE_CHECK_FINITE(yaw);
  ROVE_CHECK_FINITE(pitch);
  ROVE_CHECK_FINITE(roll);
  R_ = rotation_from_ypr(yaw, pitch, roll);
  t_ << x, y, z;
}

Pose3::Pose3(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double tolerance)
    : R_(R), t_(t) {
  ROVE_CHECK_FINITE(t);
  check_rotation(R, tolerance);
}

Pose3::Pose3(const Eigen::Matrix4d& T, double tolerance)
    : R_(T.topLeftCorner<3, 3>()), t_(T.topRightCorner<3, 1>()) {
  ROVE_CHECK_FINITE(T);
  const Eigen::RowVector4d bottom = T.row(3);
  ROVE_CHECK_MSG(bottom == Eigen::RowVector4d(0.0, 0.0, 0.0, 1.0),
                 "homogeneous matrix must end with the row (0 0 0 1), got ({} {} {} {})",
                 bottom(0), bottom(1), bottom(2), bottom(3));
  check_rotation(R_, tolerance);
}

std::string Pose3::as_string() const {
  const YawPitchRoll a = yaw_pitch_roll();
  return fmt::format("[{:f} {:f} {:f} {:f} {:f} {:f}]", x(), y(), z(), rad_to_deg(a.yaw),
                     rad_to_deg(a.pitch), rad_to_deg(a.roll));
}

Pose3 Pose3::from_string(std::string_view text) {
  const auto v = detail::parse_bracketed(
      text, {"x", "y", "z", "yaw_deg", "pitch_deg", "roll_deg"}, "Pose3");
  return Pose3(v[0], v[1], v[2], deg_to_rad(v[3]), deg_to_rad(v[4]), deg_to_rad(v[5]));
}

std::string to_string(const Pose3& p) {
  const YawPitchRoll a = p.yaw_pitch_roll();
  return fmt::format("(x,y,z,yaw,pitch,roll)=({:.4f},{:.4f},{:.4f},{:.2f}deg,{:.2f}deg,{:.2f}deg)",
                     p.x(), p.y(), p.z(), rad_to_deg(a.yaw), rad_to_deg(a.pitch),
                     rad_to_deg(a.roll));
}

std::ostream& operator<<(std::ostream& os, const Pose3& p) { return os << to_string(p); }

}  // namespace rove
