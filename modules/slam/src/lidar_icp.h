#pragma once
// The ICP steps of lidar SLAM (lidar_slam.cpp): the front-end's refinement
// of a scan's pose against the points of the latest nodes, and the
// verification of a loop-closure candidate against the points of the
// submap's nodes. This file is the only place lidar SLAM calls
// rove::icp_2d (icp_align).

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se2.h"
#include "rove/registration/icp_target_2d.h"
#include "rove/registration/termination.h"
#include "rove/slam/lidar_slam.h"

namespace rove {

/// One ICP alignment of lidar SLAM.
struct LidarIcpResult {
  SE2d T_target_robot;  ///< ICP's pose (the initial one when it failed)
  double goodness = 0.0;  ///< share of the points ICP paired
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
};

/// Point-to-line ICP of `points_robot` against `target` (which has
/// normals) from `initial`, pairing within `gate` meters at first.
/// With remap_threshold = 0, a result whose geometry leaves a direction
/// free (a corridor) is Degenerate, not Converged. With remap_threshold > 0
/// the result is remapped instead (Zhang, Kaess, Singh, "On degeneracy of
/// optimization-based state estimation problems", ICRA 2016): ICP's step
/// from `initial` is kept only along the eigenvectors of the pairs'
/// point-to-line information (in x, y and θ times the points' RMS radius)
/// whose eigenvalue is at least remap_threshold times the largest; along
/// a corridor the pose stays where `initial` put it. At most
/// `max_iterations` iterations (>= 1).
LidarIcpResult icp_align(const IcpTarget2D& target, std::span<const Eigen::Vector2d> points_robot,
                         const SE2d& initial, double gate, double remap_threshold = 0.0,
                         int max_iterations = 60);

/// The points of `nodes` (indices into `all`) in the frame `T_frame_local`
/// maps the local frame into, thinned to one per voxel of `voxel` meters,
/// with normals.
std::shared_ptr<const IcpTarget2D> nodes_icp_target(std::span<const std::size_t> nodes,
                                                    const std::vector<LidarSlamNode>& all,
                                                    const SE2d& T_frame_local, double voxel);

/// What ICP said about a loop-closure candidate.
struct LoopVerification {
  LoopClosureOutcome outcome = LoopClosureOutcome::IcpFailed;
  double goodness = 0.0;  ///< share of the node's points ICP paired
  SE2d T_submap_robot;    ///< ICP's pose (the refined one if ICP failed)
};

/// Aligns `points_robot` with `target` from `T_submap_robot` and judges
/// the result with the options' verify_* thresholds.
LoopVerification verify_loop_with_icp(const IcpTarget2D& target,
                                      std::span<const Eigen::Vector2d> points_robot,
                                      const SE2d& T_submap_robot,
                                      const LidarLoopClosureOptions& options);

}  // namespace rove
