#pragma once
// Feeding the steps of a log to an RBPF filter as MRPT's rbpf-slam does
// (CMetricMapBuilderRBPF), shared by grid mapping (rbpf_slam_run.cpp) and
// range-only SLAM (ro_slam_run.cpp): the steps move the odometry; the first
// observation of the filter's kind is inserted at the origin; afterwards,
// once the robot has moved localizeLinDistance or localizeAngDistance by
// odometry since the last update, the filter runs with the accumulated
// odometry (the actions' Gaussian models composed) and the step's first
// observation of its kind, and once it has moved insertionLinDistance or
// insertionAngDistance since the last insertion the observation is inserted
// too (a step that inserts always updates first).

#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/interrupt.h"
#include "rove/io/any_rawlog.h"
#include "rove/obs/selection_error.h"
#include "rove/core/timer.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rove/slam/rbpf_slam.h"
#include "rove/slam/rbpf_slam_config.h"
#include "rove/slam/rbpf_slam_run.h"
#include "rawlog_steps.h"

namespace rove::detail {

/// What a run counts besides its steps.
struct RbpfRunCounts {
  std::uint64_t observations = 0;  // steps holding an observation of the filter's kind
  std::uint64_t updates = 0;
  std::uint64_t insertions = 0;
  double seconds = 0.0;  // processing time of the steps
};

/// Feeds log entries to `Filter` (RbpfSlam or RoSlam), which observes `Obs`;
/// `Step` records a step (index, time, odometry, updated, inserted, update,
/// seconds, and the flag `kObserved`).
template <typename Obs, typename Filter, typename Step, bool Step::*kObserved>
class RbpfRunner {
 public:
  RbpfRunner(Filter& filter, const RbpfSlamConfig& config, std::optional<std::uint64_t> max_steps,
             std::function<void(const Step&)> on_step, const std::string& rawlog,
             std::vector<Step>& steps, RbpfRunCounts& counts)
      : filter_(filter), config_(config), max_steps_(max_steps), on_step_(std::move(on_step)),
        rawlog_(rawlog), steps_out_(steps), counts_(counts),
        // MRPT's rbpf-slam turns odometry readings of observation-only logs
        // into actions with its default Gaussian model.
        steps_(GaussianMotionOptions{}) {}

  /// Feeds the entry read at byte offset `at`; false once max_steps steps
  /// are done. Throws ParseError naming the step's offset when the filter
  /// rejects its observation.
  bool feed(const RawlogEntry& entry, std::uint64_t at) {
    std::optional<RawlogStep> s = steps_.feed(entry);
    if (!s) return true;
    const std::uint64_t index = step_index_++;
    if (index < config_.rawlog_offset) return true;
    if (max_steps_ && steps_out_.size() >= *max_steps_) return false;
    Stopwatch sw;
    Step step;
    step.index = index;
    step.time = s->time;
    if (s->motion) {
      const Pose2Gaussian g = s->motion->gaussian();
      since_update_ = since_update_ + g;
      since_insertion_ = since_insertion_ + g.mean();
      odometry_ = odometry_ + g.mean();
    }
    step.odometry = odometry_;
    if (const std::shared_ptr<const Obs> obs = s->frame.template find<Obs>()) {
      step.*kObserved = true;
      ++counts_.observations;
      try {
        process(*obs, step);
      } catch (const InvalidArgument& e) {
        throw ParseError({rawlog_, std::nullopt, at, "step " + std::to_string(index)},
                         fmt::format("the filter rejected the step's observation: {}", e.message()));
      }
    }
    step.seconds = sw.elapsed();
    counts_.seconds += step.seconds;
    steps_out_.push_back(std::move(step));
    if (on_step_) on_step_(steps_out_.back());
    return true;
  }

  /// Steps met so far (counting those skipped by rawlog_offset).
  std::uint64_t step_count() const noexcept { return step_index_; }

 private:
  static bool moved(const Pose2& d, double lin, double ang) {
    return d.norm() >= lin || std::abs(d.phi()) >= ang;
  }

  void process(const Obs& obs, Step& step) {
    if (!mapped_) {
      counts_.insertions += filter_.insert(obs, step.index);
      step.inserted = true;
      mapped_ = true;
      reset(true);
      return;
    }
    const bool insert =
        moved(since_insertion_, config_.insertion_lin_distance, config_.insertion_ang_distance);
    const bool localize = insert || moved(since_update_.mean(), config_.localize_lin_distance,
                                          config_.localize_ang_distance);
    if (!localize) return;
    const Pose2& m = since_update_.mean();
    const OdometryIncrement motion{SE2d(m.x(), m.y(), m.phi()), since_update_.covariance()};
    step.update = filter_.update(motion, obs, step.index, insert);
    step.updated = true;
    step.inserted = insert;
    ++counts_.updates;
    counts_.insertions += step.update.insertions;
    reset(insert);
  }

  void reset(bool insertion) {
    since_update_ = Pose2Gaussian();
    if (insertion) since_insertion_ = Pose2();
  }

