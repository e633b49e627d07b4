#pragma once
// Internals of the RGB-D SLAM pipeline: a frame's features with their 3D
// points, guided and brute-force matching, and PnP between two frames.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "rove/math/se3.h"
#include "rove/obs/pinhole_camera.h"
#include "rove/slam/rgbd_slam_options.h"
#include "rove/vision/binary_matching.h"
#include "rove/vision/orb.h"
#include "rove/vision/pnp.h"
#include "rove/vision/rgbd_frame.h"

namespace rove::detail {

// ORB features of one frame, the 3D point of each where the depth image has
// one, and a grid of the keypoints for guided search.
struct FrameFeatures {
  std::vector<Keypoint> keypoints;
  std::vector<OrbDescriptor> descriptors;
  // Camera-frame points, meters; NaN where the depth has no value in range.
  std::vector<Eigen::Vector3d> points;
  // The image's size, and, with a rolling shutter, the keypoints and points
  // as extracted (before correct_rolling_shutter).
  std::uint32_t width = 0, height = 0;
  std::vector<Keypoint> raw_keypoints;
  std::vector<Eigen::Vector3d> raw_points;
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();  // rad/s, of the last correction
  // The features with a point: their descriptors and indices.
  std::vector<OrbDescriptor> descriptors3d;
  std::vector<std::uint32_t> index3d;
  // Keypoints by grid cell (cell_start has cells + 1 entries).
  double cell_size = 32.0;
  int grid_cols = 0, grid_rows = 0;
  std::vector<std::uint32_t> cell_start, cell_items;
};

// Extracts and describes the features of a frame. With a rolling shutter
// (options.rolling_shutter_readout > 0) and the camera turning at
// `omega` (rad/s, camera frame), each keypoint and its point are carried
// from its row's time to the image's middle row's.
FrameFeatures describe_frame(const RgbdFrame& frame, const PinholeCamera& camera,
                             const RgbdSlamOptions& options,
                             const Eigen::Vector3d& omega = Eigen::Vector3d::Zero());

// Carries each keypoint and its point from its row's time to the middle
// row's, the camera turning at `omega` (rad/s, camera frame), from the
// extracted ones (a second call replaces the first's correction).
void correct_rolling_shutter(FrameFeatures& f, const PinholeCamera& camera, const RgbdSlamOptions& options,
                             const Eigen::Vector3d& omega);

// Guided matching: each point of `ref` mapped by T_cur_ref and projected,
// matched to the keypoints of `cur` within `radius_px` (best Hamming
// distance ≤ max_distance, below ratio × the second best when ratio > 0),
// one match per keypoint of `cur` (the smallest distance). query = index in
// ref, train = index in cur.
std::vector<DescriptorMatch> match_guided(const FrameFeatures& ref, const FrameFeatures& cur,
                                          const SE3d& T_cur_ref, const PinholeCamera& camera,
                                          double radius_px, std::uint32_t max_distance, double ratio);

// Brute-force matching of ref's features with points against all of cur's;
// query = index in ref, train = index in cur.
std::vector<DescriptorMatch> match_brute_force(const FrameFeatures& ref, const FrameFeatures& cur,
                                               const BinaryMatchOptions& options);

// PnP on ref's points and cur's pixels of the matches: T_cur_ref.
PnpResult solve_frame_pnp(const FrameFeatures& ref, const FrameFeatures& cur,
                          const std::vector<DescriptorMatch>& matches, const PinholeCamera& camera,
                          const PnpOptions& options);

// The matches PnP kept as inliers: `matches` filtered as solve_frame_pnp
// filters them (ref points with depth), indexed by pnp.inliers.
std::vector<DescriptorMatch> pnp_inlier_matches(const FrameFeatures& ref,
                                                const std::vector<DescriptorMatch>& matches,
                                                const PnpResult& pnp);

// Covariance of T⁻¹ over its right tangent from the covariance of T over
// its right tangent: T⁻¹ = T̂⁻¹·exp(−Ad(T̂)·ξ).
Eigen::Matrix<double, 6, 6> inverse_covariance(const SE3d& T,
                                               const Eigen::Matrix<double, 6, 6>& covariance);

// A measurement's covariance over the right tangent (ρ, ω), symmetrized,
// with the given standard deviations added to its diagonal.
Eigen::Matrix<double, 6, 6> floored_covariance(const Eigen::Matrix<double, 6, 6>& covariance,
                                               double min_sigma_translation, double min_sigma_rotation);

// Information of a pose-graph edge (error [t_E; q_E.xyz], pose_graph.h)
// from a measurement's covariance over the right tangent (ρ, ω), floored by
// the given standard deviations: near zero, t_E ≈ ρ and q_E.xyz ≈ ω/2.
Eigen::Matrix<double, 6, 6> edge_information(const Eigen::Matrix<double, 6, 6>& covariance,
                                             double min_sigma_translation,
                                             double min_sigma_rotation);

}  // namespace rove::detail
