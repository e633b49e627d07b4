#pragma once
/// \file
/// ICP-SLAM: the incremental map builder of MRPT's icp-slam application
/// (CMetricMapBuilderICP), reading its configuration files unchanged.
///
/// Per observation (MRPT's processObservation):
///  - odometry (an OdometryObservation, or the best 2D movement of an action
///    collection accumulated into a cumulative reading) moves the predicted
///    pose (RobotPoseEstimator2D) and the distances travelled since the last
///    localization and insertion;
///  - any other observation: the predicted pose is the estimate at the
///    observation's time (the latest pose if that is unavailable). ICP runs
///    unless odometry arrived since the last ICP and the robot moved less
///    than min(localization, insertion) distance *and* angle since then.
///    ICP matches the observation's points (robot frame, one point per
///    2 cm as MRPT's sensed-points map) against the first grid map when
///    match_against_the_grid and a grid exists, else against the first point
///    map, starting from the predicted pose. The result is accepted when its
///    goodness exceeds min_icp_goodness_to_accept (strictly, as MRPT) and is
///    finite; it then becomes the new localization.
///  - the observation is inserted in the maps at the current pose when it is
///    the first from its sensor label, or when (ICP was not possible or was
///    accepted) and the robot moved at least insertion distance or angle
///    since the last insertion, or whenever the matched map is still empty.
///    An insertion resets every distance counter and records a keyframe.
/// The first scan is therefore inserted at the origin (or at the first
/// odometry reading) without matching.

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/core/ini.h"
#include "rove/core/config_section.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/observation.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/pose2.h"
#include "rove/registration/icp_2d.h"
#include "rove/registration/icp_target_2d.h"
#include "rove/registration/termination.h"
#include "rove/slam/robot_pose_estimator_2d.h"

namespace rove {

/// Options of ICP-SLAM: MRPT's CMetricMapBuilderICP::TConfigParams from the
/// [MappingApplication] section (key names in parentheses, MRPT defaults)
/// and the [ICP] section.
struct IcpSlamOptions {
  /// (matchAgainstTheGrid) match against the first occupancy grid instead
  /// of the first point map. Default false.
  bool match_against_the_grid = false;
  /// (insertionLinDistance) meters, ≥ 0. Default 1.0.
  double insertion_lin_distance = 1.0;
  /// (insertionAngDistance, degrees in the file) radians, ≥ 0. Default 30°.
  double insertion_ang_distance = 30.0 * 3.14159265358979323846 / 180.0;
  /// (localizationLinDistance) meters, ≥ 0. Default 0.2.
  double localization_lin_distance = 0.2;
  /// (localizationAngDistance, degrees in the file) radians, ≥ 0. Default 30°.
  double localization_ang_distance = 30.0 * 3.14159265358979323846 / 180.0;
  /// (minICPgoodnessToAccept) in [0, 1]. Default 0.4.
  double min_icp_goodness_to_accept = 0.4;
  /// The [ICP] section. Its `arithmetic` is the arithmetic of the whole
  /// run: Arithmetic::Mrpt (key `arithmetic = mrpt`, or `rove icp-slam
  /// --arithmetic mrpt`) reproduces MRPT 2.5.8's icp-slam to the bit — the
  /// ICP, its target, the scans' points and their insertion into the map
  /// (IcpSlam sets the PointMapInsertionOptions::arithmetic of its point
  /// maps and the GridInsertionOptions::arithmetic of its grids); the default
  /// Double is rove's double precision throughout.
  Icp2dOptions icp;
  /// Pose prediction (not in MRPT's files; MRPT's defaults).
  RobotPoseEstimator2DOptions prediction;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// Everything an MRPT icp-slam configuration file declares.
struct IcpSlamConfig {
  /// The algorithm's options.
  IcpSlamOptions options;
  /// The maps declared in [MappingApplication] (empty, ready to fill).
  MultiMetricMap map;
  /// (rawlog_file) as written in the file, possibly empty.
  std::string rawlog_file;
  /// (rawlog_offset) steps to skip at the start of the rawlog.
  std::uint64_t rawlog_offset = 0;
  /// ([CARMEN] maxRange, meters) maximum range of a CARMEN log's FLASER /
  /// RLASER scans when the log has no PARAM line stating it; readings at or
  /// above it are "no return" (CarmenLogOptions::flaser_max_range; unset:
  /// its default, 81 m). Not read for rove or MRPT rawlogs.
  std::optional<float> carmen_max_range;
  /// Keys present that have no effect in rove (GUI and logging switches of
  /// MRPT's application, map keys without effect).
  std::vector<IgnoredConfigKey> ignored_keys;
};

/// Reads an MRPT icp-slam configuration: [MappingApplication] (thresholds,
/// the multi-metric map, the application's keys) and [ICP]. Strict: an
/// unknown key of [MappingApplication] or [ICP] is a ConfigError naming the
/// file, section, key and line; so is a malformed or out-of-range value, and
/// a configuration without a map to match against (no point map, and no grid
/// when matchAgainstTheGrid). The optional [CARMEN] section (key maxRange,
/// the name of MRPT's CObservation2DRangeScan field) sets how CARMEN logs are
/// read; an unknown key there is a ConfigError too.
IcpSlamConfig load_icp_slam_config(const IniFile& ini);

/// What ICP-SLAM did with one observation.
struct IcpSlamUpdate {
  /// True for odometry (the other fields then stay at their defaults).
  bool odometry = false;
  /// The predicted pose ICP started from (T_map_robot).
  Pose2 predicted;
  /// True if ICP ran (not skipped, observation gave points, map not empty).
  bool icp_ran = false;
  /// True if ICP ran and its result was accepted.
  bool icp_accepted = false;
  /// ICP's goodness, iterations and termination when it ran.
  double icp_goodness = 0.0;
  unsigned icp_iterations = 0;
  RegistrationTermination icp_termination = RegistrationTermination::InvalidInput;
  /// True if the observation was inserted into the maps (a keyframe).
  bool inserted = false;
  /// The pose after processing (T_map_robot).
  Pose2 pose;
};

/// One keyframe of the map: where the robot was and what it saw there.
struct IcpSlamKeyframe {
  /// T_map_robot when the observation was inserted.
  Pose2 pose;
  /// The inserted observation (shared, not copied).
  std::shared_ptr<const Observation> observation;
};

/// Counters of a run.
struct IcpSlamStats {
  std::size_t observations = 0;    ///< non-odometry observations processed
  std::size_t odometry = 0;        ///< odometry readings processed
  std::size_t icp_runs = 0;        ///< ICP alignments run
  std::size_t icp_accepted = 0;    ///< alignments accepted
  /// Alignments rejected because their goodness was not above
  /// min_icp_goodness_to_accept.
  std::size_t icp_rejected_goodness = 0;
  /// Alignments rejected because they diverged or gave a non-finite pose.
  std::size_t icp_rejected_invalid = 0;
  /// Highest goodness of any alignment run (0 before any).
  double icp_goodness_max = 0.0;
  std::size_t icp_iterations = 0;  ///< sum of ICP iterations
  std::size_t insertions = 0;      ///< observations inserted (keyframes)
  double icp_seconds = 0.0;        ///< time spent in ICP (incl. target rebuilds)
  double insert_seconds = 0.0;     ///< time spent inserting into the maps
};

/// The incremental ICP map builder. See the file comment.
/// Thread-safety: thread-compatible.
class IcpSlam {
 public:
  /// Starts with `map` (usually empty) and nothing observed. Throws
  /// InvalidArgument if options.check() fails or `map` has no map to match
  /// against (a point map, or a grid when match_against_the_grid).
  IcpSlam(IcpSlamOptions options, MultiMetricMap map);
  IcpSlam(IcpSlam&&) noexcept;
  IcpSlam& operator=(IcpSlam&&) noexcept;
  ~IcpSlam();

