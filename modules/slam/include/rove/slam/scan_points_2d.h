#pragma once
/// \file
/// The points of a planar scan as lidar SLAM uses them (lidar_slam.h): the
/// rays' end points in the robot frame within a range interval, thinned by a
/// voxel filter for insertion into the submaps, and by an adaptive voxel
/// filter (as Cartographer's) for scan matching and loop closure, which
/// keeps a scan's size near a target whatever the scene's extent.

#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"
#include "rove/obs/range_scan_2d.h"

namespace rove {

/// What counts as a return of a scan, and how finely it is kept.
struct ScanPointsOptions {
  /// (min_range) rays shorter than this are dropped, meters, >= 0.
  /// Default 0.05 (reflections off the robot itself).
  double min_range = 0.05;
  /// (max_range) rays at or beyond this are dropped, meters, > min_range.
  /// Default 50. The far returns carry a long corridor's heading and an
  /// open hall's shape (with 30 m, FR079's corridor bends and the Telecom
  /// hall's path leaves ICP-SLAM's by 1.5 m); "no return" written as a
  /// range of 50 m or more (the ACES log) is dropped, where keeping it
  /// would grow every submap to a 50 m disc (ACES: 1.6 GB peak RSS with 80).
  double max_range = 50.0;
  /// (voxel_size) the points kept for the submaps: one per square voxel of
  /// this side (their centroid), meters, >= 0 (0 keeps every point).
  /// Default 0.025 (half a cell of the default 5 cm submaps).
  double voxel_size = 0.025;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The keys above from `section` over the defaults; ConfigError (file,
  /// section, key) for a malformed or out-of-range value.
  static ScanPointsOptions from_config(const ConfigSection& section);
};

/// A scan's returns in the robot frame.
struct ScanPoints2D {
  /// The sensor's position on the robot (T_robot_sensor's x, y), meters.
  Eigen::Vector2d sensor_origin = Eigen::Vector2d::Zero();
  /// Returns within [min_range, max_range), voxel-filtered, meters.
  std::vector<Eigen::Vector2d> points;
  /// Largest distance of a kept point from the robot's origin, meters (0 if none).
  double max_point_range = 0.0;
  /// Rays of the scan.
  std::size_t rays = 0;
  /// Rays that yield a point (valid flag, finite, >= 0).
  std::size_t valid_rays = 0;
  /// Valid rays within [min_range, max_range).
  std::size_t in_range_rays = 0;
};

/// The returns of `scan` (see ScanPoints2D). Preconditions (InvalidArgument):
/// options.check() passes; scan.check() passes.
ScanPoints2D scan_points_2d(const RangeScan2D& scan, const ScanPointsOptions& options);

/// One point per square voxel of side `voxel_size` (the centroid of the
/// points in it), ordered by voxel (y, then x); the points as given when
/// voxel_size is 0. Non-finite points are dropped. Precondition
/// (InvalidArgument): voxel_size finite and >= 0.
std::vector<Eigen::Vector2d> voxel_filter_2d(std::span<const Eigen::Vector2d> points,
                                             double voxel_size);

/// Options of adaptive_voxel_filter_2d.
struct AdaptiveVoxelFilterOptions {
  /// (max_length) the largest voxel side tried, meters, > 0.
  double max_length = 0.5;
  /// (min_num_points) the filter keeps at least this many points when the
  /// input has them, >= 1.
  std::size_t min_num_points = 200;
  /// (max_range) points farther than this from the origin are dropped
  /// first, meters, > 0.
  double max_range = 50.0;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
  /// The keys above, each prefixed with `prefix` ("matching_", "loop_"),
  /// from `section` over `defaults`; ConfigError as ScanPointsOptions.
  static AdaptiveVoxelFilterOptions from_config(const ConfigSection& section,
                                                std::string_view prefix,
                                                const AdaptiveVoxelFilterOptions& defaults);
};

/// The points within max_range, voxel-filtered with the largest voxel side
/// up to max_length that still leaves min_num_points (found by bisection
/// to 1 % of max_length); all of them if there are no more than
/// min_num_points. Preconditions (InvalidArgument): options.check().
std::vector<Eigen::Vector2d> adaptive_voxel_filter_2d(std::span<const Eigen::Vector2d> points,
                                                      const AdaptiveVoxelFilterOptions& options);

}  // namespace rove
