#pragma once
/// \file
/// A top-down PNG picture of a point map with the robot's path, as ICP-SLAM
/// draws its result. The files of the result (trajectories, PLY, ROS maps,
/// simplemap) are written by rove::io (tum_trajectory.h, ply.h,
/// grid_image.h, mrpt_simplemap_writer.h).

#include <string>
#include <vector>

#include "rove/maps/point_cloud.h"
#include "rove/poses/pose2.h"

namespace rove {

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
