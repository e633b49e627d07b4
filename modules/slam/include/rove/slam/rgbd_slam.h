#pragma once
/// \file
/// RGB-D SLAM: frame-to-keyframe visual odometry on ORB features and PnP,
/// keyframes by motion thresholds, loop closure against nearby, random and
/// nearest-in-pose keyframes, an SE(3) pose graph with a Huber kernel, and a
/// voxel-filtered colored cloud as the map (docs/rgbd-slam.md).
///
/// Per frame: ORB features (rove/vision/orb.h), their normalized rays and,
/// where the depth image has a value, their 3D points. The frame is matched
/// to the current keyframe: first by a guided search (each keyframe point
/// projected with the constant-velocity prediction, matched to the frame's
/// keypoints within a radius), else by brute force; PnP with RANSAC
/// (rove/vision/pnp.h) on the keyframe's 3D points and the frame's pixels
/// gives T_frame_keyframe. When that fails and the previous frame was
/// tracked, the previous frame becomes a keyframe and the frame is matched
/// against it. A frame whose motion from its keyframe is large, or whose
/// inliers are few, becomes a keyframe: a vertex of the pose graph with an
/// edge from its keyframe (PnP's covariance, floored, as information), then
/// loop closures are tried and, when one is accepted, the graph is
/// optimized (Powell's dog-leg, Huber kernel). Frames between keyframes keep
/// their pose relative to their keyframe, so every frame's pose follows the
/// graph. A frame without features (textureless, dark) is skipped and
/// counted; a frame that cannot be tracked keeps the predicted pose and is
/// counted as lost.
///
/// Frames: T_world_camera, the world being the first keyframe's optical
/// frame (z forward, x right, y down).

#include <cstddef>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "rove/graph/bundle_adjustment.h"
#include "rove/graph/optimizer.h"
#include "rove/graph/pose_graph.h"
#include "rove/maps/occupancy_octree.h"
#include "rove/maps/point_cloud.h"
#include "rove/math/se3.h"
#include "rove/obs/pinhole_camera.h"
#include "rove/slam/rgbd_slam_options.h"
#include "rove/vision/rgbd_frame.h"

namespace rove {

/// What happened to a frame.
enum class RgbdFrameStatus {
  Keyframe,     ///< tracked (or the first frame) and made a keyframe
  Tracked,      ///< tracked against its keyframe
  Lost,         ///< not tracked: keeps the predicted pose
  NoFeatures,   ///< too few features (textureless, dark or blurred): skipped
};

/// "keyframe", "tracked", "lost", "no-features".
std::string_view to_string(RgbdFrameStatus status);

/// How a loop-closure candidate was chosen.
enum class RgbdLoopKind {
  Nearby,     ///< one of the latest keyframes
  Random,     ///< drawn at random among the older ones
  Proximity,  ///< nearest in pose
  Appearance, ///< most alike in appearance (rove/vision/place_recognition.h)
};

/// "nearby", "random", "proximity", "appearance".
std::string_view to_string(RgbdLoopKind kind);

/// One processed frame.
struct RgbdFrameUpdate {
  std::size_t index = 0;      ///< frame number, from 0
  RgbdFrameStatus status = RgbdFrameStatus::Lost;
  std::size_t features = 0;   ///< ORB features
  std::size_t matches = 0;    ///< matches with the keyframe tried last
  std::size_t inliers = 0;    ///< PnP inliers of the accepted pose (0 if none)
  std::size_t loops_accepted = 0;  ///< loop closures added for a new keyframe
};

/// A keyframe.
struct RgbdKeyframe {
  std::size_t frame = 0;   ///< frame number
  double time = 0.0;       ///< seconds
  SE3d T_world_camera;     ///< after the latest optimization
  std::size_t features = 0;       ///< ORB features
  std::size_t points = 0;         ///< features with a 3D point
};

/// One loop-closure attempt.
struct RgbdLoopCheck {
  std::size_t keyframe = 0;  ///< the new keyframe (index into keyframes())
  std::size_t candidate = 0; ///< the older keyframe
  RgbdLoopKind kind = RgbdLoopKind::Nearby;
  std::size_t matches = 0;   ///< descriptor matches
  std::size_t inliers = 0;   ///< PnP inliers
  double motion_norm = 0.0;  ///< of the estimated relative pose (0 if none)
  bool accepted = false;     ///< added to the graph
};

/// Counts and times (seconds, wall clock) of a run.
struct RgbdSlamStats {
  std::size_t frames = 0;        ///< processed
  std::size_t tracked = 0;       ///< Tracked or Keyframe (the first frame included)
  std::size_t lost = 0;          ///< Lost
  std::size_t no_features = 0;   ///< NoFeatures
  std::size_t keyframes = 0;
  std::size_t guided_tracked = 0;     ///< tracked by the guided search
  std::size_t brute_force_tracked = 0;///< tracked after brute-force matching
  std::size_t recovered = 0;     ///< tracked against the previous frame made a keyframe
  std::size_t weak_edges = 0;    ///< keyframes joined by a prediction only (after lost frames)
  std::size_t loop_checks = 0;
  std::size_t loops_accepted = 0;
  std::size_t optimizations = 0;
  std::size_t icp_edges = 0;     ///< geometric (GICP) edges added (RgbdSlamOptions::icp_voxel)
  std::size_t icp_refused = 0;   ///< GICP measurements refused (not converged, few pairs, far from PnP)
  double features_seconds = 0.0; ///< ORB extraction, rays, 3D points
  double matching_seconds = 0.0; ///< descriptor matching (tracking)
  double pnp_seconds = 0.0;      ///< PnP (tracking)
  double loop_seconds = 0.0;     ///< loop closure: matching and PnP
  double graph_seconds = 0.0;    ///< pose-graph optimization
  double icp_seconds = 0.0;      ///< GICP edges (clouds prepared, registration)
  double map_seconds = 0.0;      ///< keyframe clouds and the final voxel filter
  double octree_seconds = 0.0;   ///< the octree map (map_octree)
  double tracking_rmse_px = 0.0;   ///< RMS of PnP's inlier reprojection errors over the tracked frames, pixels
  std::size_t ba_points = 0;       ///< bundle adjustment: tracks (3D points) adjusted
  std::size_t ba_observations = 0; ///< their observations by keyframes
  std::size_t ba_outliers = 0;     ///< observations dropped as outliers
  std::size_t ba_conflicts = 0;    ///< tracks left out: one keyframe saw them at two features
  double ba_seconds = 0.0;         ///< tracks built and the adjustment
};

/// The RGB-D SLAM pipeline (see the file comment). Not thread-safe.
class RgbdSlam {
 public:
  /// Precondition (InvalidArgument): camera passes check(), options valid.
  RgbdSlam(const PinholeCamera& camera, const RgbdSlamOptions& options = {});
  ~RgbdSlam();
  RgbdSlam(RgbdSlam&&) noexcept;
  RgbdSlam& operator=(RgbdSlam&&) noexcept;

