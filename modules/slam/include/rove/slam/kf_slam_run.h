#pragma once
/// \file
/// Running EKF landmark SLAM (rove/slam/ekf_slam.h) over a whole log from
/// one of MRPT's kf-slam configuration files, read unchanged, as MRPT's
/// kf-slam application does, and measuring the result against the ground
/// truth the configuration names.
///
/// Configuration: [MappingApplication] `kf_implementation`
/// (CRangeBearingKFSLAM: 6-DoF robot, 3D landmarks, the default;
/// CRangeBearingKFSLAM2D: planar), `rawlog_file`, `rawlog_offset`,
/// `ground_truth_file` (landmarks: rows `x y z … id`, the ID in the 7th
/// column, as MRPT's simulator writes them), `ground_truth_file_robot` (the
/// robot pose of every step: rows `x y z yaw pitch roll` or `x y phi`);
/// MRPT's log, window and scene switches are listed as without effect.
/// [RangeBearingKFSLAM] and [RangeBearingKFSLAM_KalmanFilter]:
/// EkfSlamOptions::from_config. Unknown keys are ConfigErrors.
///
/// Steps: in a log of actions and sensory frames one step is an action
/// collection (its RobotMovement3D or RobotMovement2D is the odometry) with
/// the sensory frame after it; every BearingRange of the frame updates the
/// filter in turn. In an observation-only log every BearingRange is a step
/// without odometry. Step k is compared with row k of the robot ground truth.
///
/// Ground truth of the pairings: a reading's true landmark is its ID when
/// the log has IDs (the check that matters when use_landmark_ids = false
/// makes the filter associate them blindly); without IDs, the ground-truth
/// landmark nearest to the reading placed from the ground-truth pose, if
/// within `truth_gate` of it. A landmark's truth is that of the reading that
/// started it. A pairing is wrong when the reading's truth differs from its
/// landmark's; a new landmark whose truth already has one is a duplicate.
/// Landmark errors are over the first landmark of each truth.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"
#include "rove/core/ini.h"
#include "rove/io/any_rawlog.h"
#include "rove/math/se3.h"
#include "rove/obs/timestamp.h"
#include "rove/slam/ekf_slam_options.h"

namespace rove {

/// A kf-slam configuration.
struct KfSlamConfig {
  /// 2 (CRangeBearingKFSLAM2D) or 3 (CRangeBearingKFSLAM).
  int dim = 3;
  /// The filter's options.
  EkfSlamOptions options = EkfSlamOptions::defaults(3);
  /// `rawlog_file` as written, possibly empty.
  std::string rawlog_file;
  /// `ground_truth_file` as written, possibly empty.
  std::string ground_truth_file;
  /// `ground_truth_file_robot` as written, possibly empty.
  std::string ground_truth_file_robot;
  /// `rawlog_offset`: steps skipped at the start.
  std::uint64_t rawlog_offset = 0;
  /// The configuration file (IniFile::source()).
  std::string source;
  /// Keys present that have no effect in rove.
  std::vector<IgnoredConfigKey> ignored_keys;

