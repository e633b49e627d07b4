// ReactiveNavigatorOptions: defaults and MRPT's reactive-navigation INI.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <string>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/nav/reactive_navigator.h"

namespace rove {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string squeeze(std::string s) {
  s.erase(std::remove_if(s.begin(), s.end(), [](unsigned char c) { return std::isspace(c) != 0; }), s.end());
  return s;
}

// MRPT's default scores (reactive2d_config.ini), spaces removed: the
// scoring rove implements.
struct DefaultScore {
  const char* name;
  const char* formula;
};
constexpr DefaultScore kScores[] = {
    {"target_distance",
     "vareffective_trg_d_norm:=max(0,target_d_norm-move_cur_d);if(collision_free_distance>effective_trg_d_norm,"
     "1/(1+effective_trg_d_norm^2),0)"},
    {"collision_free_distance_score",
     "vareffective_trg_d_norm:=max(0,target_d_norm-move_cur_d);if(collision_free_distance>(effective_trg_d_norm+"
     "0.05),1.0,collision_free_distance)"},
    {"euclidean_nearness", "1/(1+dist_eucl_min^2)"},
    {"hysteresis_score", "hysteresis"},
    {"path_index_near_target",
     "vardif:=abs(target_k-move_k);if(dif>(num_paths/2)){dif:=num_paths-dif;};exp(-abs(dif/(num_paths/10.0)))"},
    {"ptg_priority_score", "ptg_priority"},
};
constexpr const char* kScalar =
    "ptg_priority_score*(0.3*target_distance+0.5*collision_free_distance_score+8.0*euclidean_nearness+0.1*"
    "hysteresis_score+0.2*path_index_near_target)";

void check_scores(const IniFile& ini, std::vector<IgnoredConfigKey>* ignored) {
  const ConfigSection base(ini, "CMultiObjectiveMotionOptimizerBase", ignored);
  int i = 1;
  for (const DefaultScore& d : kScores) {
    const std::string nk = "score" + std::to_string(i) + "_name", fk = "score" + std::to_string(i) + "_formula";
    ++i;
    if (!base.has(nk) && !base.has(fk)) continue;
    if (base.get<std::string>(nk, d.name) != d.name || squeeze(base.get<std::string>(fk, d.formula)) != d.formula) {
      base.fail(fk, "rove evaluates MRPT's default motion scores only (those of reactive2d_config.ini); this "
                    "score differs from them");
    }
  }
  if (base.has("score" + std::to_string(i) + "_name")) {
    base.fail("score" + std::to_string(i) + "_name", "rove evaluates MRPT's six default motion scores only");
  }
  if (base.has("movement_assert1")) base.fail("movement_assert1", "movement assertions are not supported");
  if (!squeeze(base.get<std::string>("scores_to_normalize", "")).empty()) {
    base.fail("scores_to_normalize", "score normalization is not supported (leave it empty)");
  }
  base.check_all_read();
  const ConfigSection scalar(ini, "CMultiObjMotionOpt_Scalarization", ignored);
  if (scalar.has("scalar_score_formula") && squeeze(scalar.get<std::string>("scalar_score_formula", "")) != kScalar) {
    scalar.fail("scalar_score_formula", "rove evaluates MRPT's default scalarization only (that of "
                                        "reactive2d_config.ini)");
  }
  scalar.check_all_read();
}

PtgOptions read_ptg(const ConfigSection& s, int n, double radius) {
  const std::string p = "PTG" + std::to_string(n) + "_";
  PtgOptions o;
  o.robot_radius = radius;
  const std::string type_key = p + "Type";
  if (!s.has(type_key)) s.fail(type_key, "missing (PTG_COUNT says there are more PTGs)");
  o.family = s.get_enum(type_key, o.family,
                        {{"CPTG_DiffDrive_C", PtgFamily::DiffDriveC},
                         {"CPTG_DiffDrive_alpha", PtgFamily::DiffDriveAlpha},
                         {"CPTG_DiffDrive_CCS", PtgFamily::DiffDriveCCS},
                         {"CPTG_DiffDrive_CS", PtgFamily::DiffDriveCS}});
  o.resolution = s.get_in_range(p + "resolution", o.resolution, 1e-3, 10);
  o.ref_distance = s.get_in_range(p + "refDistance", o.ref_distance, 0.1, 1000);
  o.num_paths = static_cast<int>(s.get_in_range(p + "num_paths", o.num_paths, 3, 4096));
  o.v_max = s.get_in_range(p + "v_max_mps", o.v_max, 1e-6, 1e3);
  o.w_max = s.get_in_range(p + "w_max_dps", o.w_max / kDeg, 1e-6, 1e5) * kDeg;
  o.k = s.get_in_range(p + "K", o.k, -1e3, 1e3);
  o.cte_a0v = s.get_in_range(p + "cte_a0v_deg", o.cte_a0v / kDeg, 1e-6, 1e5) * kDeg;
  o.cte_a0w = s.get_in_range(p + "cte_a0w_deg", o.cte_a0w / kDeg, 1e-6, 1e5) * kDeg;
  o.score_priority = s.get_in_range(p + "score_priority", o.score_priority, 0, 1e6);
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    s.fail(type_key, e.message());
  }
  return o;
}

}  // namespace

ReactiveNavigatorOptions ReactiveNavigatorOptions::defaults(double robot_radius) {
  ReactiveNavigatorOptions o;
  PtgOptions c;
  c.robot_radius = robot_radius;
  PtgOptions alpha = c;
  alpha.family = PtgFamily::DiffDriveAlpha;
  PtgOptions back = c;
  back.k = -1.0;
  back.score_priority = 0.5;
  o.ptgs = {c, alpha, back};
  return o;
}

