#include "rove/io/trajectory_files.h"

#include <array>

#include <fmt/format.h>

#include <Eigen/Geometry>

#include "number_rows.h"
#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove {

namespace {

/// Largest trajectory or relations file read (a KITTI sequence is ~0.5 MB).
constexpr std::uint64_t kMaxTrajectoryBytes = 1ull << 32;

}  // namespace

std::vector<StampedPose3> parse_kitti_trajectory(std::string_view text, std::string_view source) {
  static constexpr std::array<const char*, 12> kFields = {"r11", "r12", "r13", "tx",
                                                          "r21", "r22", "r23", "ty",
                                                          "r31", "r32", "r33", "tz"};
  std::vector<StampedPose3> out;
  detail::for_each_number_row(text, source, kFields, [&](std::span<const double> v, std::size_t line) {
    Eigen::Matrix3d R;
    R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
    const double off = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (!(off <= 1e-3) || R.determinant() <= 0.0)
      throw ParseError({printable(source), line, std::nullopt, "r11"},
                       fmt::format("the 3x3 block is not a rotation (|RᵀR − I| = {:.3g}, det {:.3g})",
                                   off, R.determinant()));
    const Eigen::Quaterniond q = Eigen::Quaterniond(R).normalized();
    out.push_back({static_cast<double>(out.size()), SE3d(q, Eigen::Vector3d(v[3], v[7], v[11]))});
  });
  return out;
}

std::vector<StampedPose3> read_kitti_trajectory(const std::string& path) {
  return parse_kitti_trajectory(read_input_file(path, kMaxTrajectoryBytes, "trajectory"), path);
}

std::vector<PoseRelation> parse_relations(std::string_view text, std::string_view source) {
  static constexpr std::array<const char*, 8> kFields = {"t1", "t2", "x", "y", "z",
                                                         "roll", "pitch", "yaw"};
  std::vector<PoseRelation> out;
  detail::for_each_number_row(text, source, kFields, [&](std::span<const double> v, std::size_t) {
    const Eigen::Quaterniond q = Eigen::AngleAxisd(v[7], Eigen::Vector3d::UnitZ()) *
                                 Eigen::AngleAxisd(v[6], Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(v[5], Eigen::Vector3d::UnitX());
    out.push_back({v[0], v[1], SE3d(q.normalized(), Eigen::Vector3d(v[2], v[3], v[4]))});
  });
  return out;
}

std::vector<PoseRelation> read_relations(const std::string& path) {
  return parse_relations(read_input_file(path, kMaxTrajectoryBytes, "relations"), path);
}

std::vector<std::string> first_row_fields(std::string_view text) {
  return detail::first_row_fields(text);
}

}  // namespace rove
