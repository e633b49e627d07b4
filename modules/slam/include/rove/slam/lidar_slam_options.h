#pragma once
/// \file
/// Options of lidar SLAM (lidar_slam.h) and their INI loader. Each group of
/// options is one section of the file; keys are snake_case, angles are in
/// degrees in the file and radians here, lengths in meters, times in
/// seconds. docs/lidar-slam.md lists every key with its default.

#include <cstddef>
#include <vector>

#include "rove/core/config_section.h"
#include "rove/core/ini.h"
#include "rove/slam/branch_and_bound_2d.h"
#include "rove/slam/grid_scan_matcher.h"
#include "rove/slam/probability_grid.h"
#include "rove/slam/scan_points_2d.h"

namespace rove {

/// [frontend]: scan preprocessing, scan-to-submap matching, motion filter.
struct LidarFrontEndOptions {
  /// (min_range, max_range, voxel_size) the returns kept.
  ScanPointsOptions scan;
  /// (matching_max_length, matching_min_num_points, matching_max_range) the
  /// points matched against the submap. Defaults 0.5 m, 200, 50 m.
  AdaptiveVoxelFilterOptions matching_filter;
  /// (occupied_space_weight, translation_weight, rotation_weight,
  /// max_iterations) the scan-to-submap matcher. Defaults 1, 10, 40, 20.
  GridScanMatcherOptions matcher;
  /// (correlative_linear_window, correlative_angular_window and
  /// correlative_angular_step in degrees, correlative_min_turn in degrees)
  /// when the predicted turn since the last scan is at least
  /// correlative_min_turn, the matching starts from the best pose of an
  /// exhaustive search of this window around the prediction
  /// (correlative_search_2d): turning fast, the odometry and the scans of
  /// a log are often out of step by several degrees. An angular window of 0
  /// disables it. Rotation only by default: in a corridor the translation
  /// of the best score is a guess. Defaults 0 m, 15°, 0.5°, 2°.
  CorrelativeSearchOptions correlative_window;
  double correlative_min_turn = 2.0 * 3.14159265358979323846 / 180.0;
  /// (grid_match) match each scan against the older active submap's grid
  /// (the robust first stage, with the odometry as a prior). Default true.
  bool grid_match = true;
  /// (icp_refine) refine each match by point-to-line ICP against the
  /// points of the matching submap's nodes. Default true.
  bool icp_refine = true;
  /// (icp_rebuild_every) that target (one point per cell) is rebuilt when
  /// the submap received this many nodes since (or another submap is
  /// matched), >= 1. Default 10.
  int icp_rebuild_every = 10;
  /// (icp_gate) ICP's initial pairing distance, meters, > 0: the grid
  /// match is that close; a wider gate lets ICP slide along a corridor to
  /// the next door frame. Default 0.1.
  double icp_gate = 0.1;
  /// (icp_remap_threshold) ICP's correction of the grid match is kept only
  /// along directions whose information is at least this share of the
  /// largest (solution remapping, lidar_icp.h): along a corridor the
  /// pose stays with the odometry's prediction. In (0, 1). Default 0.02.
  double icp_remap_threshold = 0.02;
  /// (use_odometry) predict each scan's pose from the odometry of the log
  /// when it has some; otherwise, and when false, from the motion of the
  /// last two scans (constant velocity). Default true.
  bool use_odometry = true;
  /// (motion_filter_distance, motion_filter_angle in degrees,
  /// motion_filter_time) a scan becomes a node of the map (is inserted in
  /// the submaps and the pose graph) when the robot moved at least this far
  /// or turned this much since the last node, or this much time passed.
  /// Defaults 0.2 m, 1°, 5 s.
  double motion_filter_distance = 0.2;
  double motion_filter_angle = 1.0 * 3.14159265358979323846 / 180.0;
  double motion_filter_time = 5.0;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The [frontend] keys over the defaults; ConfigError (file, section,
  /// key) for a malformed or out-of-range value or an unknown key.
  static LidarFrontEndOptions from_config(const ConfigSection& section);
};

/// [submaps]: the local maps scans are matched against.
struct LidarSubmapOptions {
  /// (resolution) cell side, meters, > 0. Default 0.05.
  double resolution = 0.05;
  /// (scans_per_submap) nodes a submap receives while it is the newest;
  /// it then receives as many again while a newer one starts, and is
  /// finished: every node lies in two submaps. >= 1. Default 90.
  int scans_per_submap = 90;
  /// (hit_probability, miss_probability, insert_free_space) the odds update.
  GridInsertionOdds odds;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The [submaps] keys over the defaults (strict, as above).
  static LidarSubmapOptions from_config(const ConfigSection& section);
};

/// [loop_closure]: constraints between new nodes and finished submaps.
struct LidarLoopClosureOptions {
  /// (enabled) search for loop closures at all. Default true.
  bool enabled = true;
  /// (sampling_ratio) share of the nodes searched against each submap, in
  /// (0, 1]. Default 0.3.
  double sampling_ratio = 0.3;
  /// (max_distance) a node is searched against finished submaps whose
  /// origin lies this close (meters, current estimate). Default 15.
  double max_distance = 15.0;
  /// (max_submaps_per_node) at most this many submaps, the nearest first,
  /// per node, >= 1. Default 4.
  int max_submaps_per_node = 4;
  /// (linear_search_window, angular_search_window in degrees) half-widths
  /// of the branch-and-bound window around the current estimate;
  /// (angular_step_range) the range its angular step is computed for
  /// (BranchAndBoundWindow::step_range_cap). Defaults 4 m, 20°, 10 m.
  BranchAndBoundWindow window{4.0, 20.0 * 3.14159265358979323846 / 180.0, 10.0};
  /// (branch_and_bound_depth) height of the max grids, in [0, 16]. Default 7.
  int depth = 7;
  /// (min_score) the best pose's mean probability must exceed this, in
  /// (0.1, 0.9). Default 0.55.
  double min_score = 0.55;
  /// (min_score_margin, ambiguity_radius) the best pose must score this
  /// much more than the best pose of the window farther than
  /// ambiguity_radius meters from it: in a corridor, or along a row of
  /// identical rooms, the best pose is a guess. Margin in [0, 0.8], radius
  /// > 0. Defaults 0.1, 0.5 m.
  double min_score_margin = 0.1;
  double ambiguity_radius = 0.5;
  /// (max_length, min_num_points, max_range) the points searched.
  /// Defaults 0.9 m, 100, 50 m.
  AdaptiveVoxelFilterOptions filter{0.9, 100, 50.0};
  /// (refine_occupied_space_weight, refine_translation_weight,
  /// refine_rotation_weight, refine_max_iterations) refinement of the found
  /// pose against the submap. Defaults 20, 10, 1, 10.
  GridScanMatcherOptions refine{20.0, 10.0, 1.0, 10};
  /// (verify_with_icp) verify each constraint by point-to-point ICP of the
  /// node's points against the submap's points: it must converge within
  /// verify_max_translation / verify_max_rotation (degrees) of the refined
  /// pose with goodness >= verify_min_goodness. Defaults true, 0.1 m, 2°, 0.5.
  bool verify_with_icp = true;
  double verify_max_translation = 0.1;
  double verify_max_rotation = 2.0 * 3.14159265358979323846 / 180.0;
  double verify_min_goodness = 0.5;
  /// (min_agreeing, agreement_nodes, agreement_translation,
  /// agreement_rotation in degrees) a verified candidate becomes a
  /// constraint when, with it, at least min_agreeing candidates of nodes
  /// at most agreement_nodes apart, against submaps at most two apart,
  /// imply the same correction of the front-end's frame: the node moved by
  /// another's correction lands within agreement_translation and
  /// agreement_rotation of where its own puts it. One wrong match in a
  /// self-similar building rarely has company. Defaults 2, 100, 0.3 m, 2°.
  int min_agreeing = 2;
  int agreement_nodes = 100;
  double agreement_translation = 0.3;
  double agreement_rotation = 2.0 * 3.14159265358979323846 / 180.0;
  /// (translation_sigma, rotation_sigma in degrees) standard deviations of
  /// a loop-closure constraint. Defaults 0.01 m, 0.1°.
  double translation_sigma = 0.01;
  double rotation_sigma = 0.1 * 3.14159265358979323846 / 180.0;
  /// (huber_delta) Huber kernel of the loop-closure edges, in standard
  /// deviations (whitened units), > 0. Default 10.
  double huber_delta = 10.0;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The [loop_closure] keys over the defaults (strict, as above).
  static LidarLoopClosureOptions from_config(const ConfigSection& section);
};

/// [backend]: the pose graph of nodes and submaps.
struct LidarBackEndOptions {
  /// (optimize_every_n_nodes) optimize after this many new nodes when new
  /// loop closures arrived, >= 1. Default 90.
  int optimize_every_n_nodes = 90;
  /// (translation_sigma, rotation_sigma in degrees) standard deviations of
  /// the front-end's constraint between consecutive nodes. Defaults
  /// 0.01 m, 0.1°.
  double translation_sigma = 0.01;
  double rotation_sigma = 0.1 * 3.14159265358979323846 / 180.0;
  /// (submap_translation_sigma, submap_rotation_sigma in degrees) of the
  /// constraint between a node and each submap it was inserted into.
  /// Softer than the chain, so that a loop's correction spreads along the
  /// path rather than bending it where two submaps meet. Defaults 0.05 m,
  /// 0.5°.
  double submap_translation_sigma = 0.05;
  double submap_rotation_sigma = 0.5 * 3.14159265358979323846 / 180.0;
  /// (max_iterations) of each optimization, >= 1. Default 50.
  int max_iterations = 50;
  /// (scan_window) the final refinement at finish(): every scan (not only
  /// the nodes) becomes a vertex, joined to the next by its front-end
  /// motion and aligned by point-to-line ICP with each of the next
  /// scan_window scans; those alignments are edges of a graph that keeps
  /// the submaps and loop closures, optimized once. 0 skips it (the nodes'
  /// poses then place the scans between them). In [0, 20]. Default 2.
  int scan_window = 2;
  /// (scan_window_translation_sigma, scan_window_rotation_sigma in
  /// degrees) standard deviations of a scan-to-scan ICP edge. Defaults
  /// 0.01 m, 0.1°.
  double scan_window_translation_sigma = 0.01;
  double scan_window_rotation_sigma = 0.1 * 3.14159265358979323846 / 180.0;
  /// (scan_window_gate) ICP's initial pairing distance of those
  /// alignments, meters, > 0; a pair whose ICP does not converge (or whose
  /// geometry leaves a direction free) adds no edge. Default 0.3.
  double scan_window_gate = 0.3;
  /// (num_threads) threads of the final refinement's alignments; 0 = all
  /// hardware threads. The result does not depend on it. Default 1.
  int num_threads = 1;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The [backend] keys over the defaults (strict, as above).
  static LidarBackEndOptions from_config(const ConfigSection& section);
};

/// Everything lidar SLAM takes.
struct LidarSlamOptions {
  LidarFrontEndOptions frontend;     ///< [frontend]
  LidarSubmapOptions submaps;        ///< [submaps]
  LidarLoopClosureOptions loop_closure;  ///< [loop_closure]
  LidarBackEndOptions backend;       ///< [backend]

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// The sections lidar SLAM reads: frontend, submaps, loop_closure, backend.
inline constexpr const char* kLidarSlamSections[] = {"frontend", "submaps", "loop_closure",
                                                     "backend"};

/// Reads [frontend], [submaps], [loop_closure] and [backend] of `ini` over
/// the defaults. Strict: an unknown key in these sections is a ConfigError
/// naming the file, section, key and line; so is a malformed or
/// out-of-range value. Other sections are left to the caller.
LidarSlamOptions load_lidar_slam_options(const IniFile& ini);

}  // namespace rove
