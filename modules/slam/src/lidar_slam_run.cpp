#include "rove/slam/lidar_slam_run.h"

#include <map>
#include <memory>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "log_counts.h"
#include "rawlog_steps.h"
#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/interrupt.h"
#include "rove/core/timer.h"
#include "rove/maps/grid_insertion.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/selection_error.h"
#include "rove/poses/lie_conversion.h"

namespace rove {
namespace {

// The scans of one sensor with the odometry between them, fed to LidarSlam.
class ScanFeeder {
 public:
  ScanFeeder(LidarSlam& slam, const std::string& path, const LidarSlamRunOptions& options,
             LidarSlamRunResult& result)
      : slam_(slam), path_(path), options_(options), res_(result) {
    res_.sensor_label = options.sensor_label;
  }

  // Odometry: a motion of the robot since the last observation.
  void add_motion(const SE2d& increment) {
    pending_ = pending_ * increment;
    have_pending_ = true;
    any_odometry_ = true;
  }
  // A cumulative odometry reading (layout #2).
  void add_reading(const SE2d& T_odom_robot) {
    if (last_reading_) add_motion(last_reading_->inverse() * T_odom_robot);
    last_reading_ = T_odom_robot;
  }
  // An observation: a scan of the chosen sensor goes to SLAM. False when
  // max_scans is reached.
  bool observe(const std::shared_ptr<const Observation>& o, std::uint64_t offset) {
    if (const auto* odo = dynamic_cast<const OdometryObservation*>(o.get())) {
      add_reading(to_se2(odo->odometry));
      return true;
    }
    auto scan = std::dynamic_pointer_cast<const RangeScan2D>(o);
    if (!scan) return true;
    if (res_.sensor_label.empty()) res_.sensor_label = scan->sensor_label;
    if (scan->sensor_label != res_.sensor_label) {
      ++res_.other_scans;
      return true;
    }
    if (options_.max_scans && scans_ >= *options_.max_scans) return false;
    std::optional<SE2d> increment;
    if (scans_ > 0 && have_pending_) {
      increment = pending_;
      cumulative_ = cumulative_ * pending_;
    }
    pending_ = SE2d();
    have_pending_ = false;
    res_.odometry.push_back(cumulative_);
    const Timestamp t = scan->timestamp;
    Stopwatch sw;
    LidarSlamScanUpdate up;
    try {
      up = slam_.add_scan(scan, t, increment);
    } catch (const InvalidArgument& e) {
      throw ParseError({path_, std::nullopt, offset, "scan " + std::to_string(scans_)},
                       fmt::format("lidar SLAM rejected the scan: {}", e.message()));
    }
    res_.mapping_seconds += sw.elapsed();
    if (up.matched && up.match_score < options_.min_match_score) ++res_.poor_matches;
    if (t.valid()) {
      if (scans_ == 0) res_.first_time = t.to_seconds();
      res_.last_time = t.to_seconds();
    }
    ++scans_;
    if (options_.on_scan) options_.on_scan(up);
    return true;
  }
  std::uint64_t scans() const noexcept { return scans_; }
  bool any_odometry() const noexcept { return any_odometry_; }

