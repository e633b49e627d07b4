#include "rove/obs/pinhole_camera.h"

#include <cmath>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {
namespace {

// Distorted normalized coordinates of undistorted (a, b): OpenCV's plumb bob.
Eigen::Vector2d distort(const std::array<double, 5>& d, double a, double b) {
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3], k3 = d[4];
  const double r2 = a * a + b * b;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return {a * radial + 2.0 * p1 * a * b + p2 * (r2 + 2.0 * a * a),
          b * radial + p1 * (r2 + 2.0 * b * b) + 2.0 * p2 * a * b};
}

}  // namespace

bool PinholeCamera::has_distortion() const noexcept {
  for (const double c : distortion) {
    if (c != 0.0) return true;
  }
  return false;
}

void PinholeCamera::check() const {
  ROVE_CHECK_MSG(std::isfinite(fx) && fx != 0.0 && std::isfinite(fy) && fy != 0.0,
                 "PinholeCamera: focal lengths must be finite and nonzero (fx = {}, fy = {})", fx,
                 fy);
  ROVE_CHECK_MSG(std::isfinite(cx) && std::isfinite(cy),
                 "PinholeCamera: principal point must be finite (cx = {}, cy = {})", cx, cy);
  for (const double c : distortion) {
    ROVE_CHECK_MSG(std::isfinite(c), "PinholeCamera: distortion coefficient {} is not finite", c);
  }
}

Eigen::Vector2d PinholeCamera::project(const Eigen::Vector3d& p_camera) const {
  check();
  ROVE_CHECK_FINITE(p_camera);
  ROVE_CHECK_MSG(p_camera.z() > 0.0, "PinholeCamera::project: point z = {} must be > 0",
                 p_camera.z());
  const double a = p_camera.x() / p_camera.z();
  const double b = p_camera.y() / p_camera.z();
  const Eigen::Vector2d d = has_distortion() ? distort(distortion, a, b) : Eigen::Vector2d(a, b);
  return {fx * d.x() + cx, fy * d.y() + cy};
}

Eigen::Vector3d PinholeCamera::unproject(double u, double v) const {
  check();
  ROVE_CHECK_FINITE(u);
  ROVE_CHECK_FINITE(v);
  const double a0 = (u - cx) / fx;
  const double b0 = (v - cy) / fy;
  if (!has_distortion()) return {a0, b0, 1.0};
  // Fixed-point inversion as OpenCV's undistortPoints: a = (a0 − tangential(a)) / radial(a).
  const double k1 = distortion[0], k2 = distortion[1], p1 = distortion[2], p2 = distortion[3],
               k3 = distortion[4];
  double a = a0, b = b0;
  for (int it = 0; it < 100; ++it) {
    const Eigen::Vector2d e = distort(distortion, a, b) - Eigen::Vector2d(a0, b0);
    if (e.norm() < 1e-12) return {a, b, 1.0};
    const double r2 = a * a + b * b;
    const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    if (!(radial > 0.0) || !std::isfinite(radial)) break;
    const double dx = 2.0 * p1 * a * b + p2 * (r2 + 2.0 * a * a);
    const double dy = p1 * (r2 + 2.0 * b * b) + 2.0 * p2 * a * b;
    a = (a0 - dx) / radial;
    b = (b0 - dy) / radial;
  }
  const Eigen::Vector2d e = distort(distortion, a, b) - Eigen::Vector2d(a0, b0);
  if (std::isfinite(e.norm()) && e.norm() < 1e-9) return {a, b, 1.0};
  throw NumericError(fmt::format(
      "PinholeCamera::unproject: the distortion model cannot be inverted at pixel ({}, {}) "
      "(fixed-point iteration did not converge; coefficients k1={} k2={} p1={} p2={} k3={})",
      u, v, k1, k2, p1, p2, k3));
}

void save(OutArchive& ar, const PinholeCamera& c) {
  write_version(ar, 1);
  ar.write_scalar(c.width);
  ar.write_scalar(c.height);
  ar.write_scalar(c.fx);
  ar.write_scalar(c.fy);
  ar.write_scalar(c.cx);
  ar.write_scalar(c.cy);
  save(ar, c.distortion);
}

void load(InArchive& ar, PinholeCamera& c) {
  read_version(ar, "PinholeCamera", 1);
  c.width = ar.read_scalar<std::uint32_t>("camera width");
  c.height = ar.read_scalar<std::uint32_t>("camera height");
  c.fx = ar.read_scalar<double>("fx");
  c.fy = ar.read_scalar<double>("fy");
  c.cx = ar.read_scalar<double>("cx");
  c.cy = ar.read_scalar<double>("cy");
  load(ar, c.distortion);
}

}  // namespace rove
