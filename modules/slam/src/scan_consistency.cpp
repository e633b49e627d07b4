#include "rove/slam/scan_consistency.h"

#include <algorithm>
#include <cmath>

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
  out.through_walls.reserve(scans.size());
  TiledGrid grid(resolution);
  const double margin = std::max(kThroughWallsMargin, 4.0 * static_cast<double>(resolution));
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
