#include "rove/slam/icp_slam.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/timer.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_points.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/poses/lie_conversion.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

PointsMetricMap* as_points(MetricMap* m) { return dynamic_cast<PointsMetricMap*>(m); }
OccupancyGridMetricMap* as_grid(MetricMap* m) { return dynamic_cast<OccupancyGridMetricMap*>(m); }

}  // namespace

void IcpSlamOptions::check() const {
  ROVE_CHECK_FINITE(insertion_lin_distance);
  ROVE_CHECK_FINITE(insertion_ang_distance);
  ROVE_CHECK_FINITE(localization_lin_distance);
  ROVE_CHECK_FINITE(localization_ang_distance);
  ROVE_CHECK_GE(insertion_lin_distance, 0.0);
  ROVE_CHECK_GE(insertion_ang_distance, 0.0);
  ROVE_CHECK_GE(localization_lin_distance, 0.0);
  ROVE_CHECK_GE(localization_ang_distance, 0.0);
  ROVE_CHECK_GE(min_icp_goodness_to_accept, 0.0);
  ROVE_CHECK_LE(min_icp_goodness_to_accept, 1.0);
  ROVE_CHECK_GT(prediction.max_odometry_age, 0.0);
  ROVE_CHECK_GT(prediction.max_localization_age, 0.0);
  icp.check();
}

IcpSlamConfig load_icp_slam_config(const IniFile& ini) {
  constexpr std::string_view kSec = "MappingApplication";
  IcpSlamConfig cfg;
  IcpSlamOptions& o = cfg.options;
  const ConfigSection sec(ini, std::string(kSec), &cfg.ignored_keys);
  o.match_against_the_grid = sec.get<bool>("matchAgainstTheGrid", o.match_against_the_grid);
  o.insertion_lin_distance =
      sec.get_in_range("insertionLinDistance", o.insertion_lin_distance, 0.0, 1e9);
  o.insertion_ang_distance =
      sec.get_in_range("insertionAngDistance", o.insertion_ang_distance / kDeg, 0.0, 1e9) * kDeg;
  o.localization_lin_distance =
      sec.get_in_range("localizationLinDistance", o.localization_lin_distance, 0.0, 1e9);
  o.localization_ang_distance =
      sec.get_in_range("localizationAngDistance", o.localization_ang_distance / kDeg, 0.0, 1e9) *
      kDeg;
  o.min_icp_goodness_to_accept =
      sec.get_in_range("minICPgoodnessToAccept", o.min_icp_goodness_to_accept, 0.0, 1.0);
  cfg.rawlog_file = sec.get<std::string>("rawlog_file", "");
  cfg.rawlog_offset = sec.get<std::uint64_t>("rawlog_offset", 0);
  sec.ignore({"logOutput_dir", "LOG_FREQUENCY", "SAVE_3D_SCENE", "SAVE_POSE_LOG",
              "CAMERA_3DSCENE_FOLLOWS_ROBOT", "SHOW_PROGRESS_3D_REAL_TIME",
              "SHOW_PROGRESS_3D_REAL_TIME_DELAY_MS", "SHOW_LASER_SCANS_3D", "verbosity_level"},
             "MRPT icp-slam GUI/logging switch; rove writes its outputs to -o DIR");

  if (ini.has_section("CARMEN")) {
    const ConfigSection carmen(ini, "CARMEN", &cfg.ignored_keys);
    if (carmen.has("maxRange")) {
      cfg.carmen_max_range =
          static_cast<float>(carmen.get_in_range("maxRange", 81.0, 1e-3, 1e6));
    }
    carmen.check_all_read();
  }

  MultiMetricMapLoadReport report;
  cfg.map = MultiMetricMap::from_config(ini, kSec, &report);
  cfg.ignored_keys.insert(cfg.ignored_keys.end(), report.ignored_keys.begin(),
                          report.ignored_keys.end());
  const auto unread = ini.unread_keys(kSec);
  if (!unread.empty()) {
    sec.fail(unread.front(),
             fmt::format("unknown key (line {}); [{}] holds the icp-slam thresholds, the "
                         "application's switches and the map declarations",
                         ini.line(kSec, unread.front()).value_or(0), kSec));
  }
  o.icp = Icp2dOptions::from_config(ConfigSection(ini, "ICP"));

  bool has_points = false, has_grid = false;
  for (const auto& e : cfg.map.entries()) {
    has_points = has_points || as_points(e.map.get()) != nullptr;
    has_grid = has_grid || as_grid(e.map.get()) != nullptr;
  }
  if (o.match_against_the_grid && !has_grid && !has_points) {
    sec.fail("occupancyGrid_count",
             "matchAgainstTheGrid is set but no occupancy grid (or point map) is declared");
  }
  if (!o.match_against_the_grid && !has_points) {
    sec.fail("pointsMap_count",
             "ICP-SLAM matches against a point map, but none is declared (set pointsMap_count = "
             "1, or matchAgainstTheGrid = true with an occupancy grid)");
  }
  return cfg;
}