  Filter& filter_;
  const RbpfSlamConfig& config_;
  std::optional<std::uint64_t> max_steps_;
  std::function<void(const Step&)> on_step_;
  const std::string& rawlog_;
  std::vector<Step>& steps_out_;
  RbpfRunCounts& counts_;
  RawlogStepAssembler steps_;
  Pose2Gaussian since_update_;
  Pose2 since_insertion_, odometry_;
  bool mapped_ = false;
  std::uint64_t step_index_ = 0;
};

/// The pose of a filter's most likely particle at every step: its last
/// path node up to the step, moved on by the odometry since that node's
/// step (before its first node: the odometry since the first step).
template <typename Step>
std::vector<Pose2> best_path(const std::vector<Step>& steps, const std::vector<RbpfPathNode>& nodes) {
  std::vector<Pose2> out;
  out.reserve(steps.size());
  std::size_t k = 0;                // next node
  std::optional<std::size_t> last;  // index into steps of the last node's step
  std::size_t si = 0;
  for (const Step& s : steps) {
    while (k < nodes.size() && nodes[k].step <= s.index) {
      while (steps[si].index < nodes[k].step) ++si;
      last = si;
      ++k;
    }
    if (!last) {
      out.push_back(s.odometry - steps.front().odometry);
      continue;
    }
    const Pose2 since = s.odometry - steps[*last].odometry;
    const SE2d& T = nodes[k - 1].pose;
    out.push_back(Pose2(T.translation().x(), T.translation().y(), T.angle()) + since);
  }
  return out;
}

/// The issues every RBPF run can have (rove/slam/rbpf_slam_run.h):
/// "no-updates" and "ess-collapse".
template <typename Step>
std::vector<RbpfSlamIssue> filter_issues(const std::vector<Step>& steps, std::size_t particles,
                                         const RbpfSlamConfig& config) {
  std::vector<RbpfSlamIssue> out;
  std::size_t collapsed = 0, n = 0;
  for (const auto& s : steps) {
    if (!s.updated) continue;
    ++n;
    collapsed += s.update.ess * static_cast<double>(particles) < 1.5 && particles > 1 ? 1 : 0;
  }
  if (n == 0) {
    out.push_back({"no-updates", fmt::format("the robot never moved {:g} m or {:g} deg by odometry: "
                                             "the filter never ran and the map holds the first "
                                             "observation only",
                                             config.localize_lin_distance,
                                             config.localize_ang_distance * 180.0 / 3.14159265358979323846)});
  }
  if (n > 0 && 2 * collapsed > n) {
    out.push_back(
        {"ess-collapse",
         fmt::format("in {} of {} updates the weights sat on fewer than 1.5 effective particles: "
                     "the filter kept a single hypothesis (raise sampleSize or lower powFactor)",
                     collapsed, n)});
  }
  return out;
}

/// Reads the log at `path` through `runner` (an RbpfRunner writing `steps`
/// and `counts`), polling rove::throw_if_interrupted() once per entry.
/// Throws SelectionError when rawlog_offset skips every step, or when no
/// processed step held the filter's observation (`what` names it).
template <typename Runner, typename Steps>
LogRead read_log(Runner& runner, const std::string& path, const AnyRawlogOptions& options,
                     const RbpfSlamConfig& config, const RbpfRunCounts& counts, const Steps& steps,
                     const char* what) {
  const LogRead out =
      read_entries(path, options, [&](const RawlogEntry& e, std::uint64_t at) { return runner.feed(e, at); });
  if (steps.empty() && runner.step_count() > 0 && config.rawlog_offset >= runner.step_count()) {
    throw SelectionError("rawlog_offset",
                         fmt::format("rawlog_offset {} skips every step of {}: it has {} steps",
                                     config.rawlog_offset, path, runner.step_count()));
  }
  if (counts.observations == 0) {
    throw SelectionError("", fmt::format("{} holds no {} in its {} processed steps ({} entries): "
                                         "nothing to map",
                                         path, what, steps.size(), out.entries));
  }
  return out;
}

/// The filter's options with the run's seed, threads and particle count.
template <typename Options>
Options with_run_options(Options o, const RbpfSlamRunOptions& run) {
  o.seed = run.seed;
  o.num_threads = run.num_threads;
  if (run.particles) o.particles = *run.particles;
  return o;
}

/// Runs `filter` (observing `Obs`) over the log at `rawlog` (read_log),
/// recording its steps; `also(step)` is called after each step before the
/// run options' on_step.
template <typename Obs, typename Step, bool Step::*kObserved, typename Filter>
LogRead run_filter_over_log(Filter& filter, const RbpfSlamConfig& config,
                                const RbpfSlamRunOptions& options, const std::string& rawlog,
                                std::vector<Step>& steps, RbpfRunCounts& counts, const char* what,
                                const std::function<void(const Step&)>& also = {}) {
  const auto on_step = [&](const Step& s) {
    if (also) also(s);
    if (options.on_step) options.on_step(s.index);
  };
  RbpfRunner<Obs, Filter, Step, kObserved> runner(filter, config, options.max_steps, on_step, rawlog,
                                                  steps, counts);
  return read_log(runner, rawlog, options.reader, config, counts, steps, what);
}

/// Fills what `totals` takes from the log's reading, the runner's counts
/// and the filter's most likely particle, whose path `nodes` are.
template <typename Filter, typename Step>
void fill_totals(RbpfRunTotals& totals, const LogRead& read, const RbpfRunCounts& counts,
                 const Filter& filter, const std::vector<Step>& steps,
                 const std::vector<RbpfPathNode>& nodes) {
  totals.format = read.format;
  totals.entries = read.entries;
  totals.read_seconds = read.seconds;
  totals.updates = counts.updates;
  totals.insertions = counts.insertions;
  totals.mapping_seconds = counts.seconds;
  totals.best = filter.best();
  totals.best_log_weight = filter.log_weights()[totals.best];
  totals.path = best_path(steps, nodes);
  for (const auto& p : filter.particles()) totals.particles.push_back(p.pose);
}

}  // namespace rove::detail
