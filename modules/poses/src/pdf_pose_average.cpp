#include "rove/poses/pdf_pose_average.h"

#include <cmath>

#include <Eigen/SVD>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

template <typename P>
double check_weights(std::span<const P> poses, std::span<const double> weights) {
  ROVE_CHECK_EQ(poses.size(), weights.size());
  ROVE_CHECK_MSG(!poses.empty(), "weighted_mean needs at least one pose");
  double sum = 0.0;
  for (double w : weights) {
    ROVE_CHECK_MSG(std::isfinite(w) && w >= 0.0, "weights must be finite and >= 0, got {}", w);
    sum += w;
  }
  ROVE_CHECK_MSG(sum > 0.0, "weights must not all be zero");
  return sum;
}

}  // namespace

Pose2 weighted_mean(std::span<const Pose2> poses, std::span<const double> weights) {
  const double sum = check_weights(poses, weights);
  double x = 0.0, y = 0.0, c = 0.0, s = 0.0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double w = weights[i] / sum;
    x += w * poses[i].x();
    y += w * poses[i].y();
    c += w * std::cos(poses[i].phi());
    s += w * std::sin(poses[i].phi());
  }
  if (std::hypot(c, s) < 1e-12)
    throw NumericError("weighted_mean(Pose2): the headings cancel out, their mean is undetermined");
  return Pose2(x, y, std::atan2(s, c));
}

Pose3 weighted_mean(std::span<const Pose3> poses, std::span<const double> weights) {
  const double sum = check_weights(poses, weights);
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double w = weights[i] / sum;
    t += w * poses[i].translation();
    M += w * poses[i].rotation();
  }
  // Chordal L2 mean: argmin_R Σ wᵢ‖R − Rᵢ‖_F² = proj_SO(3)(M) = U·diag(1, 1, det(UVᵀ))·Vᵀ.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d sv = svd.singularValues();
  if (sv[1] < 1e-12 * std::max(1.0, sv[0]))
    throw NumericError("weighted_mean(Pose3): the rotations cancel out, their mean is undetermined");
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();
  return Pose3(R, t);
}

Eigen::Vector3d pose_difference(const Pose2& p, const Pose2& mean) {
  return {p.x() - mean.x(), p.y() - mean.y(), wrap_to_pi(p.phi() - mean.phi())};
}

Eigen::Matrix<double, 6, 1> pose_difference(const Pose3& p, const Pose3& mean) {
  const YawPitchRoll a = p.yaw_pitch_roll(), m = mean.yaw_pitch_roll();
  Eigen::Matrix<double, 6, 1> d;
  d << p.translation() - mean.translation(), wrap_to_pi(a.yaw - m.yaw),
      wrap_to_pi(a.pitch - m.pitch), wrap_to_pi(a.roll - m.roll);
  return d;
}

}  // namespace rove
