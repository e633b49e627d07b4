#pragma once
/// \file
/// Options of the RGB-D SLAM pipeline (rove/slam/rgbd_slam.h), with two
/// presets: rove's defaults, and the RGB-D SLAM tutorial's values under its
/// own parameter names (detector, good_match_threshold, min_inliers,
/// max_norm, keyframe_threshold, nearby_loops, random_loops, voxel_grid).
/// Needs rove::vision (built when OpenCV is found).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "rove/core/config_section.h"
#include "rove/vision/binary_matching.h"
#include "rove/vision/orb.h"
#include "rove/vision/pnp.h"

namespace rove {

/// Options of RgbdSlam. Motion norms are the tutorial's: for a relative pose
/// with rotation angle θ (radians) and translation t (meters),
/// norm = min(θ, 2π − θ) + ‖t‖.
struct RgbdSlamOptions {
  /// ORB extraction. Default 800 features, FAST threshold 20.
  OrbOptions orb{800, 1.2, 8, 20, 31};
  /// Brute-force matching (first frame pairs, lost tracking, random loop
  /// candidates). The tutorial's good_match_threshold is relative_factor.
  BinaryMatchOptions match;
  /// PnP with RANSAC on the reference frame's 3D points and the current
  /// frame's pixels. Its min_inliers is set from min_inliers below, its
  /// seed from seed. Default threshold 3 px (2 px kept fewer good pairs on
  /// the blurred frames of TUM fr1/rpy), 500 samples.
  PnpOptions pnp{3.0, 0.99, 500, 42, 10, 10};
  /// Depths used for 3D points, meters. Defaults 0.1 and 6 (the Kinect's
  /// depth noise grows with the square of the distance).
  double min_depth = 0.1;
  double max_depth = 6.0;
  /// A feature gets no 3D point when a depth within depth_edge_radius
  /// pixels (≥ 0) is missing or differs from its own by more than
  /// depth_edge_step·z (a depth edge, where color and depth may be
  /// misregistered); 0 disables. Defaults 2 and 0 (off: on TUM fr1/rpy it lost
  /// more points than it removed errors).
  int depth_edge_radius = 2;
  double depth_edge_step = 0.0;

  /// Guided matching: search radius around a point's predicted pixel,
  /// pixels (> 0); 0 turns guided matching off (brute force only).
  /// Default 40.
  double guided_radius_px = 40.0;
  /// Largest Hamming distance of a guided match, bits. Default 64.
  std::uint32_t guided_max_distance = 64;
  /// After a pose is found, the keyframe's points are matched again around
  /// their projections at that pose within this radius, pixels, and PnP is
  /// solved again on those matches (kept when it has more inliers); 0
  /// disables. Default 6.
  double refine_radius_px = 6.0;
  /// Fewer descriptor matches than this are not tried with PnP (the
  /// tutorial's min_good_match). Default 10.
  std::size_t min_matches = 10;

  /// A frame is tracked when PnP has at least this many inliers (≥ 4).
  /// Default 25; the tutorial's 5.
  std::size_t min_inliers = 25;
  /// A motion norm above this (frame against keyframe) is refused as a bad
  /// match; 0 disables. Default 0.5; the tutorial's 0.2.
  double max_norm = 0.5;
  /// A frame whose motion norm from its keyframe exceeds this becomes a
  /// keyframe (> 0). Default 0.12; the tutorial's 0.1.
  double keyframe_threshold = 0.12;
  /// A frame tracked with fewer inliers than this becomes a keyframe too
  /// (0 disables). Default 80.
  std::size_t keyframe_min_inliers = 80;

  /// Loop closure: each new keyframe is matched against the keyframes before
  /// its predecessor: the `nearby_loops` latest, `random_loops` random older
  /// ones (the tutorial's scheme) and the `proximity_loops` nearest in pose
  /// (by motion norm, among those not yet chosen). Defaults 3, 1, 3; the
  /// tutorial's 5, 5, 0.
  std::size_t nearby_loops = 3;
  std::size_t random_loops = 1;
  std::size_t proximity_loops = 3;
  /// And the `appearance_loops` keyframes most alike in appearance (ORB
  /// descriptors hashed by bit sampling, rove/vision/place_recognition.h),
  /// among those not yet chosen, scoring at least `appearance_min_score`
  /// (votes over the geometric mean of the descriptor counts); drawn before
  /// the random ones. Defaults 1 and 0.05 (one of the two random candidates
  /// of before: on TUM fr1/rpy 45 % of appearance candidates were accepted
  /// as loops, 9 % of random ones); the tutorial's 0.
  std::size_t appearance_loops = 1;
  double appearance_min_score = 0.05;
  /// Proximity candidates lie within this motion norm of the new keyframe
  /// (> 0). Default 1.0.
  double proximity_max_norm = 1.0;
  /// Inliers a loop closure needs (≥ 4). Default 40.
  std::size_t loop_min_inliers = 40;
  /// A loop whose motion norm exceeds this is refused (0 disables).
  /// Default 5 (the tutorial's max_norm_lp).
  double loop_max_norm = 5.0;

