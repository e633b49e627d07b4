#include "rove/slam/rgbd_slam_options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <string>

#include "rove/core/check.h"
#include "rove/maps/occupancy_octree.h"

namespace rove {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::size_t get_count(const ConfigSection& s, std::string_view key, std::size_t fallback,
                      double lo, double hi) {
  const double v = s.get_in_range(key, static_cast<double>(fallback), lo, hi);
  if (v != std::floor(v)) s.fail(key, "expected a whole number");
  return static_cast<std::size_t>(v);
}

void read_features(const ConfigSection& s, RgbdSlamOptions& o) {
  for (const char* key : {"detector", "descriptor"}) {
    if (s.has(key)) {
      const std::string v = lower(s.get<std::string>(key, "orb"));
      if (v != "orb") s.fail(key, "only ORB is implemented (got '" + v + "')");
    }
  }
  o.orb.max_features = static_cast<int>(get_count(s, "max_features", static_cast<std::size_t>(o.orb.max_features), 10, 100000));
  o.orb.fast_threshold = static_cast<int>(get_count(s, "fast_threshold", static_cast<std::size_t>(o.orb.fast_threshold), 1, 254));
  o.match.relative_factor = s.get_in_range("good_match_threshold", o.match.relative_factor, 0.0, 1e6);
  o.match.ratio = s.get_in_range("ratio", o.match.ratio, 0.0, 1.0);
  o.match.cross_check = s.get<bool>("cross_check", o.match.cross_check);
  o.min_matches = get_count(s, "min_good_match", o.min_matches, 0, 1e9);
  o.guided_radius_px = s.get_in_range("guided_radius_px", o.guided_radius_px, 0.0, 1e4);
  o.guided_max_distance = static_cast<std::uint32_t>(get_count(s, "guided_max_distance", o.guided_max_distance, 0, 256));
  o.refine_radius_px = s.get_in_range("refine_radius_px", o.refine_radius_px, 0.0, 1e4);
  o.min_depth = s.get_in_range("min_depth", o.min_depth, 0.0, 1e3);
  o.max_depth = s.get_in_range("max_depth", o.max_depth, 1e-3, 1e3);
  o.depth_edge_radius = static_cast<int>(get_count(s, "depth_edge_radius", static_cast<std::size_t>(o.depth_edge_radius), 0, 100));
  o.depth_edge_step = s.get_in_range("depth_edge_step", o.depth_edge_step, 0.0, 1e3);
}

void read_tracking(const ConfigSection& s, RgbdSlamOptions& o) {
  o.pnp.reprojection_threshold_px = s.get_in_range("reprojection_threshold_px", o.pnp.reprojection_threshold_px, 1e-3, 1e3);
  o.pnp.max_iterations = get_count(s, "ransac_iterations", o.pnp.max_iterations, 1, 1e7);
  o.min_inliers = get_count(s, "min_inliers", o.min_inliers, 4, 1e9);
  o.max_norm = s.get_in_range("max_norm", o.max_norm, 0.0, 1e6);
  o.keyframe_threshold = s.get_in_range("keyframe_threshold", o.keyframe_threshold, 1e-6, 1e6);
  o.keyframe_min_inliers = get_count(s, "keyframe_min_inliers", o.keyframe_min_inliers, 0, 1e9);
}

void read_loops(const ConfigSection& s, RgbdSlamOptions& o) {
  const bool check_loops = s.get<bool>("check_loop_closure", true);
  o.nearby_loops = get_count(s, "nearby_loops", o.nearby_loops, 0, 1e6);
  o.random_loops = get_count(s, "random_loops", o.random_loops, 0, 1e6);
  o.proximity_loops = get_count(s, "proximity_loops", o.proximity_loops, 0, 1e6);
  o.appearance_loops = get_count(s, "appearance_loops", o.appearance_loops, 0, 1e6);
  o.appearance_min_score = s.get_in_range("appearance_min_score", o.appearance_min_score, 0.0, 1.0);
  if (!check_loops) o.nearby_loops = o.random_loops = o.proximity_loops = o.appearance_loops = 0;
  o.proximity_max_norm = s.get_in_range("proximity_max_norm", o.proximity_max_norm, 1e-6, 1e6);
  o.loop_min_inliers = get_count(s, "loop_min_inliers", o.loop_min_inliers, 4, 1e9);
  o.loop_max_norm = s.get_in_range("max_norm_lp", o.loop_max_norm, 0.0, 1e6);
  o.symmetric_edges = s.get<bool>("symmetric_edges", o.symmetric_edges);
  o.huber_delta = s.get_in_range("huber_delta", o.huber_delta, 1e-6, 1e6);
  o.icp_voxel = s.get_in_range("icp_voxel", o.icp_voxel, 0.0, 10.0);
  o.icp_max_distance = s.get_in_range("icp_max_distance", o.icp_max_distance, 1e-4, 10.0);
  o.icp_min_pairing = s.get_in_range("icp_min_pairing", o.icp_min_pairing, 0.0, 1.0);
  o.icp_max_correction = s.get_in_range("icp_max_correction", o.icp_max_correction, 0.0, 1e3);
  if (s.has("rolling_shutter_readout")) {
    o.rolling_shutter_readout = s.get_in_range("rolling_shutter_readout", 0.0, 0.0, 1.0);
  }
  o.bundle_adjustment = s.get<bool>("bundle_adjustment", o.bundle_adjustment);
  o.ba_inverse_depth_sigma = s.get_in_range("ba_inverse_depth_sigma", o.ba_inverse_depth_sigma, 1e-6, 1e3);
  o.ba_iterations = static_cast<int>(get_count(s, "ba_iterations", static_cast<std::size_t>(o.ba_iterations), 1, 10000));
  o.voxel_grid = s.get_in_range("voxel_grid", o.voxel_grid, 1e-4, 1e3);
  o.map_stride = static_cast<std::uint32_t>(get_count(s, "map_stride", o.map_stride, 1, 1000));
  o.map_max_depth = s.get_in_range("map_max_depth", o.map_max_depth, 1e-3, 1e3);
  o.octree_resolution = s.get_in_range("octree_resolution", o.octree_resolution, 0.0, 1e3);
  o.octree_threads = static_cast<int>(get_count(s, "octree_threads", static_cast<std::size_t>(o.octree_threads), 0, 256));
  o.seed = static_cast<std::uint64_t>(get_count(s, "seed", static_cast<std::size_t>(o.seed), 0, 9e15));
}

}  // namespace

