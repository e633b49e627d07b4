#pragma once
/// \file
/// Files ICP-SLAM results are written to: trajectories in the TUM format,
/// point maps as PLY, occupancy grids as a ROS map_server image + YAML pair,
/// and a top-down PNG picture of a point map with the robot's path.

#include <string>
#include <utility>
#include <vector>

#include "rove/maps/occupancy_grid.h"
#include "rove/maps/point_cloud.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"

namespace rove {

/// A planar pose at a time.
struct TimedPose2 {
  Timestamp time;  ///< when (invalid: unknown)
  Pose2 pose;      ///< T_world_robot
};

/// Writes `t x y z qx qy qz qw` lines (TUM RGB-D format; t in seconds since
/// the Unix epoch with 6 decimals, z = 0, the quaternion of a rotation by
/// phi about z). A pose with an invalid time gets its index as time. Throws
/// IoError if the file cannot be written.
void write_tum_trajectory(const std::string& path, const std::vector<TimedPose2>& poses);

/// Writes the points as an ASCII PLY (`element vertex`, float x y z).
/// Throws IoError if the file cannot be written.
void write_ply(const std::string& path, const PointCloud& cloud);

/// The two files of a ROS map_server map.
struct GridMapFiles {
  std::string image;  ///< the PNG
  std::string yaml;   ///< the YAML description
};

/// Writes `<prefix>.png` (8-bit gray, first row = largest y, 255·p(free):
/// white free, black occupied, 128 unknown) and `<prefix>.yaml` (image,
/// resolution, origin = lower-left corner, negate 0, occupied_thresh 0.65,
/// free_thresh 0.196). Throws IoError if a file cannot be written.
GridMapFiles write_grid_map(const std::string& prefix, const OccupancyGrid& grid);

/// Options of render_points_png.
struct PointsImageOptions {
  double resolution = 0.05;  ///< meters per pixel, > 0
  double margin = 1.0;       ///< meters around the content, ≥ 0
  int max_side = 4096;       ///< largest image side, pixels (resolution grows to fit)
};

/// Draws the points (x, y; dark gray on white) and the path (red, the
/// start in green, the end in blue) seen from above, +x right, +y up, into
/// an 8-bit palette PNG (white, dark gray (40, 40, 40), red (220, 30, 30),
/// green (0, 170, 0), blue (0, 0, 220)). Throws IoError if the file cannot be written and
/// InvalidArgument on bad options.
void render_points_png(const std::string& path, const PointCloud& cloud,
                       const std::vector<Pose2>& robot_path,
                       const PointsImageOptions& options = {});

}  // namespace rove
