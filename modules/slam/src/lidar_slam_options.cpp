#include "rove/slam/lidar_slam_options.h"

#include <cmath>
#include <numbers>
#include <string>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/parallel.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Degrees in the file, radians in the options.
double get_degrees(const ConfigSection& s, std::string_view key, double fallback_rad, double lo_deg,
                   double hi_deg) {
  return s.get_in_range(key, fallback_rad / kDeg, lo_deg, hi_deg) * kDeg;
}

int get_int(const ConfigSection& s, std::string_view key, int fallback, int lo, int hi) {
  const double v = s.get_in_range(key, fallback, lo, hi);
  if (v != std::floor(v)) s.fail(key, "must be a whole number");
  return static_cast<int>(v);
}

void check_positive(double v, const char* name) {
  ROVE_CHECK_MSG(std::isfinite(v) && v > 0.0, "{} = {} must be finite and > 0", name, v);
}

}  // namespace

void LidarFrontEndOptions::check() const {
  scan.check();
  matching_filter.check();
  matcher.check();
  ROVE_CHECK_MSG(icp_rebuild_every >= 1, "icp_rebuild_every {} must be >= 1", icp_rebuild_every);
  check_positive(icp_gate, "icp_gate");
  ROVE_CHECK_MSG(icp_remap_threshold > 0.0 && icp_remap_threshold < 1.0,
                 "icp_remap_threshold {} must lie in (0, 1)", icp_remap_threshold);
  correlative_window.check();
  ROVE_CHECK_MSG(correlative_min_turn >= 0.0, "correlative_min_turn {} must be >= 0",
                 correlative_min_turn);
  ROVE_CHECK_MSG(std::isfinite(motion_filter_distance) && motion_filter_distance >= 0.0,
                 "motion_filter_distance {} must be >= 0", motion_filter_distance);
  ROVE_CHECK_MSG(std::isfinite(motion_filter_angle) && motion_filter_angle >= 0.0,
                 "motion_filter_angle {} must be >= 0", motion_filter_angle);
  ROVE_CHECK_MSG(motion_filter_time >= 0.0, "motion_filter_time {} must be >= 0",
                 motion_filter_time);
}

LidarFrontEndOptions LidarFrontEndOptions::from_config(const ConfigSection& s) {
  LidarFrontEndOptions o;
  o.scan = ScanPointsOptions::from_config(s);
  o.matching_filter = AdaptiveVoxelFilterOptions::from_config(s, "matching_", o.matching_filter);
  o.matcher = GridScanMatcherOptions::from_config(s, "", o.matcher);
  o.correlative_window.linear_window = s.get_in_range(
      "correlative_linear_window", o.correlative_window.linear_window, 0.0, 10.0);
  o.correlative_window.angular_window = get_degrees(
      s, "correlative_angular_window", o.correlative_window.angular_window, 0.0, 180.0);
  o.correlative_window.angular_step = get_degrees(
      s, "correlative_angular_step", o.correlative_window.angular_step, 1e-3, 90.0);
  o.correlative_min_turn = get_degrees(s, "correlative_min_turn", o.correlative_min_turn, 0.0, 360.0);
  o.grid_match = s.get<bool>("grid_match", o.grid_match);
  o.icp_refine = s.get<bool>("icp_refine", o.icp_refine);
  o.icp_rebuild_every = get_int(s, "icp_rebuild_every", o.icp_rebuild_every, 1, 100000);
  o.icp_gate = s.get_in_range("icp_gate", o.icp_gate, 1e-3, 100.0);
  o.icp_remap_threshold = s.get_in_range("icp_remap_threshold", o.icp_remap_threshold, 1e-6, 0.999);
  o.use_odometry = s.get<bool>("use_odometry", o.use_odometry);
  o.motion_filter_distance =
      s.get_in_range("motion_filter_distance", o.motion_filter_distance, 0.0, 1e6);
  o.motion_filter_angle = get_degrees(s, "motion_filter_angle", o.motion_filter_angle, 0.0, 360.0);
  o.motion_filter_time = s.get_in_range("motion_filter_time", o.motion_filter_time, 0.0, 1e9);
  s.check_all_read();
  return o;
}

void LidarSubmapOptions::check() const {
  check_positive(resolution, "resolution");
  ROVE_CHECK_MSG(scans_per_submap >= 1, "scans_per_submap {} must be >= 1", scans_per_submap);
  odds.check();
}

