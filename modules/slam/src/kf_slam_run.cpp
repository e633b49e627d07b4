#include "rove/slam/kf_slam_run.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <variant>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/timer.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/bearing_range.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/robot_movement_3d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/lie_conversion.h"
#include "rove/slam/ekf_slam.h"
#include "kf_slam_truth.h"
#include "rawlog_steps.h"

namespace rove {
namespace {

// The odometry of an action collection for a `Dim`-D filter: MRPT's
// poseChange Gaussians over (x, y, z, yaw, pitch, roll) or (x, y, phi) as
// right-tangent covariances; std_odo_z_additional added to z's variance.
template <int Dim>
std::optional<EkfSlamOdometry<Dim>> odometry_of(const ActionCollection* actions,
                                                const EkfSlamOptions& o) {
  if (actions == nullptr) return std::nullopt;
  const RobotMovement3D* m3 = nullptr;
  const RobotMovement2D* m2 = nullptr;
  for (const auto& a : actions->actions) {
    if (!m3) m3 = dynamic_cast<const RobotMovement3D*>(a.get());
    if (!m2) m2 = dynamic_cast<const RobotMovement2D*>(a.get());
  }
  if (!m3 && !m2) return std::nullopt;
  Pose3 mean;
  Eigen::Matrix<double, 6, 6> cov = Eigen::Matrix<double, 6, 6>::Zero();
  if (m3 && (Dim == 3 || !m2)) {
    mean = m3->pose_change.mean();
    cov = m3->pose_change.covariance();
  } else {
    const Pose2Gaussian g = m2->gaussian();
    mean = Pose3(g.mean());
    const int idx[3] = {0, 1, 3};  // x, y, yaw in (x, y, z, yaw, pitch, roll)
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) cov(idx[r], idx[c]) = g.covariance()(r, c);
    }
  }
  EkfSlamOdometry<Dim> odo;
  if constexpr (Dim == 3) {
    cov(2, 2) += o.std_odometry_z_additional * o.std_odometry_z_additional;
    odo.increment = to_se3(mean);
    odo.covariance = ypr_to_right_tangent_covariance(mean, cov);
  } else {
    const Pose2 p(mean);
    const int idx[3] = {0, 1, 3};
    Eigen::Matrix3d c2;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) c2(r, c) = cov(idx[r], idx[c]);
    }
    odo.increment = to_se2(p);
    odo.covariance = xyphi_to_right_tangent_covariance(p, c2);
  }
  return odo;
}

template <int Dim>
typename EkfSlamTraits<Dim>::Pose sensor_pose(const Pose3& T) {
  if constexpr (Dim == 3) {
    return to_se3(T);
  } else {
    return to_se2(Pose2(T));
  }
}

template <int Dim>
SE3d as_se3(const typename EkfSlamTraits<Dim>::Pose& X) {
  if constexpr (Dim == 3) {
    return X;
  } else {
    return SE3d(SO3d::exp(Eigen::Vector3d(0.0, 0.0, X.angle())),
                Eigen::Vector3d(X.translation().x(), X.translation().y(), 0.0));
  }
}

Timestamp first_time(const SensoryFrame& sf) {
  for (const auto& o : sf.observations) {
    if (o->timestamp.valid()) return o->timestamp;
  }
  return {};
}

template <int Dim>
class Runner {
 public:
  Runner(const KfSlamConfig& config, const KfSlamRunOptions& options, const KfSlamTruth& truth,
         const std::string& rawlog, KfSlamResult& res)
      : config_(config), options_(options), truth_(truth), rawlog_(rawlog), res_(res),
        slam_(res.options) {}