  /// Processes the next frame taken at `time` (seconds, increasing).
  /// Preconditions (InvalidArgument): the frame's images have one size,
  /// equal to the camera's when it states one; 8-bit color.
  RgbdFrameUpdate process(const RgbdFrame& frame, double time);

  /// After the last frame: optimizes the pose graph once more when it has
  /// loop closures, then, with options.bundle_adjustment, adjusts the
  /// keyframes and the tracks of their features together (see
  /// RgbdSlamOptions::bundle_adjustment) and gives the keyframes its poses
  /// when it improved on the graph's (BundleAdjustmentResult::improved).
  /// Returns the graph's optimization, if any; bundle_adjustment() holds the
  /// adjustment's result.
  std::optional<GraphOptimizerResult> finish();
  /// The bundle adjustment of finish(), when it ran.
  const std::optional<BundleAdjustmentResult>& bundle_adjustment() const noexcept;

  /// Frames processed.
  std::size_t num_frames() const noexcept;
  /// T_world_camera of frame i (its keyframe's pose after the latest
  /// optimization composed with the frame's pose relative to it). Frames
  /// before the first keyframe (no features) have the identity.
  /// Precondition: i < num_frames().
  SE3d frame_pose(std::size_t i) const;
  /// Time of frame i, seconds.
  double frame_time(std::size_t i) const;
  /// Status of frame i.
  RgbdFrameStatus frame_status(std::size_t i) const;

  /// The keyframes, poses after the latest optimization.
  std::vector<RgbdKeyframe> keyframes() const;
  /// Every loop-closure attempt, in order.
  const std::vector<RgbdLoopCheck>& loop_checks() const noexcept;
  /// The pose graph (vertex i = keyframe i).
  const PoseGraph3D& graph() const noexcept;
  /// The latest optimization, if the graph was optimized.
  const std::optional<GraphOptimizerResult>& last_optimization() const noexcept;
  /// The map: the keyframes' colored clouds (options.map_stride,
  /// map_max_depth) at the keyframes' poses, voxel filtered with leaf
  /// voxel_grid. Its time is added to stats().map_seconds.
  PointCloud map_cloud();
  /// The map as a 3D occupancy octree with OctoMap's semantics
  /// (rove/maps/occupancy_octree.h, default sensor model), cells
  /// options.octree_resolution meters wide: each keyframe's cloud (the one
  /// map_cloud() uses) placed at the keyframe's pose and inserted with rays
  /// from the camera's origin, keyframe after keyframe, so the cells between
  /// the camera and the surfaces it saw are free. Rays end at the centres of
  /// the distinct cells each cloud's points fall in (OctoMap's discretized
  /// insertion); options.octree_threads threads. World frame as
  /// frame_pose(). Its time is added to stats().octree_seconds.
  /// Precondition (InvalidArgument): options.octree_resolution > 0.
  OccupancyOctree map_octree();
  /// Counts and times so far.
  const RgbdSlamStats& stats() const noexcept;
  /// The options in use.
  const RgbdSlamOptions& options() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rove