void IcpSlam::Travel::update_distances(const Pose2& p) {
  const Pose2 d = p - last;
  lin = d.norm();
  ang = std::abs(d.phi());
}

void IcpSlam::Travel::reset(const Pose2& p) {
  last = p;
  lin = 0.0;
  ang = 0.0;
}

IcpSlam::IcpSlam(IcpSlamOptions options, MultiMetricMap map)
    : options_(std::move(options)), map_(std::move(map)), estimator_(options_.prediction) {
  options_.check();
  for (const auto& e : map_.entries()) {
    if (points_map_ == nullptr && as_points(e.map.get()) != nullptr) points_map_ = e.map.get();
    if (grid_map_ == nullptr && as_grid(e.map.get()) != nullptr) grid_map_ = e.map.get();
  }
  ROVE_CHECK_MSG(points_map_ != nullptr || (options_.match_against_the_grid && grid_map_),
                 "ICP-SLAM needs a point map in the multi-metric map (or a grid when "
                 "match_against_the_grid)");
  // One arithmetic for the whole run (IcpSlamOptions::icp): the scans
  // become points and are inserted into the grids as the ICP computes.
  for (const auto& e : map_.entries()) {
    if (auto* g = as_grid(e.map.get())) g->insert_options.arithmetic = options_.icp.arithmetic;
    if (auto* p = as_points(e.map.get())) p->points().insertion_options.arithmetic = options_.icp.arithmetic;
  }
}

IcpSlam::IcpSlam(IcpSlam&&) noexcept = default;
IcpSlam& IcpSlam::operator=(IcpSlam&&) noexcept = default;
IcpSlam::~IcpSlam() = default;

Pose2 IcpSlam::pose() const { return estimator_.latest_pose().value_or(Pose2()); }

void IcpSlam::accumulate(const Pose2& p) {
  since_icp_.update_distances(p);
  for (auto& [label, t] : since_insertion_) t.update_distances(p);
}

void IcpSlam::reset_counters(const Pose2& p) {
  since_icp_.reset(p);
  for (auto& [label, t] : since_insertion_) t.reset(p);
}

MetricMap* IcpSlam::match_map() const {
  if (options_.match_against_the_grid && grid_map_ != nullptr) return grid_map_;
  return points_map_;
}

const IcpTarget2D& IcpSlam::target() {
  if (target_revision_ == map_revision_) return target_;
  IcpTarget2DOptions to;
  to.arithmetic = options_.icp.arithmetic;
  if (options_.icp.metric == Icp2dMetric::PointToLine) {
    to.normal_neighbors = options_.icp.normal_neighbors;
  }
  MetricMap* m = match_map();
  if (auto* g = as_grid(m)) {
    target_ = IcpTarget2D::from_grid(g->grid(), to);
  } else {
    target_ = IcpTarget2D::from_cloud(as_points(m)->points().cloud(), to);
  }
  target_revision_ = map_revision_;
  return target_;
}

void IcpSlam::process_odometry(const Pose2& odometry, Timestamp time,
                               const std::optional<Twist2>& velocity) {
  ++stats_.odometry;
  odometry_since_icp_ = true;
  const bool had_pose = estimator_.latest_pose().has_value();
  estimator_.update_odometry(odometry, time, velocity);
  if (had_pose) accumulate(*estimator_.latest_pose());
}

void IcpSlam::process(const ActionCollection& actions, const SensoryFrame& frame,
                      Timestamp fallback_time) {
  // MRPT's getBestMovementEstimation.
  const std::shared_ptr<const RobotMovement2D> best = best_movement_2d(actions);
  if (best) {
    accumulated_odometry_ = accumulated_odometry_ + best->mean();
    process_odometry(accumulated_odometry_, best->timestamp.valid() ? best->timestamp : fallback_time,
                     best->velocity);
  }
  for (const auto& o : frame.observations) process(o);
}