LidarSubmapOptions LidarSubmapOptions::from_config(const ConfigSection& s) {
  LidarSubmapOptions o;
  o.resolution = s.get_in_range("resolution", o.resolution, 1e-3, 10.0);
  o.scans_per_submap = get_int(s, "scans_per_submap", o.scans_per_submap, 1, 1000000);
  o.odds = GridInsertionOdds::from_config(s);
  s.check_all_read();
  return o;
}

void LidarLoopClosureOptions::check() const {
  ROVE_CHECK_MSG(sampling_ratio > 0.0 && sampling_ratio <= 1.0,
                 "sampling_ratio {} must lie in (0, 1]", sampling_ratio);
  ROVE_CHECK_MSG(std::isfinite(max_distance) && max_distance >= 0.0, "max_distance {} must be >= 0",
                 max_distance);
  ROVE_CHECK_MSG(max_submaps_per_node >= 1, "max_submaps_per_node {} must be >= 1",
                 max_submaps_per_node);
  window.check();
  ROVE_CHECK_MSG(depth >= 0 && depth <= 16, "branch_and_bound_depth {} must lie in [0, 16]", depth);
  ROVE_CHECK_MSG(min_score > ProbabilityGrid::kMinProbability &&
                     min_score < ProbabilityGrid::kMaxProbability,
                 "min_score {} must lie in (0.1, 0.9)", min_score);
  ROVE_CHECK_MSG(min_score_margin >= 0.0 && min_score_margin <= 0.8,
                 "min_score_margin {} must lie in [0, 0.8]", min_score_margin);
  check_positive(ambiguity_radius, "ambiguity_radius");
  filter.check();
  refine.check();
  check_positive(verify_max_translation, "verify_max_translation");
  check_positive(verify_max_rotation, "verify_max_rotation");
  ROVE_CHECK_MSG(verify_min_goodness >= 0.0 && verify_min_goodness <= 1.0,
                 "verify_min_goodness {} must lie in [0, 1]", verify_min_goodness);
  ROVE_CHECK_MSG(min_agreeing >= 1, "min_agreeing {} must be >= 1", min_agreeing);
  ROVE_CHECK_MSG(agreement_nodes >= 0, "agreement_nodes {} must be >= 0", agreement_nodes);
  check_positive(agreement_translation, "agreement_translation");
  check_positive(agreement_rotation, "agreement_rotation");
  check_positive(translation_sigma, "loop_closure translation_sigma");
  check_positive(rotation_sigma, "loop_closure rotation_sigma");
  check_positive(huber_delta, "huber_delta");
}

LidarLoopClosureOptions LidarLoopClosureOptions::from_config(const ConfigSection& s) {
  LidarLoopClosureOptions o;
  o.enabled = s.get<bool>("enabled", o.enabled);
  o.sampling_ratio = s.get_in_range("sampling_ratio", o.sampling_ratio, 1e-6, 1.0);
  o.max_distance = s.get_in_range("max_distance", o.max_distance, 0.0, 1e6);
  o.max_submaps_per_node = get_int(s, "max_submaps_per_node", o.max_submaps_per_node, 1, 1000000);
  o.window.linear = s.get_in_range("linear_search_window", o.window.linear, 0.0, 1000.0);
  o.window.angular = get_degrees(s, "angular_search_window", o.window.angular, 0.0, 180.0);
  o.window.step_range_cap =
      s.get_in_range("angular_step_range", o.window.step_range_cap, 0.1, 1e6);
  o.depth = get_int(s, "branch_and_bound_depth", o.depth, 0, 16);
  o.min_score = s.get_in_range("min_score", o.min_score, 0.1, 0.9);
  if (!(o.min_score > 0.1 && o.min_score < 0.9)) {
    s.fail("min_score", "must lie strictly between 0.1 and 0.9 (the grid's probability range)");
  }
  o.min_score_margin = s.get_in_range("min_score_margin", o.min_score_margin, 0.0, 0.8);
  o.ambiguity_radius = s.get_in_range("ambiguity_radius", o.ambiguity_radius, 1e-3, 1e3);
  o.filter = AdaptiveVoxelFilterOptions::from_config(s, "", o.filter);
  o.refine = GridScanMatcherOptions::from_config(s, "refine_", o.refine);
  o.verify_with_icp = s.get<bool>("verify_with_icp", o.verify_with_icp);
  o.verify_max_translation =
      s.get_in_range("verify_max_translation", o.verify_max_translation, 1e-6, 1e3);
  o.verify_max_rotation = get_degrees(s, "verify_max_rotation", o.verify_max_rotation, 1e-6, 180.0);
  o.verify_min_goodness = s.get_in_range("verify_min_goodness", o.verify_min_goodness, 0.0, 1.0);
  o.min_agreeing = get_int(s, "min_agreeing", o.min_agreeing, 1, 1000);
  o.agreement_nodes = get_int(s, "agreement_nodes", o.agreement_nodes, 0, 100000000);
  o.agreement_translation =
      s.get_in_range("agreement_translation", o.agreement_translation, 1e-6, 1e6);
  o.agreement_rotation = get_degrees(s, "agreement_rotation", o.agreement_rotation, 1e-6, 360.0);
  o.translation_sigma = s.get_in_range("translation_sigma", o.translation_sigma, 1e-9, 1e6);
  o.rotation_sigma = get_degrees(s, "rotation_sigma", o.rotation_sigma, 1e-9, 360.0);
  o.huber_delta = s.get_in_range("huber_delta", o.huber_delta, 1e-9, 1e9);
  s.check_all_read();
  return o;
}