ReactiveNavigatorOptions ReactiveNavigatorOptions::from_config(const IniFile& ini,
                                                              std::vector<IgnoredConfigKey>* ignored) {
  ReactiveNavigatorOptions o;
  const ConfigSection nav(ini, "CAbstractNavigator", ignored);
  nav.ignore({"dist_to_target_for_sending_event", "alarm_seems_not_approaching_target_timeout",
              "dist_check_target_is_blocked", "hysteresis_check_target_is_blocked", "enable_time_profiler"},
             "the navigation run decides when the goal is reached and when to replan");
  nav.check_all_read();
  const ConfigSection wp(ini, "CWaypointsNavigator", ignored);
  wp.ignore({"max_distance_to_allow_skip_waypoint", "min_timesteps_confirm_skip_waypoints", "waypoint_angle_tolerance",
             "multitarget_look_ahead"},
            "targets come from the global plan's look-ahead point, not from waypoints");
  wp.check_all_read();
  const ConfigSection filter(ini, "CPointCloudFilterByDistance", ignored);
  filter.ignore({"min_dist", "angle_tolerance", "too_old_seconds", "previous_keyframes", "max_deletion_ratio"},
                "no point-cloud filter: every point of the current scan is an obstacle");
  filter.check_all_read();

  const ConfigSection r(ini, "CAbstractPTGBasedReactive", ignored);
  o.robot_max_v = r.get_in_range("robotMax_V_mps", o.robot_max_v, 1e-6, 1e3);
  o.robot_max_w = r.get_in_range("robotMax_W_degps", o.robot_max_w / kDeg, 1e-6, 1e5) * kDeg;
  o.holonomic = r.get_enum("holonomic_method", o.holonomic,
                           {{"CHolonomicFullEval", HolonomicMethod::FullEval},
                            {"CHolonomicND", HolonomicMethod::NearnessDiagram},
                            {"CHolonomicVFF", HolonomicMethod::Vff}});
  if (r.get<std::string>("motion_decider_method", "CMultiObjMotionOpt_Scalarization") !=
      "CMultiObjMotionOpt_Scalarization") {
    r.fail("motion_decider_method", "only CMultiObjMotionOpt_Scalarization is available");
  }
  o.ref_distance = r.get_in_range("ref_distance", o.ref_distance, 0.1, 1000);
  o.secure_distance_start = r.get_in_range("secure_distance_start", o.secure_distance_start, 0, 1);
  o.secure_distance_end = r.get_in_range("secure_distance_end", o.secure_distance_end, 0, 1);
  r.ignore({"robotMinCurvRadius"}, "differential-drive PTGs need no minimum curvature radius");
  r.ignore({"speedfilter_tau"}, "commands are not low-pass filtered");
  r.ignore({"use_delays_model", "max_distance_predicted_actual_path", "min_normalized_free_space_for_ptg_continuation"},
           "no delay model and no PTG continuation: each cycle chooses anew");
  r.ignore({"enable_obstacle_filtering"}, "no point-cloud filter");
  r.ignore({"evaluate_clearance"}, "clearance is not a score here");
  r.check_all_read();

  const ConfigSection full(ini, "CHolonomicFullEval", ignored);
  o.full_eval = FullEvalOptions::from_config(full);
  full.check_all_read();
  const ConfigSection nd(ini, "CHolonomicND", ignored);
  o.nd = NdOptions::from_config(nd);
  nd.check_all_read();
  const ConfigSection vff(ini, "CHolonomicVFF", ignored);
  o.vff = VffOptions::from_config(vff);
  vff.check_all_read();
  check_scores(ini, ignored);

  const ConfigSection sys(ini, "CReactiveNavigationSystem", ignored);
  sys.ignore({"min_obstacles_height", "max_obstacles_height"}, "obstacles are 2D points");
  sys.ignore({"RobotModel_shape2D_xs", "RobotModel_shape2D_ys"}, "rove's PTGs use the circular footprint");
  const double radius = sys.get_in_range("RobotModel_circular_shape_radius", 0.5, 1e-3, 100);
  const int count = static_cast<int>(sys.get_in_range("PTG_COUNT", 3, 0, 64));
  if (sys.has("PTG_COUNT")) {
    for (int i = 0; i < count; ++i) o.ptgs.push_back(read_ptg(sys, i, radius));
  } else {
    o.ptgs = defaults(radius).ptgs;
  }
  sys.check_all_read();
  try {
    o.check();
  } catch (const InvalidArgument& e) {
    throw ConfigError(ini.source(), "CAbstractPTGBasedReactive", "", e.message());
  }
  return o;
}

void ReactiveNavigatorOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(robot_max_v) && robot_max_v > 0, "robotMax_V_mps must be > 0, got {}", robot_max_v);
  ROVE_CHECK_MSG(std::isfinite(robot_max_w) && robot_max_w > 0, "robotMax_W_degps must be > 0");
  ROVE_CHECK_MSG(std::isfinite(ref_distance) && ref_distance > 0, "ref_distance must be > 0");
  ROVE_CHECK_MSG(secure_distance_start >= 0 && secure_distance_end > secure_distance_start && secure_distance_end <= 1,
                 "secure distances must satisfy 0 <= start < end <= 1, got {} and {}", secure_distance_start,
                 secure_distance_end);
  ROVE_CHECK_MSG(!ptgs.empty(), "the reactive navigator needs at least one PTG (PTG_COUNT)");
  for (const PtgOptions& p : ptgs) p.check();
  for (const FullEvalPhase& ph : full_eval.phases) {
    ROVE_CHECK_MSG(!ph.factors.empty(), "a FullEval phase needs factors");
  }
}

}  // namespace rove