double motion_norm(const SE3d& T) {
  const double angle = T.rotation().log().norm();
  return std::min(angle, 2.0 * std::numbers::pi - angle) + T.translation().norm();
}

RgbdSlamOptions RgbdSlamOptions::tutorial() {
  RgbdSlamOptions o;
  o.orb.max_features = 500;  // OpenCV's ORB default, which the tutorial used
  o.match.ratio = 0.0;
  o.match.cross_check = false;
  o.match.max_distance = 256;
  o.match.relative_factor = 10.0;
  o.min_matches = 10;
  o.guided_radius_px = 0.0;
  o.refine_radius_px = 0.0;
  o.pnp.reprojection_threshold_px = 1.0;  // its solvePnPRansac call: 100 samples, 1 px
  o.pnp.max_iterations = 100;
  o.min_inliers = 5;
  o.max_norm = 0.2;
  o.keyframe_threshold = 0.1;
  o.keyframe_min_inliers = 0;
  o.nearby_loops = 5;
  o.random_loops = 5;
  o.proximity_loops = 0;
  o.appearance_loops = 0;
  o.loop_min_inliers = 5;
  o.loop_max_norm = 5.0;
  o.symmetric_edges = false;
  o.icp_voxel = 0.0;
  o.rolling_shutter_readout = 0.0;
  o.depth_edge_step = 0.0;
  o.voxel_grid = 0.01;
  return o;
}

RgbdSlamOptions RgbdSlamOptions::from_config(const ConfigSection& s) {
  RgbdSlamOptions o;
  if (s.has("preset")) {
    const std::string p = lower(s.get<std::string>("preset", "default"));
    if (p == "tutorial") {
      o = tutorial();
    } else if (p != "default") {
      s.fail("preset", "expected 'default' or 'tutorial', got '" + p + "'");
    }
  }
  read_features(s, o);
  read_tracking(s, o);
  read_loops(s, o);
  s.ignore_prefix("camera.", "the camera comes from the sequence (its camera file or --camera)");
  s.ignore({"start_index", "end_index", "rgb_dir", "rgb_extension", "depth_dir", "depth_extension",
            "visualize_pointcloud"},
           "the tutorial's file and display settings: the frames come from the sequence folder");
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    s.fail("", e.what());
  }
  return o;
}