 private:
  LidarSlam& slam_;
  const std::string& path_;
  const LidarSlamRunOptions& options_;
  LidarSlamRunResult& res_;
  SE2d pending_, cumulative_;
  bool have_pending_ = false, any_odometry_ = false;
  std::optional<SE2d> last_reading_;
  std::uint64_t scans_ = 0;
};

std::vector<LidarSlamIssue> run_issues(const LidarSlam& slam, const LidarSlamRunResult& res,
                                       const LidarSlamRunOptions& options) {
  std::vector<LidarSlamIssue> issues;
  const LidarSlamStats& st = slam.stats();
  if (const auto& opt = slam.last_optimization(); opt && !opt->ok()) {
    issues.push_back({"optimization-not-converged",
                      fmt::format("the last pose-graph optimization stopped without converging "
                                  "({}: {}); the poses are its last iterate",
                                  to_string(opt->termination), opt->message)});
  }
  if (st.loop_searches > 0 && st.loops_accepted == 0) {
    issues.push_back({"no-loop-closure",
                      fmt::format("none of {} loop-closure searches was accepted ({} below "
                                  "min_score {:g}, {} not confirmed by ICP): the map is the "
                                  "front-end's alone",
                                  st.loop_searches, st.loops_low_score,
                                  slam.options().loop_closure.min_score, st.loops_icp_rejected)});
  }
  if (st.matched > 0 && static_cast<double>(res.poor_matches) >
                            options.max_poor_match_fraction * static_cast<double>(st.matched)) {
    issues.push_back(
        {"poor-matching",
         fmt::format("{} of {} scans matched their submap with a score under {:g} (more than "
                     "{:g} %): the front-end may have lost track there",
                     res.poor_matches, st.matched, options.min_match_score,
                     100.0 * options.max_poor_match_fraction)});
  }
  if (res.consistency.flagged()) {
    issues.push_back(
        {"map-contradicts-scans",
         contradiction_message(res.consistency.contradicted, res.consistency.checked, "nodes",
                               " at the final poses",
                               "the map holds passes that disagree (a loop closed wrong, or one not closed)")});
  }
  if (st.scans_without_points > 0) {
    issues.push_back({"scans-without-points",
                      fmt::format("{} of {} scans had no return within [{:g}, {:g}) m; they got "
                                  "the predicted pose only",
                                  st.scans_without_points, st.scans,
                                  slam.options().frontend.scan.min_range,
                                  slam.options().frontend.scan.max_range)});
  }
  return issues;
}

}  // namespace

LidarSlamRunResult run_lidar_slam(LidarSlam& slam, const std::string& path,
                                  const LidarSlamRunOptions& options) {
  LidarSlamRunResult res;
  ScanFeeder feeder(slam, path, options, res);
  std::map<std::string, std::uint64_t> classes;
  const detail::LogRead read = detail::read_entries(path, options.reader, [&](const RawlogEntry& entry, std::uint64_t at) {
    if (auto* ac = std::get_if<std::shared_ptr<const ActionCollection>>(&entry)) {
      ++classes["ActionCollection"];
      if (const auto best = best_movement_2d(**ac)) feeder.add_motion(to_se2(best->mean()));
      return true;
    }
    if (auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&entry)) {
      for (const auto& o : (*sf)->observations) {
        ++classes[std::string(o->class_name())];
        if (!feeder.observe(o, at)) return false;
      }
      return true;
    }
    const auto& o = std::get<std::shared_ptr<const Observation>>(entry);
    ++classes[std::string(o->class_name())];
    return feeder.observe(o, at);
  });
  res.format = read.format;
  res.entries = read.entries;
  res.read_seconds = read.seconds;
  const auto& f = slam.options().frontend.scan;
  if (feeder.scans() == 0) {
    throw SelectionError("", fmt::format("{} holds no 2D scan{} for lidar SLAM ({} entries: {}); "
                                         "nothing written",
                                         path,
                                         options.sensor_label.empty()
                                             ? std::string()
                                             : " labelled '" + options.sensor_label + "'",
                                         res.entries, detail::describe_counts(classes)));
  }
  if (feeder.scans() == 1) {
    throw SelectionError("", fmt::format("{} holds a single 2D scan ('{}'): lidar SLAM needs at "
                                         "least two; nothing written",
                                         path, res.sensor_label));
  }
  if (slam.stats().scans_without_points == slam.stats().scans) {
    throw SelectionError(
        "", fmt::format("none of the {} scans ('{}') of {} has a valid return within [{:g}, {:g}) "
                        "m (all ranges invalid, or out of [frontend] min_range / max_range); "
                        "nothing written",
                        slam.stats().scans, res.sensor_label, path, f.min_range, f.max_range));
  }
  if (!feeder.any_odometry()) res.odometry.clear();
  Stopwatch sw;
  res.final_optimization = slam.finish();
  res.mapping_seconds += sw.elapsed();
  // The nodes' scans against each other at their final poses.
  std::vector<PosedScan> nodes;
  for (const LidarSlamNode& n : slam.nodes()) {
    if (n.observation) nodes.push_back({n.T_world_robot, n.observation.get()});
  }
  res.consistency = scan_consistency(nodes);
  res.issues = run_issues(slam, res, options);
  return res;
}

void LidarMapOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(resolution) && resolution > 0.0, "map resolution {} must be > 0",
                 resolution);
  insertion.check();
}

LidarMapOptions LidarMapOptions::from_config(const ConfigSection& section) {
  LidarMapOptions o;
  o.resolution = section.get_in_range("resolution", o.resolution, 1e-3, 10.0);
  o.insertion = GridInsertionOptions::from_config(section);
  section.check_all_read();
  return o;
}

OccupancyGrid build_lidar_slam_map(const LidarSlam& slam, const LidarMapOptions& options) {
  options.check();
  const auto r = static_cast<float>(options.resolution);
  OccupancyGrid grid(-r, r, -r, r, r);
  bool first = true;
  for (const LidarSlamNode& n : slam.nodes()) {
    if (!n.observation) continue;
    const Pose2 pose = to_pose2(n.T_world_robot);
    if (first) {
      const auto x = static_cast<float>(pose.x()), y = static_cast<float>(pose.y());
      grid = OccupancyGrid(x - 1.0f, x + 1.0f, y - 1.0f, y + 1.0f, r);
      first = false;
    }
    insert_scan(grid, *n.observation, pose, options.insertion);
  }
  return grid;
}

}  // namespace rove
