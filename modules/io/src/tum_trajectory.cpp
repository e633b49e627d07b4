#include "rove/io/tum_trajectory.h"

#include <array>
#include <cmath>
#include <cstddef>

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "number_rows.h"
#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove {

void write_tum_trajectory(const std::string& path, const std::vector<TimedPose2>& poses) {
  AtomicOutputFile out(path);
  out.write("# t x y z qx qy qz qw\n");
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto& p = poses[i];
    const double t = p.time.valid() ? p.time.to_seconds() : static_cast<double>(i);
    const double h = 0.5 * p.pose.phi();
    out.write(fmt::format("{:.6f} {:.6f} {:.6f} 0 0 0 {:.9f} {:.9f}\n", t, p.pose.x(),
                          p.pose.y(), std::sin(h), std::cos(h)));
  }
  out.commit();
}

void write_tum_trajectory(const std::string& path, const std::vector<TimedPose3>& poses) {
  AtomicOutputFile out(path);
  out.write("# t x y z qx qy qz qw\n");
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const auto& p = poses[i];
    const double t = p.time.valid() ? p.time.to_seconds() : static_cast<double>(i);
    Eigen::Quaterniond q = p.pose.quaternion();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    const Eigen::Vector3d& x = p.pose.translation();
    out.write(fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.9f} {:.9f} {:.9f} {:.9f}\n", t, x.x(),
                          x.y(), x.z(), q.x(), q.y(), q.z(), q.w()));
  }
  out.commit();
}

std::vector<StampedPose3> parse_tum_trajectory(std::string_view text, std::string_view source) {
  static constexpr std::array<const char*, 8> kFields = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
  std::vector<StampedPose3> out;
  detail::for_each_number_row(text, source, kFields, [&](std::span<const double> v, std::size_t line) {
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (!(q.norm() > 1e-12))
      throw ParseError({printable(source), line, std::nullopt, "qw"}, "the quaternion is zero");
    out.push_back({v[0], SE3d(q.normalized(), Eigen::Vector3d(v[1], v[2], v[3]))});
  });
  return out;
}

std::vector<StampedPose3> read_tum_trajectory(const std::string& path) {
  return parse_tum_trajectory(read_input_file(path, 1ull << 32, "trajectory"), path);
}

}  // namespace rove
