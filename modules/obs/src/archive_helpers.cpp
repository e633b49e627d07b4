#include "archive_helpers.h"

#include <Eigen/Core>

#include "rove/serialization/version.h"

namespace rove::detail {

void save_pose2(OutArchive& ar, const Pose2& p) {
  ar.write_scalar(p.x());
  ar.write_scalar(p.y());
  ar.write_scalar(p.phi());
}

Pose2 load_pose2(InArchive& ar, std::string_view field) {
  const std::uint64_t at = ar.offset();
  const double x = ar.read_scalar<double>(field);
  const double y = ar.read_scalar<double>(field);
  const double phi = ar.read_scalar<double>(field);
  return parse_guard(ar, at, field, [&] { return Pose2(x, y, phi); });
}

void save_pose3(OutArchive& ar, const Pose3& p) {
  const Eigen::Matrix3d& R = p.rotation();
  ar.write_scalars(std::span<const double>(R.data(), 9));
  ar.write_scalars(std::span<const double>(p.translation().data(), 3));
}

Pose3 load_pose3(InArchive& ar, std::string_view field) {
  const std::uint64_t at = ar.offset();
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  ar.read_scalars(std::span<double>(R.data(), 9), field);
  ar.read_scalars(std::span<double>(t.data(), 3), field);
  return parse_guard(ar, at, field, [&] { return Pose3(R, t); });
}

void save_pose2_gaussian(OutArchive& ar, const Pose2Gaussian& g) {
  save_pose2(ar, g.mean());
  ar.write_scalars(std::span<const double>(g.covariance().data(), 9));
}

Pose2Gaussian load_pose2_gaussian(InArchive& ar, std::string_view field) {
  const Pose2 mean = load_pose2(ar, field);
  const std::uint64_t at = ar.offset();
  Eigen::Matrix3d C;
  ar.read_scalars(std::span<double>(C.data(), 9), field);
  return parse_guard(ar, at, field, [&] { return Pose2Gaussian(mean, C); });
}

}  // namespace rove::detail
