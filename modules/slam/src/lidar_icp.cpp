#include "lidar_icp.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

#include "rove/registration/icp_2d.h"
#include "rove/slam/scan_points_2d.h"

namespace rove {

namespace {

// The solution remapping of Zhang et al. 2016 (see icp_align): the step
// from `initial` to `solved` projected onto the well-constrained directions
// of the point-to-line information of the pairs at `solved`.
SE2d remap(const IcpTarget2D& target, std::span<const Eigen::Vector2d> points_robot,
           const SE2d& initial, const SE2d& solved, double threshold) {
  constexpr double kPairDistance = 0.1;  // meters: pairs of a converged ICP
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  double r2 = 0.0;
  std::size_t pairs = 0;
  for (const auto& p : points_robot) {
    if (!p.allFinite()) continue;
    const Eigen::Vector2d q_rot = solved.rotation() * p;
    const Eigen::Vector2d q = q_rot + solved.translation();
    const auto nn = target.tree().nearest(q, kPairDistance);
    if (!nn) continue;
    const Eigen::Vector2d n = target.normals()[nn->index];
    if (n.squaredNorm() < 0.5) continue;
    const Eigen::Vector3d J(n.x(), n.y(), n.dot(Eigen::Vector2d(-q_rot.y(), q_rot.x())));
    H.noalias() += J * J.transpose();
    r2 += q_rot.squaredNorm();
    ++pairs;
  }
  if (pairs < 3) return initial;
  // Scale θ by the RMS radius so that the eigenvalues compare like lengths.
  const double r = std::sqrt(r2 / static_cast<double>(pairs));
  const Eigen::Vector3d scale(1.0, 1.0, r > 1e-9 ? 1.0 / r : 1.0);
  const Eigen::Matrix3d Hs = scale.asDiagonal() * H * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Hs);
  const double lambda_max = es.eigenvalues().maxCoeff();
  Eigen::Vector3d step(solved.translation().x() - initial.translation().x(),
                       solved.translation().y() - initial.translation().y(),
                       std::remainder(solved.angle() - initial.angle(), 2.0 * std::numbers::pi));
  step = step.cwiseQuotient(scale);  // into (x, y, r·θ)
  Eigen::Vector3d kept = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (es.eigenvalues()(i) >= threshold * lambda_max) {
      const Eigen::Vector3d v = es.eigenvectors().col(i);
      kept += v * v.dot(step);
    }
  }
  kept = kept.cwiseProduct(scale);
  return SE2d(initial.translation().x() + kept.x(), initial.translation().y() + kept.y(),
              initial.angle() + kept.z());
}

}  // namespace

LidarIcpResult icp_align(const IcpTarget2D& target, std::span<const Eigen::Vector2d> points_robot,
                         const SE2d& initial, double gate, double remap_threshold,
                         int max_iterations) {
  Icp2dOptions o;
  o.algorithm = IcpAlgorithm::Classic;
  o.metric = Icp2dMetric::PointToLine;
  o.max_iterations = max_iterations;
  o.threshold_dist = gate;
  o.threshold_ang = 0.0;
  o.alfa = 0.5;
  o.smallest_threshold_dist = 0.05;
  o.corresponding_points_decimation = 1;
  o.skip_cov_calculation = true;
  if (remap_threshold > 0.0) o.degeneracy_threshold = 0.0;  // remapped below instead
  const Icp2dResult r = icp_2d(target, points_robot, initial, o);
  LidarIcpResult out;
  out.termination = r.termination;
  out.goodness = r.goodness;
  out.T_target_robot = r.ok() ? r.T_target_source : initial;
  if (r.ok() && remap_threshold > 0.0 && target.has_normals()) {
    out.T_target_robot = remap(target, points_robot, initial, out.T_target_robot, remap_threshold);
  }
  return out;
}

std::shared_ptr<const IcpTarget2D> nodes_icp_target(std::span<const std::size_t> nodes,
                                                    const std::vector<LidarSlamNode>& all,
                                                    const SE2d& T_frame_local, double voxel) {
  std::vector<Eigen::Vector2d> pts;
  for (const std::size_t i : nodes) {
    const LidarSlamNode& n = all[i];
    const SE2d T = T_frame_local * n.T_local_robot;
    for (const auto& p : n.points) pts.push_back(T * p);
  }
  IcpTarget2DOptions to;
  to.normal_neighbors = 5;
  return std::make_shared<const IcpTarget2D>(voxel_filter_2d(pts, voxel), to);
}

LoopVerification verify_loop_with_icp(const IcpTarget2D& target,
                                      std::span<const Eigen::Vector2d> points_robot,
                                      const SE2d& T_submap_robot,
                                      const LidarLoopClosureOptions& options) {
  LoopVerification v;
  v.T_submap_robot = T_submap_robot;
  const LidarIcpResult r = icp_align(target, points_robot, T_submap_robot,
                                     std::max(2.0 * options.verify_max_translation, 0.1));
  v.goodness = r.goodness;
  if (r.termination != RegistrationTermination::Converged || r.goodness < options.verify_min_goodness) {
    return v;
  }
  v.T_submap_robot = r.T_target_robot;
  const SE2d d = T_submap_robot.inverse() * v.T_submap_robot;
  v.outcome = d.translation().norm() <= options.verify_max_translation &&
                      std::abs(d.angle()) <= options.verify_max_rotation
                  ? LoopClosureOutcome::Accepted
                  : LoopClosureOutcome::IcpDisagrees;
  return v;
}

}  // namespace rove
