#include "rove/slam/rbpf_slam_run.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/interrupt.h"
#include "rove/core/timer.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/selection_error.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rawlog_steps.h"

namespace rove {
namespace {

const RangeScan2D* first_scan(const SensoryFrame& frame) {
  for (const auto& o : frame.observations) {
    if (const auto* s = dynamic_cast<const RangeScan2D*>(o.get())) return s;
  }
  return nullptr;
}

SE2d to_se2(const Pose2& p) { return SE2d(p.x(), p.y(), p.phi()); }
Pose2 to_pose2(const SE2d& t) { return Pose2(t.translation().x(), t.translation().y(), t.angle()); }

bool moved(const Pose2& d, double lin, double ang) {
  return d.norm() >= lin || std::abs(d.phi()) >= ang;
}

// Feeds the steps of one log to the filter.
class Runner {
 public:
  Runner(RbpfSlamResult& res, RbpfSlam& slam, const RbpfSlamConfig& config,
         const RbpfSlamRunOptions& options, const std::string& rawlog)
      : res_(res), slam_(slam), config_(config), options_(options), rawlog_(rawlog),
        steps_(default_dummy_odometry()) {}

  // False once max_steps steps are done.
  bool feed(const RawlogEntry& entry, std::uint64_t at) {
    std::optional<detail::RawlogStep> s = steps_.feed(entry);
    if (!s) return true;
    const std::uint64_t index = step_index_++;
    if (index < config_.rawlog_offset) return true;
    if (options_.max_steps && res_.steps.size() >= *options_.max_steps) return false;
    Stopwatch sw;
    RbpfSlamStep step;
    step.index = index;
    step.time = s->time;
    if (s->motion) {
      const Pose2Gaussian g = s->motion->gaussian();
      since_update_ = since_update_ + g;
      since_insertion_ = since_insertion_ + g.mean();
      odometry_ = odometry_ + g.mean();
    }
    step.odometry = odometry_;
    if (const RangeScan2D* scan = first_scan(s->frame)) {
      step.scan = true;
      ++res_.scans;
      try {
        process(*scan, step);
      } catch (const InvalidArgument& e) {
        throw ParseError({rawlog_, std::nullopt, at, "step " + std::to_string(index)},
                         fmt::format("the filter rejected the step's scan: {}", e.message()));
      }
    }
    step.seconds = sw.elapsed();
    res_.mapping_seconds += step.seconds;
    res_.steps.push_back(step);
    if (options_.on_step) options_.on_step(res_.steps.back());
    return true;
  }

  std::uint64_t step_count() const noexcept { return step_index_; }

 private:
  static GaussianMotionOptions default_dummy_odometry() {
    // MRPT's rbpf-slam turns odometry readings of observation-only logs into
    // actions with its default Gaussian model.
    return GaussianMotionOptions{};
  }

  void process(const RangeScan2D& scan, RbpfSlamStep& step) {
    if (!mapped_) {
      res_.insertions += slam_.insert(scan, step.index);
      step.inserted = true;
      mapped_ = true;
      reset(true);
      return;
    }
    const bool insert = moved(since_insertion_, config_.insertion_lin_distance,
                              config_.insertion_ang_distance);
    const bool localize = insert || moved(since_update_.mean(), config_.localize_lin_distance,
                                          config_.localize_ang_distance);
    if (!localize) return;
    const OdometryIncrement motion{to_se2(since_update_.mean()), since_update_.covariance()};
    step.update = slam_.update(motion, scan, step.index, insert);
    step.updated = true;
    step.inserted = insert;
    ++res_.updates;
    res_.insertions += step.update.insertions;
    if (step.update.distinct_tiles > res_.peak_tiles) res_.peak_tiles = step.update.distinct_tiles;
    reset(insert);
  }

  void reset(bool insertion) {
    since_update_ = Pose2Gaussian();
    if (insertion) since_insertion_ = Pose2();
  }

