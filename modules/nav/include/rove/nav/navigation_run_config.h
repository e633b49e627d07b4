#pragma once
/// \file
/// The options of a navigation run as `rove nav run` (and rove.nav_run)
/// take them: a disc robot's radius and top speeds, then an optional INI
/// file — for the TEB, a [TEB] section with teb_local_planner's parameter
/// names; for the reactive navigator, MRPT's reactive-navigation file —
/// and, after the run, the clearance of every driven pose.

#include <string>
#include <vector>

#include "rove/core/ini.h"
#include "rove/nav/navigation_run.h"

namespace rove {

/// The robot and planner of a run, before any configuration file.
struct NavigationRobot {
  LocalPlannerKind planner = LocalPlannerKind::Teb;  ///< the local planner
  double radius = 0.3;                               ///< m, > 0
  double max_v = 0.8;                                ///< top speed, m/s, > 0
  double max_omega = 1.0471975511965976;             ///< top turn rate, rad/s (60°/s), > 0
};

/// Run options with their notes on the configuration.
struct NavigationRunConfig {
  NavigationRunOptions options;
  /// One line per thing of the file without effect (a missing [TEB]
  /// section; keys of the reactive file rove does not use, one line per
  /// section and reason).
  std::vector<std::string> notes;
};

/// NavigationRunOptions::for_robot(robot), its planner, then `config` (may
/// be null; `config_name` names it in notes and errors) over them: for the
/// TEB, the [TEB] section (what it leaves out of the robot's radius,
/// speeds, obstacle distance and penalty margin stays as the robot sets
/// them; unknown keys refused); for the reactive navigator, the whole file.
/// Throws ConfigError for a malformed or unknown key, and when the reactive
/// navigator's PTG footprint is smaller than the robot; InvalidArgument
/// when the TEB options fail their check.
NavigationRunConfig navigation_run_config(const NavigationRobot& robot, const IniFile* config,
                                          const std::string& config_name = "");

/// Per driven pose of `result`: the distance from the robot's edge (a disc
/// of `robot_radius` m) to the nearest obstacle of `world`, m (≥ 0; at
/// most 10 m is searched).
std::vector<double> driven_clearances(const NavigationRunResult& result, const NavigationGrid& world,
                                      double robot_radius);

}  // namespace rove
