#include "rove/slam/scan_consistency.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/maps/tiled_grid.h"
#include "rove/obs/selection_error.h"
#include "rove/poses/pose3.h"

namespace rove {

std::string contradiction_message(std::size_t contradicted, std::size_t checked, std::string_view what,
                                  std::string_view where, std::string_view consequence) {
  return fmt::format("{} of {} {} saw more than {:.0f} % of their rays through walls of the {} before "
                     "them{} (> {:.0f} % of the {}): {}",
                     contradicted, checked, what, 100.0 * kContradictedRays, what, where,
                     100.0 * kContradictedScans, what, consequence);
}

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

std::vector<PosedScan> posed_scans(const SimpleMap& map) {
  std::vector<PosedScan> out;
  for (std::size_t k = 0; k < map.keyframes.size(); ++k) {
    const SimpleMapKeyframe& kf = map.keyframes[k];
    std::optional<SE2d> pose;
    for (const auto& o : kf.frame->observations) {
      const auto* scan = dynamic_cast<const RangeScan2D*>(o.get());
      if (scan == nullptr) continue;
      if (!pose) {
        const Pose3 m = kf.pose.mean();
        ROVE_CHECK_MSG(m.translation().allFinite() && std::isfinite(m.yaw()),
                       "keyframe {} of the simple map has a pose that is not finite", k);
        pose = SE2d(m.x(), m.y(), m.yaw());
      }
      out.push_back({*pose, scan});
    }
  }
  return out;
}

SimplemapCheck check_simplemap(const SimpleMap& map, float resolution) {
  SimplemapCheck out;
  out.keyframes = map.keyframes.size();
  const std::vector<PosedScan> scans = posed_scans(map);
  if (scans.size() < 2) {
    throw SelectionError("", fmt::format("{} keyframes hold {} 2D scan(s): nothing to check the scans "
                                         "against",
                                         map.keyframes.size(), scans.size()));
  }
  for (const PosedScan& s : scans) out.poses.push_back(s.T_map_robot);
  out.consistency = scan_consistency(scans, resolution);
  const ScanConsistency& c = out.consistency;
  if (c.resolution == 0.0) {
    out.issues.push_back({"not-checked", fmt::format("the scans span more than {} tiles of 32 cells even "
                                                     "at {} times {:g} m: too far apart to replay",
                                                     kMaxReplayTiles, kMaxCoarsening, resolution)});
  } else if (c.flagged()) {
    out.issues.push_back(
        {"map-contradicts-scans",
         contradiction_message(c.contradicted, c.checked, "scans", "",
                               "the map holds passes that disagree (a loop closed wrong, or one not closed)")});
  }
  return out;
}

}  // namespace rove