  // Feeds one log entry; false once max_steps steps are done.
  bool feed(const RawlogEntry& entry, std::uint64_t at) {
    if (const auto* ac = std::get_if<std::shared_ptr<const ActionCollection>>(&entry)) {
      pending_ = *ac;
      return true;
    }
    if (const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&entry)) {
      const auto actions = std::move(pending_);
      pending_.reset();
      std::vector<const BearingRange*> obs;
      for (const auto& o : (*sf)->observations) {
        if (const auto* b = dynamic_cast<const BearingRange*>(o.get())) obs.push_back(b);
      }
      return step(actions.get(), obs, first_time(**sf), at);
    }
    const auto& o = std::get<std::shared_ptr<const Observation>>(entry);
    if (const auto* b = dynamic_cast<const BearingRange*>(o.get())) {
      return step(nullptr, {b}, b->timestamp, at);
    }
    return true;
  }

  std::uint64_t step_count() const noexcept { return index_; }
  const EkfSlam<Dim>& slam() const noexcept { return slam_; }
  const std::vector<std::uint64_t>& first_steps() const noexcept { return first_step_; }
  const std::vector<std::optional<std::int64_t>>& landmark_truth() const noexcept {
    return landmark_truth_;
  }

 private:
  bool step(const ActionCollection* actions, const std::vector<const BearingRange*>& obs,
            Timestamp time, std::uint64_t at) {
    const std::uint64_t index = index_++;
    if (index < config_.rawlog_offset) return true;
    if (options_.max_steps && res_.steps.size() >= *options_.max_steps) return false;
    KfSlamStep s;
    s.index = index;
    s.time = time;
    if (index < truth_.path.size()) s.ground_truth = truth_.path[index];
    Stopwatch sw;
    slam_.predict(odometry_of<Dim>(actions, res_.options));
    for (const BearingRange* b : obs) update(*b, s, at);
    s.seconds = sw.elapsed();
    s.pose = as_se3<Dim>(slam_.pose());
    s.position_std =
        std::sqrt(slam_.pose_covariance().template topLeftCorner<Dim, Dim>().trace());
    s.landmarks = slam_.landmark_count();
    res_.filter_seconds += s.seconds;
    res_.steps.push_back(s);
    if (options_.on_step) options_.on_step(res_.steps.back());
    return true;
  }

  void update(const BearingRange& b, KfSlamStep& s, std::uint64_t at) {
    EkfSlamFrame<Dim> frame;
    frame.T_robot_sensor = sensor_pose<Dim>(b.T_robot_sensor);
    for (std::size_t j = 0; j < b.measurements.size(); ++j) {
      const LandmarkMeasurement& m = b.measurements[j];
      if (!std::isfinite(m.range) || !std::isfinite(m.yaw) || !std::isfinite(m.pitch)) {
        throw ParseError({rawlog_, std::nullopt, at, fmt::format("step {}", s.index)},
                         fmt::format("reading {} of a BearingRange is not finite (range {}, yaw {}, "
                                     "pitch {})",
                                     j, m.range, m.yaw, m.pitch));
      }
      EkfSlamReading<Dim> r;
      r.id = m.landmark_id;
      if constexpr (Dim == 3) {
        r.z = Eigen::Vector3d(m.range, m.yaw, m.pitch);
      } else {
        r.z = Eigen::Vector2d(m.range, m.yaw);
      }
      frame.readings.push_back(r);
    }
    const EkfSlamStepResult r = slam_.update(frame);
    s.readings += frame.readings.size();
    s.by_id += r.by_id, s.associated += r.associated, s.created += r.created;
    s.skipped += r.skipped;
    s.nis += r.nis, s.nis_dof += r.nis_dof;
    s.update_skipped = s.update_skipped || r.termination != EkfSlamTermination::Updated;
    if (r.association) {
      s.jcbb_nodes += r.association->nodes;
      if (r.association->termination == DataAssociationTermination::NodeLimit) {
        ++res_.association.node_limit_steps;
      }
    }
    check_pairings(b, r, s);
  }

  // Counts the pairings against the ground truth of each reading.
  void check_pairings(const BearingRange& b, const EkfSlamStepResult& r, const KfSlamStep& s) {
    KfSlamAssociationStats& a = res_.association;
    for (std::size_t j = 0; j < r.outcome.size(); ++j) {
      if (r.outcome[j] == ReadingOutcome::Skipped) continue;
      const std::optional<std::int64_t> t =
          truth_.reading_truth(b.measurements[j], b.T_robot_sensor, s.ground_truth);
      const auto l = static_cast<std::size_t>(r.landmark[j]);
      if (r.outcome[j] == ReadingOutcome::NewLandmark) {
        first_step_.push_back(s.index);
        landmark_truth_.push_back(t);
        if (t && std::find(landmark_truth_.begin(), landmark_truth_.end() - 1, t) !=
                     landmark_truth_.end() - 1) {
          ++a.duplicates;
        }
      } else if (t && landmark_truth_[l]) {
        ++(*landmark_truth_[l] == *t ? a.correct : a.wrong);
      }
      if (t) ++a.with_truth;
    }
    a.readings += r.outcome.size();
    a.by_id += r.by_id, a.associated += r.associated, a.created += r.created;
    a.skipped += r.skipped;
  }

  const KfSlamConfig& config_;
  const KfSlamRunOptions& options_;
  const KfSlamTruth& truth_;
  const std::string& rawlog_;
  KfSlamResult& res_;
  EkfSlam<Dim> slam_;
  std::shared_ptr<const ActionCollection> pending_;
  std::uint64_t index_ = 0;
  std::vector<std::uint64_t> first_step_;
  std::vector<std::optional<std::int64_t>> landmark_truth_;
};