void LidarBackEndOptions::check() const {
  ROVE_CHECK_MSG(optimize_every_n_nodes >= 1, "optimize_every_n_nodes {} must be >= 1",
                 optimize_every_n_nodes);
  check_positive(translation_sigma, "backend translation_sigma");
  check_positive(rotation_sigma, "backend rotation_sigma");
  check_positive(submap_translation_sigma, "submap_translation_sigma");
  check_positive(submap_rotation_sigma, "submap_rotation_sigma");
  ROVE_CHECK_MSG(max_iterations >= 1, "max_iterations {} must be >= 1", max_iterations);
  ROVE_CHECK_MSG(scan_window >= 0 && scan_window <= 20, "scan_window {} must lie in [0, 20]",
                 scan_window);
  check_positive(scan_window_translation_sigma, "scan_window_translation_sigma");
  check_positive(scan_window_rotation_sigma, "scan_window_rotation_sigma");
  check_positive(scan_window_gate, "scan_window_gate");
  resolve_thread_count(num_threads, "[backend] num_threads");
}

LidarBackEndOptions LidarBackEndOptions::from_config(const ConfigSection& s) {
  LidarBackEndOptions o;
  o.optimize_every_n_nodes =
      get_int(s, "optimize_every_n_nodes", o.optimize_every_n_nodes, 1, 100000000);
  o.translation_sigma = s.get_in_range("translation_sigma", o.translation_sigma, 1e-9, 1e6);
  o.rotation_sigma = get_degrees(s, "rotation_sigma", o.rotation_sigma, 1e-9, 360.0);
  o.submap_translation_sigma =
      s.get_in_range("submap_translation_sigma", o.submap_translation_sigma, 1e-9, 1e6);
  o.submap_rotation_sigma =
      get_degrees(s, "submap_rotation_sigma", o.submap_rotation_sigma, 1e-9, 360.0);
  o.max_iterations = get_int(s, "max_iterations", o.max_iterations, 1, 100000);
  o.scan_window = get_int(s, "scan_window", o.scan_window, 0, 20);
  o.scan_window_translation_sigma = s.get_in_range(
      "scan_window_translation_sigma", o.scan_window_translation_sigma, 1e-9, 1e6);
  o.scan_window_rotation_sigma =
      get_degrees(s, "scan_window_rotation_sigma", o.scan_window_rotation_sigma, 1e-9, 360.0);
  o.scan_window_gate = s.get_in_range("scan_window_gate", o.scan_window_gate, 1e-3, 100.0);
  o.num_threads = get_int(s, "num_threads", o.num_threads, 0, kMaxThreads);
  s.check_all_read();
  return o;
}

void LidarSlamOptions::check() const {
  frontend.check();
  submaps.check();
  loop_closure.check();
  backend.check();
}

LidarSlamOptions load_lidar_slam_options(const IniFile& ini) {
  LidarSlamOptions o;
  o.frontend = LidarFrontEndOptions::from_config(ConfigSection(ini, "frontend"));
  o.submaps = LidarSubmapOptions::from_config(ConfigSection(ini, "submaps"));
  o.loop_closure = LidarLoopClosureOptions::from_config(ConfigSection(ini, "loop_closure"));
  o.backend = LidarBackEndOptions::from_config(ConfigSection(ini, "backend"));
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), "", "", e.message());
  }
  return o;
}

}  // namespace rove