void RgbdSlamOptions::check() const {
  orb.check();
  match.check();
  ROVE_CHECK_MSG(std::isfinite(min_depth) && min_depth >= 0.0 && std::isfinite(max_depth) &&
                     max_depth > min_depth,
                 "need 0 <= min_depth < max_depth, got {} and {}", min_depth, max_depth);
  ROVE_CHECK_MSG(depth_edge_radius >= 0 && std::isfinite(depth_edge_step) && depth_edge_step >= 0.0,
                 "need depth_edge_radius >= 0 and depth_edge_step >= 0, got {} and {}",
                 depth_edge_radius, depth_edge_step);
  ROVE_CHECK_MSG(std::isfinite(guided_radius_px) && guided_radius_px >= 0.0,
                 "guided_radius_px must be finite and >= 0, got {}", guided_radius_px);
  ROVE_CHECK_MSG(std::isfinite(refine_radius_px) && refine_radius_px >= 0.0,
                 "refine_radius_px must be finite and >= 0, got {}", refine_radius_px);
  ROVE_CHECK_MSG(guided_max_distance <= 256, "guided_max_distance must be <= 256, got {}",
                 guided_max_distance);
  ROVE_CHECK_MSG(min_inliers >= 4, "min_inliers must be >= 4, got {}", min_inliers);
  ROVE_CHECK_MSG(loop_min_inliers >= 4, "loop_min_inliers must be >= 4, got {}", loop_min_inliers);
  ROVE_CHECK_MSG(std::isfinite(max_norm) && max_norm >= 0.0, "max_norm must be >= 0, got {}", max_norm);
  ROVE_CHECK_MSG(std::isfinite(loop_max_norm) && loop_max_norm >= 0.0,
                 "loop_max_norm must be >= 0, got {}", loop_max_norm);
  ROVE_CHECK_MSG(std::isfinite(keyframe_threshold) && keyframe_threshold > 0.0,
                 "keyframe_threshold must be > 0, got {}", keyframe_threshold);
  ROVE_CHECK_MSG(std::isfinite(proximity_max_norm) && proximity_max_norm > 0.0,
                 "proximity_max_norm must be > 0, got {}", proximity_max_norm);
  ROVE_CHECK_MSG(std::isfinite(huber_delta) && huber_delta > 0.0, "huber_delta must be > 0, got {}",
                 huber_delta);
  ROVE_CHECK_MSG(std::isfinite(edge_min_sigma_translation) && edge_min_sigma_translation >= 0.0 &&
                     std::isfinite(edge_min_sigma_rotation) && edge_min_sigma_rotation >= 0.0,
                 "edge_min_sigma_translation and _rotation must be >= 0, got {} and {}",
                 edge_min_sigma_translation, edge_min_sigma_rotation);
  ROVE_CHECK_MSG(std::isfinite(icp_voxel) && icp_voxel >= 0.0, "icp_voxel must be >= 0, got {}", icp_voxel);
  ROVE_CHECK_MSG(std::isfinite(icp_max_distance) && icp_max_distance > 0.0,
                 "icp_max_distance must be > 0, got {}", icp_max_distance);
  ROVE_CHECK_MSG(icp_min_pairing >= 0.0 && icp_min_pairing <= 1.0, "icp_min_pairing must be in [0, 1], got {}",
                 icp_min_pairing);
  ROVE_CHECK_MSG(std::isfinite(icp_max_correction) && icp_max_correction >= 0.0,
                 "icp_max_correction must be >= 0, got {}", icp_max_correction);
  ROVE_CHECK_MSG(std::isfinite(ba_inverse_depth_sigma) && ba_inverse_depth_sigma > 0.0,
                 "ba_inverse_depth_sigma must be > 0, got {}", ba_inverse_depth_sigma);
  ROVE_CHECK_MSG(ba_iterations >= 1, "ba_iterations must be >= 1, got {}", ba_iterations);
  ROVE_CHECK_MSG(!rolling_shutter_readout || (std::isfinite(*rolling_shutter_readout) &&
                                               *rolling_shutter_readout >= 0.0 && *rolling_shutter_readout <= 1.0),
                 "rolling_shutter_readout must be in [0, 1] s, got {}", rolling_shutter_readout.value_or(0.0));
  ROVE_CHECK_MSG(map_stride >= 1, "map_stride must be >= 1, got {}", map_stride);
  ROVE_CHECK_MSG(std::isfinite(voxel_grid) && voxel_grid > 0.0, "voxel_grid must be > 0, got {}", voxel_grid);
  ROVE_CHECK_MSG(std::isfinite(map_max_depth) && map_max_depth > 0.0,
                 "map_max_depth must be > 0, got {}", map_max_depth);
  ROVE_CHECK_MSG(octree_resolution == 0.0 || octree_resolution_valid(octree_resolution),
                 "octree_resolution must be 0 (no octree) or a valid octree resolution > 0, got {}",
                 octree_resolution);
  ROVE_CHECK_MSG(octree_threads >= 0 && octree_threads <= 256, "octree_threads must be in 0..256, got {}",
                 octree_threads);
  PnpOptions p = pnp;
  p.min_inliers = std::min(min_inliers, loop_min_inliers);
  p.check();
}

}  // namespace rove