  /// Each accepted keyframe edge is also measured the other way round (the
  /// later keyframe's points in the earlier one's image) and added as a
  /// second edge: the two measurements use the depth of different frames.
  /// Default true; the tutorial's false.
  bool symmetric_edges = true;
  /// Huber kernel's δ on the pose graph's edges (whitened units, > 0).
  /// Default 10: PnP's covariance is optimistic (pixel noise only), and a
  /// δ of 2 down-weighted good edges (ATE 3.0 cm against 2.6 on fr1/rpy).
  double huber_delta = 10.0;
  /// Standard deviations floored into an edge's covariance (meters and
  /// radians, ≥ 0): PnP's covariance reflects only pixel noise, not depth
  /// bias. Defaults 2 mm and 0.002 rad.
  double edge_min_sigma_translation = 0.002;
  double edge_min_sigma_rotation = 0.002;
  /// Geometric edges: each keyframe edge and accepted loop closure is also
  /// measured by GICP between the two keyframes' clouds (voxel filtered
  /// with leaf `icp_voxel` meters), started at the PnP estimate, and added
  /// as a further edge (its covariance floored as above) when GICP
  /// converged, paired at least `icp_min_pairing` of the points within
  /// `icp_max_distance` meters, and moved the estimate by a motion norm of
  /// at most `icp_max_correction`. Depth then constrains the graph beside
  /// the features' pixels. 0 for icp_voxel turns it off. Defaults 0.03
  /// (0.02 is a little more accurate on TUM fr1/rpy but costs twice the
  /// time), 0.1, 0.5, 0.1; the tutorial's off.
  double icp_voxel = 0.03;
  double icp_max_distance = 0.1;
  double icp_min_pairing = 0.5;
  double icp_max_correction = 0.1;

  /// Rolling shutter: seconds from reading the image's first row to its
  /// last (≥ 0; 0: a global shutter). Each keypoint (and its depth point)
  /// is carried from its row's time to the middle row's by the camera's
  /// turn at the angular velocity of the last two tracked frames. Unset:
  /// the sequence's camera's (RgbdSequence::rolling_shutter_readout, set
  /// by for_sequence in rgbd_slam_run.h; "tum-fr1": 0.02), and 0 for
  /// RgbdSlam used alone. The tutorial's 0.
  std::optional<double> rolling_shutter_readout;
  /// Bundle adjustment at the end of the run (RgbdSlam::finish,
  /// rove/graph/bundle_adjustment.h): the keyframes' features that PnP
  /// paired (tracking, the edges both ways, loop closures) are joined into
  /// tracks, each a 3D point seen by several keyframes, and the keyframes'
  /// poses and the points are adjusted together on the keypoints' pixels
  /// (σ = 1.2^octave px) and their depths (as inverse depth, σ
  /// `ba_inverse_depth_sigma` 1/m), with the geometric (GICP) edges and the
  /// weak edges as relative-pose terms. Default false: on TUM fr1/rpy it
  /// left the keyframes' ATE where the pose graph had it (2.52 against
  /// 2.49 cm) and made the frames between them worse (2.83 against 2.40 cm).
  bool bundle_adjustment = false;
  /// Standard deviation of a feature's measured inverse depth, 1/m (> 0).
  /// Default 0.01: σ_z = 0.01·z², 1 cm at 1 m, 4 cm at 2 m.
  double ba_inverse_depth_sigma = 0.01;
  /// Levenberg–Marquardt iterations per round of the bundle adjustment
  /// (≥ 1; two rounds, outliers dropped between). Default 20.
  int ba_iterations = 20;

  /// The map: each keyframe's cloud with this pixel stride (≥ 1), voxel
  /// filtered with leaf `voxel_grid` meters (> 0). Defaults 2 and 0.01 (the
  /// tutorial's voxel_grid).
  std::uint32_t map_stride = 2;
  double voxel_grid = 0.01;
  /// Largest depth of map points, meters (> 0). Default 4.
  double map_max_depth = 4.0;
  /// The occupancy octree map (RgbdSlam::map_octree): edge of its finest
  /// cells, meters (≥ 0; 0: no octree). Default 0.05.
  double octree_resolution = 0.05;
  /// Threads inserting the keyframes' clouds into the octree (1–256, 0: every
  /// hardware thread); the octree does not depend on the number. Default 1.
  int octree_threads = 1;

  /// Seed of the random loop candidates and of RANSAC.
  std::uint64_t seed = 42;

  /// The RGB-D SLAM tutorial's values: ORB, good_match_threshold 10 (on
  /// brute-force matches without ratio test or cross check, no guided
  /// search), min_inliers 5, max_norm 0.2, keyframe_threshold 0.1,
  /// nearby_loops 5, random_loops 5, no proximity loops, max_norm_lp 5,
  /// voxel_grid 0.01.
  static RgbdSlamOptions tutorial();

  /// Reads a section: `preset` (`default` or `tutorial`) picks the starting
  /// values, then the tutorial's names (detector = ORB, descriptor = ORB,
  /// good_match_threshold, min_good_match, min_inliers, max_norm,
  /// keyframe_threshold, max_norm_lp, check_loop_closure, nearby_loops,
  /// random_loops, voxel_grid) and rove's own (max_features,
  /// fast_threshold, ratio, cross_check, guided_radius_px,
  /// guided_max_distance, reprojection_threshold_px, ransac_iterations,
  /// keyframe_min_inliers, proximity_loops, proximity_max_norm,
  /// loop_min_inliers, huber_delta, icp_voxel, icp_max_distance,
  /// icp_min_pairing, icp_max_correction, bundle_adjustment,
  /// ba_inverse_depth_sigma, ba_iterations, min_depth, max_depth, map_stride,
  /// map_max_depth, octree_resolution, octree_threads, seed). The tutorial's camera.* keys, and its file and
  /// display keys, are accepted and ignored (the camera comes from the
  /// sequence). Throws ConfigError naming the key for a bad value or an
  /// unknown preset or detector.
  static RgbdSlamOptions from_config(const ConfigSection& section);

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// The tutorial's motion norm of a relative pose (see RgbdSlamOptions).
double motion_norm(const SE3d& T);

}  // namespace rove