IcpSlamUpdate IcpSlam::process(const std::shared_ptr<const Observation>& observation) {
  ROVE_CHECK(observation != nullptr);
  IcpSlamUpdate up;
  if (const auto* odo = dynamic_cast<const OdometryObservation*>(observation.get())) {
    process_odometry(odo->odometry, odo->timestamp, odo->velocity);
    up.odometry = true;
    up.pose = pose();
    return up;
  }
  ++stats_.observations;
  const Observation& obs = *observation;

  // The pose predicted for the observation's time.
  std::optional<Pose2> predicted = estimator_.estimate_at(obs.timestamp);
  if (!predicted) predicted = estimator_.latest_pose();
  up.predicted = predicted.value_or(Pose2());
  accumulate(estimator_.latest_pose().value_or(Pose2()));

  const bool skip_icp =
      odometry_since_icp_ &&
      since_icp_.lin < std::min(options_.localization_lin_distance,
                                options_.insertion_lin_distance) &&
      since_icp_.ang < std::min(options_.localization_ang_distance,
                                options_.insertion_ang_distance);

  MetricMap* matched = match_map();
  bool can_do_icp = false;
  if (!skip_icp) {
    odometry_since_icp_ = false;
    // The observation's points in the robot frame, as MRPT's sensed-points
    // map makes them (one point per 2 cm along the scan).
    PointMap sensed;
    sensed.insertion_options.min_dist_between_points = 0.02f;
    sensed.insertion_options.arithmetic = options_.icp.arithmetic;
    const auto* scan = dynamic_cast<const RangeScan2D*>(&obs);
    const auto* image = dynamic_cast<const RangeImage3D*>(&obs);
    auto* grid = as_grid(matched);
    if (grid != nullptr && grid->insert_options.use_map_altitude) {
      if (scan != nullptr &&
          std::abs(grid->insert_options.map_altitude - scan->T_robot_sensor.z()) < 0.01) {
        can_do_icp = sensed.insert(*scan, Pose3());
      }
    } else if (scan != nullptr) {
      can_do_icp = sensed.insert(*scan, Pose3());
    } else if (image != nullptr) {
      can_do_icp = sensed.insert(*image, Pose3());
    }
    can_do_icp = can_do_icp && !sensed.empty();
    if (as_points(matched) != nullptr && matched->empty()) can_do_icp = false;
    if (can_do_icp) {
      std::vector<Eigen::Vector2d> source;
      source.reserve(sensed.size());
      for (const auto& p : sensed.cloud().points()) {
        source.emplace_back(static_cast<double>(p.x()), static_cast<double>(p.y()));
      }
      Stopwatch sw;
      const Icp2dResult r = icp_2d(target(), source, to_se2(up.predicted), options_.icp);
      stats_.icp_seconds += sw.elapsed();
      ++stats_.icp_runs;
      stats_.icp_iterations += r.iterations;
      up.icp_ran = true;
      up.icp_goodness = r.goodness;
      up.icp_iterations = r.iterations;
      up.icp_termination = r.termination;
      const Pose2 est = to_pose2(r.T_target_source);
      const bool finite = std::isfinite(est.x()) && std::isfinite(est.y()) &&
                          std::isfinite(est.phi()) &&
                          r.termination != RegistrationTermination::Diverged;
      if (std::isfinite(r.goodness)) {
        stats_.icp_goodness_max = std::max(stats_.icp_goodness_max, r.goodness);
      }
      if (!finite) {
        ++stats_.icp_rejected_invalid;
      } else if (!(r.goodness > options_.min_icp_goodness_to_accept)) {
        ++stats_.icp_rejected_goodness;
      } else {
        up.icp_accepted = true;
        ++stats_.icp_accepted;
        estimator_.update_localization(est, obs.timestamp);
        last_cov_ = r.covariance;
        since_icp_.reset(est);
      }
      accumulate(estimator_.latest_pose().value_or(Pose2()));
    }
  }

  // Map update rule (MRPT's CMetricMapBuilderICP).
  const auto it = since_insertion_.find(obs.sensor_label);
  const bool first_for_sensor = it == since_insertion_.end();
  bool update = first_for_sensor;
  if (!first_for_sensor) {
    update = (!can_do_icp || up.icp_accepted) &&
             (it->second.lin >= options_.insertion_lin_distance ||
              it->second.ang >= options_.insertion_ang_distance);
  }
  if (matched->empty()) update = true;

  if (update) {
    const Pose2 now = pose();
    since_insertion_[obs.sensor_label].last = now;
    reset_counters(now);
    Stopwatch sw;
    if (map_.insert(obs, Pose3(now))) ++map_revision_;
    stats_.insert_seconds += sw.elapsed();
    keyframes_.push_back({now, observation});
    ++stats_.insertions;
    up.inserted = true;
  }
  up.pose = pose();
  return up;
}

}  // namespace rove
