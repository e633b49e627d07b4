#include "rove/slam/scan_consistency.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rove/core/check.h"
#include "rove/maps/tiled_grid.h"

namespace rove {

ScanConsistency scan_consistency(const std::vector<PosedScan>& scans, float resolution,
                                 const GridInsertionOptions& options) {
  ROVE_CHECK_MSG(std::isfinite(resolution) && resolution > 0.0f, "resolution must be > 0, got {}",
                 resolution);
  options.check();
  for (std::size_t i = 0; i < scans.size(); ++i) {
    ROVE_CHECK_MSG(scans[i].scan != nullptr, "scan {} of the replay is null", i);
    ROVE_CHECK_MSG(scans[i].T_map_robot.translation().allFinite() && std::isfinite(scans[i].T_map_robot.angle()),
                   "the pose of scan {} of the replay is not finite", i);
  }
  ScanConsistency out;
  if (scans.empty()) {
    out.resolution = resolution;
    return out;
  }
  // The extent the insertions can reach: each pose ± its farthest return
  // (no farther than the insertion's limit) and a meter.
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const PosedScan& s : scans) {
    double reach = 0.0;
    for (std::size_t i = 0; i < s.scan->size(); ++i) {
      if (s.scan->ray_yields_point(i)) reach = std::max(reach, static_cast<double>(s.scan->ranges[i]));
    }
    reach = std::min(reach, static_cast<double>(options.max_distance_insertion)) + 1.0 +
            std::hypot(s.scan->T_robot_sensor.x(), s.scan->T_robot_sensor.y());
    const Eigen::Vector2d& t = s.T_map_robot.translation();
    x0 = std::min(x0, t.x() - reach);
    x1 = std::max(x1, t.x() + reach);
    y0 = std::min(y0, t.y() - reach);
    y1 = std::max(y1, t.y() + reach);
  }
  const auto tiles = [&](double res) {
    const double side = res * GridTile::kSide;
    return (std::floor(x1 / side) - std::floor(x0 / side) + 1.0) * (std::floor(y1 / side) - std::floor(y0 / side) + 1.0);
  };
  double res = resolution;
  while (tiles(res) > static_cast<double>(kMaxReplayTiles)) {
    res *= 2.0;
    if (res > kMaxCoarsening * static_cast<double>(resolution)) {
      out.through_walls.assign(scans.size(), 0.0);
      return out;  // resolution 0: not checked
    }
  }
  out.resolution = res;
  out.through_walls.reserve(scans.size());
  TiledGrid grid(static_cast<float>(res));
  grid.reserve(x0, x1, y0, y1);
  const double margin = std::max(kThroughWallsMargin, 4.0 * res);
  for (const PosedScan& s : scans) {
    double through = 0.0;
    if (!grid.empty()) {
      through = rays_through_occupied(grid, *s.scan, s.T_map_robot, margin).fraction();
      ++out.checked;
      out.contradicted += through > kContradictedRays ? 1 : 0;
    }
    out.through_walls.push_back(through);
    insert_scan(grid, *s.scan, s.T_map_robot, options);
  }
  return out;
}

}  // namespace rove