  RbpfSlamResult& res_;
  RbpfSlam& slam_;
  const RbpfSlamConfig& config_;
  const RbpfSlamRunOptions& options_;
  const std::string& rawlog_;
  detail::RawlogStepAssembler steps_;
  Pose2Gaussian since_update_;
  Pose2 since_insertion_, odometry_;
  bool mapped_ = false;
  std::uint64_t step_index_ = 0;
};

// The best particle's pose at every step: its last path node up to the
// step, moved on by the odometry since that node's step.
std::vector<Pose2> best_path(const RbpfSlamResult& res, const RbpfParticle& best) {
  const std::vector<RbpfPathNode> nodes = path_of(best);
  std::vector<Pose2> out;
  out.reserve(res.steps.size());
  std::size_t k = 0;  // next node
  std::optional<std::size_t> last;  // index into res.steps of the last node's step
  std::size_t si = 0;
  for (const RbpfSlamStep& s : res.steps) {
    while (k < nodes.size() && nodes[k].step <= s.index) {
      while (res.steps[si].index < nodes[k].step) ++si;
      last = si;
      ++k;
    }
    if (!last) {
      out.push_back(s.odometry - res.steps.front().odometry);
      continue;
    }
    const Pose2 since = s.odometry - res.steps[*last].odometry;
    out.push_back(to_pose2(nodes[k - 1].pose) + since);
  }
  return out;
}

void conclude(RbpfSlamResult& res, const RbpfSlam& slam, const RbpfSlamConfig& config) {
  std::size_t collapsed = 0, n = 0;
  double fit_sum = 0.0;
  const double particles = static_cast<double>(slam.options().particles);
  for (const auto& s : res.steps) {
    if (!s.updated) continue;
    ++n;
    fit_sum += s.update.fit;
    collapsed += s.update.ess * particles < 1.5 && particles > 1.0 ? 1 : 0;
  }
  if (n == 0) {
    res.issues.push_back({"no-updates", fmt::format("the robot never moved {:g} m or {:g} deg by "
                                                    "odometry: the filter never ran and the map "
                                                    "holds the first scan only",
                                                    config.localize_lin_distance,
                                                    config.localize_ang_distance * 180.0 / 3.14159265358979323846)});
  }
  if (n > 0 && 2 * collapsed > n) {
    res.issues.push_back(
        {"ess-collapse",
         fmt::format("in {} of {} updates the weights sat on fewer than 1.5 effective particles: "
                     "the filter kept a single hypothesis (raise sampleSize or lower powFactor)",
                     collapsed, n)});
  }
  if (n > 0 && fit_sum / static_cast<double>(n) < 0.5) {
    res.issues.push_back(
        {"poor-scan-fit",
         fmt::format("on average {:.0f} % of the scans' points lay within LF_maxCorrsDistance of "
                     "a wall of the most likely map (< 50 %): the map disagrees with the scans",
                     100.0 * fit_sum / static_cast<double>(n))});
  }
  res.termination =
      res.issues.empty() ? RbpfSlamTermination::Completed : RbpfSlamTermination::CompletedWithIssues;
  res.message = fmt::format("{} steps, {} updates, {} insertions, {} particles; most likely particle "
                            "{} (weight {:.3g})",
                            res.steps.size(), res.updates, res.insertions,
                            slam.particles().size(), res.best, std::exp(res.best_log_weight));
}

}  // namespace

std::string_view to_string(RbpfSlamTermination t) noexcept {
  switch (t) {
    case RbpfSlamTermination::Completed: return "completed";
    case RbpfSlamTermination::CompletedWithIssues: return "completed-with-issues";
  }
  return "unknown";
}

RbpfSlamResult run_rbpf_slam(const RbpfSlamConfig& config, const std::string& rawlog_path,
                             const RbpfSlamRunOptions& options) {
  RbpfSlamResult res;
  RbpfSlamOptions o = config.options;
  o.seed = options.seed;
  o.num_threads = options.num_threads;
  if (options.particles) o.particles = *options.particles;
  res.options = o;
  AnyRawlogReader reader(rawlog_path, options.reader);
  res.format = reader.format();
  RbpfSlam slam(o);
  Runner runner(res, slam, config, options, rawlog_path);
  Stopwatch read_sw;
  for (;;) {
    throw_if_interrupted();
    read_sw.reset();
    const std::uint64_t at = reader.position();
    std::optional<RawlogEntry> entry = reader.next();
    res.read_seconds += read_sw.elapsed();
    if (!entry) break;
    ++res.entries;
    if (!runner.feed(*entry, at)) break;
  }
  if (res.steps.empty() && runner.step_count() > 0 && config.rawlog_offset >= runner.step_count()) {
    throw SelectionError("rawlog_offset",
                         fmt::format("rawlog_offset {} skips every step of {}: it has {} steps",
                                     config.rawlog_offset, rawlog_path, runner.step_count()));
  }
  if (res.scans == 0) {
    throw SelectionError("", fmt::format("{} holds no 2D laser scan in its {} processed steps ({} "
                                         "entries): nothing to map",
                                         rawlog_path, res.steps.size(), res.entries));
  }
  res.best = slam.best();
  res.best_log_weight = slam.log_weights()[res.best];
  const RbpfParticle& best = slam.particles()[res.best];
  res.path = best_path(res, best);
  res.map = best.map.to_occupancy_grid();
  for (const auto& p : slam.particles()) res.particles.push_back(p.pose);
  res.peak_tiles = std::max(res.peak_tiles, slam.distinct_tiles());
  res.peak_tile_bytes = res.peak_tiles * sizeof(GridTile);
  std::size_t largest = 0;
  for (const auto& p : slam.particles()) largest = std::max(largest, p.map.tile_count());
  res.unshared_tiles = largest * slam.particles().size();
  conclude(res, slam, config);
  return res;
}

}  // namespace rove