template <int Dim>
void collect_landmarks(const Runner<Dim>& runner, const KfSlamTruth& truth, KfSlamResult& res) {
  const EkfSlam<Dim>& slam = runner.slam();
  res.final_pose_covariance = slam.pose_covariance();
  std::map<std::int64_t, bool> taken;
  double sum2 = 0.0;
  for (std::size_t i = 0; i < slam.landmark_count(); ++i) {
    KfSlamLandmark l;
    l.id = slam.landmark_id(i);
    l.mean.head<Dim>() = slam.landmark(i);
    l.covariance.topLeftCorner<Dim, Dim>() = slam.landmark_covariance(i);
    l.observations = slam.landmark_observations(i);
    l.first_step = runner.first_steps()[i];
    l.truth_id = runner.landmark_truth()[i];
    if (l.truth_id && !taken[*l.truth_id]) {
      const auto it = truth.landmarks.find(*l.truth_id);
      if (it != truth.landmarks.end()) {
        taken[*l.truth_id] = true;
        l.truth = it->second;
        if (Dim == 2) l.truth->z() = 0.0;
        l.error = (l.mean - *l.truth).norm();
        sum2 += *l.error * *l.error;
        ++res.landmarks_with_truth;
      }
    }
    res.landmarks.push_back(l);
  }
  if (res.landmarks_with_truth > 0) {
    res.landmark_rmse = std::sqrt(sum2 / static_cast<double>(res.landmarks_with_truth));
  }
}

void path_errors(KfSlamResult& res) {
  double p2 = 0.0, h2 = 0.0;
  std::size_t n = 0;
  for (const KfSlamStep& s : res.steps) {
    if (!s.ground_truth) continue;
    const SE3d& g = *s.ground_truth;
    const double dp = (res.dim == 2 ? (s.pose.translation() - g.translation()).head<2>().norm()
                                    : (s.pose.translation() - g.translation()).norm());
    const double dh = (g.rotation().inverse() * s.pose.rotation()).log().norm();
    p2 += dp * dp, h2 += dh * dh, ++n;
  }
  if (n == 0) return;
  res.path_rmse = std::sqrt(p2 / static_cast<double>(n));
  res.heading_rmse = std::sqrt(h2 / static_cast<double>(n));
}

template <int Dim>
void run(const KfSlamConfig& config, const std::string& rawlog_path,
         const KfSlamRunOptions& options, const KfSlamTruth& truth, KfSlamResult& res) {
  Runner<Dim> runner(config, options, truth, rawlog_path, res);
  const detail::LogRead read = detail::read_entries(
      rawlog_path, options.reader, [&](const RawlogEntry& e, std::uint64_t at) { return runner.feed(e, at); });
  res.format = read.format;
  res.entries = read.entries;
  res.read_seconds = read.seconds;
  if (runner.step_count() > 0 && config.rawlog_offset >= runner.step_count()) {
    throw ConfigError(config.source, "MappingApplication", "rawlog_offset",
                      fmt::format("rawlog_offset {} skips every step of {}: it has {} steps",
                                  config.rawlog_offset, rawlog_path, runner.step_count()));
  }
  collect_landmarks(runner, truth, res);
}

}  // namespace

KfSlamResult run_kf_slam(const KfSlamConfig& config, const std::string& rawlog_path,
                         const KfSlamRunOptions& options) {
  KfSlamResult res;
  res.dim = config.dim;
  res.options = config.options;
  if (options.use_landmark_ids) res.options.use_landmark_ids = *options.use_landmark_ids;
  const KfSlamTruth truth = load_kf_slam_truth(config, options.truth_gate);
  if (config.dim == 2) {
    run<2>(config, rawlog_path, options, truth, res);
  } else {
    run<3>(config, rawlog_path, options, truth, res);
  }
  path_errors(res);
  add_kf_slam_issues(res);
  return res;
}

}  // namespace rove
