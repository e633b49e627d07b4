#include "rove/maps/metric_map_builder.h"

#include <chrono>
#include <filesystem>
#include <variant>

#include "rove/obs/action_collection.h"
#include "rove/obs/any_rawlog.h"
#include "rove/obs/mrpt_simplemap.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/robot_movement_2d.h"

namespace rove {

MapInputKind detect_map_input(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  return name.find(".simplemap") != std::string::npos ? MapInputKind::kSimpleMap
                                                       : MapInputKind::kRawlog;
}

namespace {

void insert_frame(const SensoryFrame& frame, const Pose3& T, MetricMap& map, MapBuildResult& r) {
  for (const auto& o : frame.observations) {
    ++r.observations;
    if (map.insert(*o, T)) ++r.observations_used;
  }
}

}  // namespace

MapBuildResult build_map(const std::string& path, MetricMap& map, const MapBuildOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  MapBuildResult r;
  r.input = detect_map_input(path);
  if (r.input == MapInputKind::kSimpleMap) {
    const SimpleMap sm = load_mrpt_simplemap(path);
    for (const auto& kf : sm.keyframes) {
      const Pose3 T = kf.pose.mean();
      insert_frame(*kf.frame, T, map, r);
      ++r.keyframes;
      r.final_pose = T;
      if (options.on_progress) options.on_progress(r.keyframes);
    }
  } else {
    AnyRawlogReader reader(path);  // MRPT or rove rawlog, or CARMEN log
    Pose3 T;
    std::optional<Pose2> first_odometry;
    while (auto entry = reader.next()) {
      if (const auto* ac = std::get_if<std::shared_ptr<const ActionCollection>>(&*entry)) {
        if (auto mv = (*ac)->find<RobotMovement2D>()) {
          T = T + Pose3(mv->mean());
          ++r.odometry_steps;
        }
      } else if (const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&*entry)) {
        insert_frame(**sf, T, map, r);
        ++r.keyframes;
      } else {
        const auto& obs = std::get<std::shared_ptr<const Observation>>(*entry);
        if (const auto* odo = dynamic_cast<const OdometryObservation*>(obs.get())) {
          if (!first_odometry) first_odometry = odo->odometry;
          T = Pose3(odo->odometry - *first_odometry);
          ++r.odometry_steps;
          ++r.keyframes;
        } else {
          ++r.observations;
          if (map.insert(*obs, T)) ++r.observations_used;
        }
      }
      if (options.on_progress) options.on_progress(reader.entries_read());
    }
    r.final_pose = T;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace rove