  /// MRPT's processActionObservation: the best 2D movement of `actions`
  /// (smallest covariance determinant; its time, or `fallback_time` if it
  /// has none) is accumulated into the odometry and processed, then every
  /// observation of `frame` in order.
  void process(const ActionCollection& actions, const SensoryFrame& frame,
               Timestamp fallback_time = {});
  /// MRPT's processObservation for one observation (odometry or sensor).
  IcpSlamUpdate process(const std::shared_ptr<const Observation>& observation);
  /// Processes odometry: `odometry` is a cumulative reading in the odometry
  /// frame at `time`.
  void process_odometry(const Pose2& odometry, Timestamp time,
                        const std::optional<Twist2>& velocity = std::nullopt);

  /// The current pose T_map_robot (the origin before any data).
  Pose2 pose() const;
  /// Covariance of the last accepted ICP fix over the right tangent
  /// (ρx, ρy, θ) (zero before any).
  const Eigen::Matrix3d& last_icp_covariance() const noexcept { return last_cov_; }
  /// The cumulative odometry of the action collections seen so far.
  const Pose2& accumulated_odometry() const noexcept { return accumulated_odometry_; }
  /// The maps.
  const MultiMetricMap& map() const noexcept { return map_; }
  /// The keyframes, in insertion order (MRPT's simple map).
  const std::vector<IcpSlamKeyframe>& keyframes() const noexcept { return keyframes_; }
  /// Counters.
  const IcpSlamStats& stats() const noexcept { return stats_; }
  /// The options.
  const IcpSlamOptions& options() const noexcept { return options_; }

 private:
  struct Travel {  // MRPT's TDist
    Pose2 last;
    double lin = 0.0;
    double ang = 0.0;
    void update_distances(const Pose2& p);
    void reset(const Pose2& p);
  };
  void accumulate(const Pose2& p);
  void reset_counters(const Pose2& p);
  MetricMap* match_map() const;
  const IcpTarget2D& target();

  IcpSlamOptions options_;
  MultiMetricMap map_;
  MetricMap* points_map_ = nullptr;
  MetricMap* grid_map_ = nullptr;
  RobotPoseEstimator2D estimator_;
  Pose2 accumulated_odometry_;
  Eigen::Matrix3d last_cov_ = Eigen::Matrix3d::Zero();
  bool odometry_since_icp_ = false;
  Travel since_icp_;
  std::map<std::string, Travel> since_insertion_;
  std::vector<IcpSlamKeyframe> keyframes_;
  IcpSlamStats stats_;
  IcpTarget2D target_;
  std::uint64_t target_revision_ = ~std::uint64_t{0};
  std::uint64_t map_revision_ = 0;
};

}  // namespace rove
