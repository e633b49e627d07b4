#include "rove/slam/metric_map_builder.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <variant>

#include "rove/core/error.h"
#include "rove/core/interrupt.h"

#include "rove/io/any_rawlog.h"
#include "rove/io/mrpt_simplemap.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/robot_movement_2d.h"

namespace rove {

MapInputKind detect_map_input(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  return name.find(".simplemap") != std::string::npos ? MapInputKind::SimpleMap
                                                       : MapInputKind::Rawlog;
}

namespace {

bool same_ascii_ci(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

// The first section with a `<known kind>_count` key.
std::string find_map_section(const IniFile& ini) {
  const auto kinds = supported_metric_map_kinds();
  for (const auto& sec : ini.sections()) {
    for (const auto& key : ini.keys(sec)) {
      constexpr std::string_view kCount = "_count";
      if (key.size() <= kCount.size() || !key.ends_with(kCount)) continue;
      const std::string_view stem(key.data(), key.size() - kCount.size());
      if (std::any_of(kinds.begin(), kinds.end(),
                      [&](const std::string& k) { return same_ascii_ci(k, stem); })) {
        return sec;
      }
    }
  }
  throw ConfigError(ini.source(), "", "",
                    "no section declares a metric map (no `<kind>_count` key); name it with "
                    "--section");
}

void insert_frame(const SensoryFrame& frame, const Pose3& T, MetricMap& map, MapBuildResult& r) {
  for (const auto& o : frame.observations) {
    ++r.observations;
    if (map.insert(*o, T)) ++r.observations_used;
  }
}

}  // namespace

MapBuildConfig load_map_build_config(const IniFile& ini, std::string_view section) {
  MapBuildConfig c;
  c.section = section.empty() ? find_map_section(ini) : std::string(section);
  if (!ini.has_section(c.section)) throw ConfigError(ini.source(), c.section, "", "section not found");
  MultiMetricMapLoadReport report;
  c.maps = MultiMetricMap::from_config(ini, c.section, &report);
  c.ignored_keys = std::move(report.ignored_keys);
  if (c.maps.size() == 0) {
    throw ConfigError(ini.source(), c.section, "", "declares no map (every `_count` is 0)");
  }
  return c;
}

MapBuildResult build_map(const std::string& path, MetricMap& map, const MapBuildOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  MapBuildResult r;
  r.input = detect_map_input(path);
  if (r.input == MapInputKind::SimpleMap) {
    const SimpleMap sm = load_mrpt_simplemap(path);
    for (const auto& kf : sm.keyframes) {
      const Pose3 T = kf.pose.mean();
      throw_if_interrupted();
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
      throw_if_interrupted();
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