  /// A file of [MappingApplication] as it exists (resolve_config_path);
  /// ConfigError naming `key` if it does not.
  std::string resolve(const std::string& path, const std::string& key) const;
};

/// Reads a kf-slam configuration (see the file comment). Throws ConfigError
/// (file, section, key, line) for an unknown key, a malformed value or a
/// file with none of the three sections.
KfSlamConfig load_kf_slam_config(const IniFile& ini);

/// One step of a run: the state after it.
struct KfSlamStep {
  /// 0-based step index in the log (steps skipped by rawlog_offset counted).
  std::uint64_t index = 0;
  /// Time of the step's first observation (invalid if none has one).
  Timestamp time;
  /// The robot pose mean, T_world_robot (planar runs: z = 0, level).
  SE3d pose;
  /// Robot position standard deviation, m (√ of the trace of its block).
  double position_std = 0.0;
  /// Readings seen, paired by ID, associated, new landmarks, skipped.
  std::size_t readings = 0, by_id = 0, associated = 0, created = 0, skipped = 0;
  /// NIS of the step's update and its degrees of freedom.
  double nis = 0.0;
  /// Degrees of freedom of nis.
  std::size_t nis_dof = 0;
  /// Landmarks in the map after the step.
  std::size_t landmarks = 0;
  /// JCBB nodes visited in the step.
  std::size_t jcbb_nodes = 0;
  /// True if an update was skipped (innovation covariance not positive definite).
  bool update_skipped = false;
  /// The ground-truth robot pose of the step, when the configuration has one.
  std::optional<SE3d> ground_truth;
  /// Wall time of the filter step, seconds (reading excluded).
  double seconds = 0.0;
};

/// One mapped landmark at the end of a run.
struct KfSlamLandmark {
  /// Its ID (from the readings; −1 if they had none).
  std::int64_t id = -1;
  /// Position mean, world frame (m); planar runs: z = 0.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  /// Position covariance (m²); planar runs: the z row and column are 0.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  /// Times observed.
  std::size_t observations = 0;
  /// Step that started it.
  std::uint64_t first_step = 0;
  /// The ground-truth landmark it stands for (see the file comment).
  std::optional<std::int64_t> truth_id;
  /// That landmark's true position, and the error to it (m), for the first
  /// landmark of each truth.
  std::optional<Eigen::Vector3d> truth;
  /// ‖mean − truth‖, m.
  std::optional<double> error;
};

/// Pairing counts over a run, and their check against the ground truth.
struct KfSlamAssociationStats {
  /// Readings, paired by ID, associated, new landmarks, skipped (range ≤ 0
  /// or an ID repeated within a frame).
  std::size_t readings = 0, by_id = 0, associated = 0, created = 0, skipped = 0;
  /// Readings whose true landmark is known (see the file comment).
  std::size_t with_truth = 0;
  /// Pairings with a mapped landmark whose truth agrees / differs.
  std::size_t correct = 0, wrong = 0;
  /// New landmarks for a truth already mapped.
  std::size_t duplicates = 0;
  /// Data-association runs that stopped at the JCBB node limit.
  std::size_t node_limit_steps = 0;
};

/// Something the user must know about a finished run.
struct KfSlamIssue {
  /// "wrong-associations", "duplicate-landmarks", "landmarks-seen-once",
  /// "skipped-readings", "updates-skipped", "no-readings",
  /// "innovations-too-large", "untracked-landmarks", "association-node-limit".
  std::string code;
  /// One line for a person.
  std::string message;
};

/// Options of run_kf_slam (what the command line sets).
struct KfSlamRunOptions {
  /// Replace the configuration's use_landmark_ids.
  std::optional<bool> use_landmark_ids;
  /// Stop after this many processed steps (all if unset).
  std::optional<std::uint64_t> max_steps;
  /// Greatest distance (m) between a reading placed from the ground-truth
  /// pose and the ground-truth landmark it is taken for (logs without IDs).
  double truth_gate = 0.5;
  /// Options of the log reader.
  AnyRawlogOptions reader;
  /// Called after every processed step, if set.
  std::function<void(const KfSlamStep&)> on_step;
};

/// The result of run_kf_slam.
struct KfSlamResult {
  /// The configuration's dimension (2 or 3).
  int dim = 3;
  /// The options used.
  EkfSlamOptions options;
  /// The log's format.
  RawlogFormat format = RawlogFormat::Mrpt;
  /// Every processed step.
  std::vector<KfSlamStep> steps;
  /// The map at the end.
  std::vector<KfSlamLandmark> landmarks;
  /// Pairing counts.
  KfSlamAssociationStats association;
  /// Landmark position RMSE against the ground truth (m), over the first
  /// landmark of each truth, when the configuration has one.
  std::optional<double> landmark_rmse;
  /// Landmarks with a truth (count of the RMSE).
  std::size_t landmarks_with_truth = 0;
  /// Robot position RMSE over the steps with a ground-truth pose (m).
  std::optional<double> path_rmse;
  /// Robot heading RMSE over those steps (rad; 3D: rotation angle).
  std::optional<double> heading_rmse;
  /// Sum of the steps' NIS and of their degrees of freedom.
  double nis_sum = 0.0;
  /// Degrees of freedom of nis_sum.
  std::size_t nis_dof = 0;
  /// Robot pose covariance at the end, over its right tangent (3×3 or 6×6).
  Eigen::MatrixXd final_pose_covariance;
  /// Entries read from the log.
  std::uint64_t entries = 0;
  /// Seconds in the filter and in reading the log.
  double filter_seconds = 0.0, read_seconds = 0.0;
  /// What the user must know.
  std::vector<KfSlamIssue> issues;
};

/// Runs EKF-SLAM over the log at `rawlog_path` with `config` (paths of the
/// configuration resolved with config.resolve). Throws IoError / ParseError
/// on unreadable logs and ground-truth files (naming file, offset or line
/// and field), ParseError naming the step for a non-finite reading, and
/// ConfigError when rawlog_offset skips every step.
KfSlamResult run_kf_slam(const KfSlamConfig& config, const std::string& rawlog_path,
                         const KfSlamRunOptions& options = {});

}  // namespace rove
