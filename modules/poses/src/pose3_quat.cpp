#include "rove/poses/pose3_quat.h"

#include <cmath>
#include <ostream>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {
namespace {

/// Normalizes q (any non-zero finite quaternion) and makes w >= 0.
Eigen::Quaterniond checked_unit_quaternion(double qw, double qx, double qy, double qz) {
  ROVE_CHECK_FINITE(qw);
  ROVE_CHECK_FINITE(qx);
  ROVE_CHECK_FINITE(qy);
  ROVE_CHECK_FINITE(qz);
  const Eigen::Vector4d c(qw, qx, qy, qz);
  const double n = c.stableNorm();
  ROVE_CHECK_MSG(n > 0.0 && std::isfinite(n),
                 "quaternion (w, x, y, z) = ({}, {}, {}, {}) has norm {}: cannot normalize", qw,
                 qx, qy, qz, n);
  const double k = qw < 0.0 ? -1.0 / n : 1.0 / n;
  return Eigen::Quaterniond(qw * k, qx * k, qy * k, qz * k);
}

}  // namespace

Pose3Quat::Pose3Quat(double x, double y, double z, double qw, double qx, double qy, double qz)
    : t_(x, y, z), q_(checked_unit_quaternion(qw, qx, qy, qz)) {
  ROVE_CHECK_FINITE(x);
  ROVE_CHECK_FINITE(y);
  ROVE_CHECK_FINITE(z);
}

Pose3Quat::Pose3Quat(const Eigen::Vector3d& t, const Eigen::Quaterniond& q)
    : t_(t), q_(checked_unit_quaternion(q.w(), q.x(), q.y(), q.z())) {
  ROVE_CHECK_FINITE(t);
}

Pose3Quat::Pose3Quat(const Eigen::Matrix4d& T, double tolerance) : Pose3Quat(Pose3(T, tolerance)) {}

std::string Pose3Quat::as_string() const {
  return fmt::format("[{:f} {:f} {:f} {:f} {:f} {:f} {:f}]", x(), y(), z(), qw(), qx(), qy(),
                     qz());
}

Pose3Quat Pose3Quat::from_string(std::string_view text) {
  const auto v =
      detail::parse_bracketed(text, {"x", "y", "z", "qw", "qx", "qy", "qz"}, "Pose3Quat");
  if (v[3] == 0.0 && v[4] == 0.0 && v[5] == 0.0 && v[6] == 0.0) {
    ParseError::Location where;
    where.source = "<string>";
    where.field = "qw qx qy qz";
    throw ParseError(std::move(where),
                     fmt::format("Pose3Quat: the quaternion is zero in \"{}\"", text));
  }
  return Pose3Quat(v[0], v[1], v[2], v[3], v[4], v[5], v[6]);
}

std::string to_string(const Pose3Quat& p) {
  return fmt::format("(x,y,z,qr,qx,qy,qz)=({:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f})",
                     p.x(), p.y(), p.z(), p.qw(), p.qx(), p.qy(), p.qz());
}

std::ostream& operator<<(std::ostream& os, const Pose3Quat& p) { return os << to_string(p); }

}  // namespace rove
