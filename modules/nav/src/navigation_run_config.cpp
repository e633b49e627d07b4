#include "rove/nav/navigation_run_config.h"

#include <fmt/format.h>

#include <algorithm>
#include <utility>

#include "rove/core/config_section.h"
#include "rove/core/error.h"
#include "rove/core/files.h"

namespace rove {

NavigationRunConfig navigation_run_config(const NavigationRobot& robot, const IniFile* config,
                                          const std::string& config_name) {
  NavigationRunConfig c;
  NavigationRunOptions& o = c.options;
  o = NavigationRunOptions::for_robot(robot.radius, robot.max_v, robot.max_omega);
  o.planner = robot.planner;
  if (config == nullptr) return c;
  const IniFile& ini = *config;
  if (o.planner == LocalPlannerKind::Teb) {
    if (!ini.has_section("TEB")) {
      c.notes.push_back(fmt::format("{} has no [TEB] section: the TEB keeps its defaults", printable(config_name)));
      return c;
    }
    const ConfigSection teb(ini, "TEB");
    const TebOptions from_robot = o.teb;
    o.teb = TebOptions::from_config(teb);
    teb.check_all_read();
    // What the section leaves out stays as the robot sets it.
    for (const auto& [key, field] :
         {std::pair{"robot_radius", &TebOptions::robot_radius}, {"max_vel_x", &TebOptions::max_vel_x},
          {"max_vel_theta", &TebOptions::max_vel_theta}, {"min_obstacle_dist", &TebOptions::min_obstacle_dist},
          {"penalty_epsilon", &TebOptions::penalty_epsilon}}) {
      if (!teb.has(key)) o.teb.*field = from_robot.*field;
    }
    o.teb.check();
    return c;
  }
  std::vector<IgnoredConfigKey> ignored;
  o.reactive = ReactiveNavigatorOptions::from_config(ini, &ignored);
  // One note per section and reason.
  for (std::size_t i = 0; i < ignored.size();) {
    std::string keys = printable(ignored[i].key);
    std::size_t j = i + 1;
    for (; j < ignored.size() && ignored[j].section == ignored[i].section && ignored[j].reason == ignored[i].reason; ++j) {
      keys += ", " + printable(ignored[j].key);
    }
    c.notes.push_back(fmt::format("[{}] {}: without effect ({})", printable(ignored[i].section), keys, ignored[i].reason));
    i = j;
  }
  for (const PtgOptions& p : o.reactive.ptgs) {
    if (p.robot_radius < robot.radius) {
      throw ConfigError(config_name, "CReactiveNavigationSystem", "RobotModel_circular_shape_radius",
                        fmt::format("the PTGs' footprint ({} m) is smaller than the robot (radius {} m)",
                                    p.robot_radius, robot.radius));
    }
  }
  return c;
}

std::vector<double> driven_clearances(const NavigationRunResult& result, const NavigationGrid& world,
                                      double robot_radius) {
  std::vector<double> out;
  out.reserve(result.driven.size());
  for (const SE2d& p : result.driven)
    out.push_back(std::max(0.0, world.distance_to_obstacle(p.translation(), robot_radius + 10.0) - robot_radius));
  return out;
}

}  // namespace rove
