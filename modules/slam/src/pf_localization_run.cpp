#include "rove/slam/pf_localization_run.h"

#include <cmath>
#include <map>
#include <memory>
#include <sstream>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/core/timer.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/selection_error.h"
#include "rove/poses/angle.h"
#include "rawlog_steps.h"

namespace rove {
namespace {

constexpr const char* kSec = "LocalizationExperiment";

// MRPT's ground-truth files (MonteCarloLocalization_Base::getGroundTruth):
// rows `x y phi` (one per step), `i x y phi` or `t x y phi` (i a step index,
// t a time in seconds: the first column is a time when its first two values
// are not whole numbers), or `t x y z yaw pitch roll`.
class GroundTruth {
 public:
  GroundTruth(const std::string& path, const std::string& config, const std::string& key) {
    const std::string text = read_input_file(path, kMaxTextInputBytes, "ground truth file");
    std::istringstream in(text);
    std::string line;
    std::size_t line_no = 0, cols = 0;
    while (std::getline(in, line)) {
      ++line_no;
      if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '%' || line[0] == '#') {
        continue;
      }
      std::istringstream ls(line);
      std::vector<double> v;
      double x = 0.0;
      while (ls >> x) v.push_back(x);
      if (!ls.eof() || (cols != 0 && v.size() != cols) ||
          (v.size() != 3 && v.size() != 4 && v.size() != 7)) {
        throw ParseError({path, line_no, std::nullopt, key},
                         fmt::format("expected 3, 4 or 7 numbers per row as the first rows (the "
                                     "ground truth named by [{}] {} in {})",
                                     kSec, key, printable(config)));
      }
      for (const double d : v) {
        if (!std::isfinite(d)) throw ParseError({path, line_no, std::nullopt, key}, "not finite");
      }
      cols = v.size();
      rows_.push_back(std::move(v));
    }
    cols_ = cols;
    by_time_ = cols_ != 3 && rows_.size() > 2 && std::floor(rows_[0][0]) != rows_[0][0] &&
               std::floor(rows_[1][0]) != rows_[1][0];
  }

  // The pose of step `index` at `time`, if the file has it (times: linear
  // interpolation between rows at most 0.2 s apart, MRPT's limit).
  std::optional<Pose2> at(std::uint64_t index, Timestamp time) const {
    if (rows_.empty()) return std::nullopt;
    const std::size_t yaw = cols_ == 7 ? 4 : 3;
    if (cols_ == 3) {
      if (index >= rows_.size()) return std::nullopt;
      return Pose2(rows_[index][0], rows_[index][1], rows_[index][2]);
    }
    if (!by_time_) {
      for (const auto& r : rows_) {
        if (r[0] == static_cast<double>(index)) return Pose2(r[1], r[2], r[yaw]);
      }
      return std::nullopt;
    }
    if (!time.valid()) return std::nullopt;
    const double t = time.to_seconds();
    for (std::size_t i = 1; i < rows_.size(); ++i) {
      const auto& a = rows_[i - 1];
      const auto& b = rows_[i];
      if (a[0] <= t && t <= b[0] && b[0] - a[0] <= 0.2) {
        const double s = b[0] > a[0] ? (t - a[0]) / (b[0] - a[0]) : 0.0;
        return Pose2(a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]),
                     a[yaw] + s * wrap_to_pi(b[yaw] - a[yaw]));
      }
    }
    return std::nullopt;
  }

 private:
  std::vector<std::vector<double>> rows_;
  std::size_t cols_ = 0;
  bool by_time_ = false;
};

// Runs the steps of one log and keeps what the result needs.
class Runner {
 public:
  Runner(PfLocalizationResult& result, MonteCarloLocalization& mcl,
         const PfLocalizationConfig& config, const PfLocalizationRunOptions& options,
         const std::optional<GroundTruth>& truth, const std::string& rawlog)
      : res_(result), mcl_(mcl), config_(config), options_(options), truth_(truth),
        rawlog_(rawlog), steps_(mcl.options().dummy_odometry), odometry_(config.initial_odometry) {}

  // Feeds one log entry; false once max_steps steps are done. Increments of
  // an observation-only log get [DummyOdometryParams]' Gaussian model (as
  // MRPT).
  bool feed(const RawlogEntry& entry, std::uint64_t at) {
    const std::optional<detail::RawlogStep> s = steps_.feed(entry);
    if (!s) return true;
    return step(s->motion ? &*s->motion : nullptr, s->frame, s->time, at);
  }

  std::uint64_t step_count() const noexcept { return step_index_; }
  std::uint64_t streak() const noexcept { return streak_; }
  std::optional<std::uint64_t> streak_start() const noexcept { return streak_start_; }

 private:
  bool step(const RobotMovement2D* motion, const SensoryFrame& frame, Timestamp time,
            std::uint64_t at) {
    const std::uint64_t index = step_index_++;
    if (index < config_.rawlog_offset) return true;
    if (options_.max_steps && res_.steps.size() >= *options_.max_steps) return false;
    Stopwatch sw;
    MclStepResult r;
    try {
      r = mcl_.step(motion, frame);
    } catch (const InvalidArgument& e) {
      throw ParseError({rawlog_, std::nullopt, at, "step " + std::to_string(index)},
                       fmt::format("the localization rejected the step: {}", e.message()));
    }
    PfLocalizationStep s;
    s.seconds = sw.elapsed();
    s.index = index;
    s.time = time;
    s.estimate = r.estimate;
    s.particles = r.particles;
    s.ess = r.filter.ess_before_resampling;
    s.informative = r.informative;
    s.degenerate = r.filter.termination == ParticleFilterTermination::Degenerate;
    s.scan_fit = r.scan_fit;
    s.range_residual = r.range_residual;
    s.mass_near = r.mass_near;
    s.converged = r.concentrated && r.fits && r.informative;
    s.injected = r.injected;
    if (motion != nullptr) odometry_ = odometry_ + motion->mean();
    s.odometry = odometry_;
    if (truth_) s.ground_truth = truth_->at(index, time);
    res_.filter_seconds += s.seconds;
    res_.peak_particles = std::max(res_.peak_particles, s.particles);
    track_convergence(s);
    const std::uint64_t n = options_.snapshot_every;
    if (n > 0 && (res_.steps.size() + 1) % n == 0) snapshot("periodic", index);
    res_.steps.push_back(s);
    if (options_.on_step) options_.on_step(res_.steps.back());
    return true;
  }

  void track_convergence(const PfLocalizationStep& s) {
    if (!s.converged) {
      streak_ = 0;
      return;
    }
    if (streak_ == 0) streak_start_ = s.index;
    ++streak_;
    if (streak_ == mcl_.options().convergence.min_steps && !res_.first_converged_step) {
      res_.first_converged_step = streak_start_;
      snapshot("converged", s.index);
    }
  }

  void snapshot(const char* reason, std::uint64_t index) {
    res_.snapshots.push_back({index, reason, mcl_.particles()});
  }

  PfLocalizationResult& res_;
  MonteCarloLocalization& mcl_;
  const PfLocalizationConfig& config_;
  const PfLocalizationRunOptions& options_;
  const std::optional<GroundTruth>& truth_;
  const std::string& rawlog_;
  detail::RawlogStepAssembler steps_;
  Pose2 odometry_;
  std::uint64_t step_index_ = 0;
  std::uint64_t streak_ = 0;
  std::optional<std::uint64_t> streak_start_;
};

void conclude(PfLocalizationResult& res, const Runner& runner, const MclOptions& o) {
  const ConvergenceOptions& c = o.convergence;
  std::size_t degenerate = 0, informative = 0;
  double gt_sum = 0.0;
  std::size_t gt_n = 0;
  bool scan_checked = false, ranges_checked = false;
  for (const auto& s : res.steps) {
    degenerate += s.degenerate ? 1 : 0;
    informative += s.informative ? 1 : 0;
    scan_checked = scan_checked || s.scan_fit.has_value();
    ranges_checked = ranges_checked || s.range_residual.has_value();
    if (s.ground_truth) {
      const Eigen::Vector2d d = s.estimate.mean.translation() -
                                Eigen::Vector2d(s.ground_truth->x(), s.ground_truth->y());
      gt_sum += d.squaredNorm();
      ++gt_n;
    }
  }
  if (gt_n > 0) res.ground_truth_rmse = std::sqrt(gt_sum / static_cast<double>(gt_n));
  const PfLocalizationStep& last = res.steps.back();
  // The criteria name only the map checks that applied to this run.
  const std::string criteria = fmt::format(
      "{:g} % of the weight within {:g} m and {:g} deg of the estimate{}{} for {} steps",
      100.0 * c.min_mass, c.radius, c.heading_radius * 180.0 / std::numbers::pi,
      scan_checked ? fmt::format(", >= {:g} % of the scan within {:g} m of a wall",
                                 100.0 * c.min_scan_fit, c.fit_distance)
                   : std::string(),
      ranges_checked ? fmt::format(", range residual <= {:g} sigma", c.max_range_residual)
                     : std::string(),
      c.min_steps);
  const std::string last_state = fmt::format(
      "last step {}: {:.0f} % of the weight that close, position std {:.3f} m{}{}", last.index,
      100.0 * last.mass_near, last.estimate.position_std,
      last.scan_fit ? fmt::format(", scan fit {:.0f} %", 100.0 * *last.scan_fit) : std::string(),
      last.range_residual ? fmt::format(", range residual {:.2f} sigma", *last.range_residual)
                          : std::string());
  if (runner.streak() >= c.min_steps) {
    res.termination = PfLocalizationTermination::Converged;
    res.converged_step = runner.streak_start();
    res.message = fmt::format("converged at step {} ({}) and stayed so to step {}",
                              *res.converged_step, criteria, last.index);
  } else if (res.first_converged_step) {
    res.termination = PfLocalizationTermination::Lost;
    res.message = fmt::format("converged at step {} but not at the end ({})",
                              *res.first_converged_step, last_state);
    res.issues.push_back({"lost", res.message});
  } else {
    res.termination = PfLocalizationTermination::NotConverged;
    res.message = fmt::format("never converged ({}); {}", criteria, last_state);
    res.issues.push_back({"not-converged", res.message});
  }
  if (informative == 0) {
    res.issues.push_back({"no-observations",
                          fmt::format("none of the {} steps holds an observation the map can "
                                      "evaluate: the particles followed the odometry only",
                                      res.steps.size())});
  }
  if (degenerate > 0) {
    res.issues.push_back({"degenerate-steps",
                          fmt::format("{} of {} steps gave every particle zero likelihood; their "
                                      "observations were ignored",
                                      degenerate, res.steps.size())});
  }
}

}  // namespace

std::string_view to_string(PfLocalizationTermination t) noexcept {
  switch (t) {
    case PfLocalizationTermination::Converged: return "converged";
    case PfLocalizationTermination::NotConverged: return "not-converged";
    case PfLocalizationTermination::Lost: return "lost";
  }
  return "unknown";
}

PfLocalizationResult run_pf_localization(PfLocalizationConfig config,
                                         const std::string& rawlog_path,
                                         const PfLocalizationRunOptions& options) {
  PfLocalizationResult res;
  MclOptions o = config.options;
  o.seed = options.seed;
  o.num_threads = options.num_threads;
  if (options.init) o.init = *options.init;
  if (options.recovery) o.recovery = *options.recovery;
  res.options = o;

  Stopwatch map_sw;
  auto map = std::make_shared<MultiMetricMap>(std::move(config.map));
  res.map_info = load_localization_map(config, *map);
  res.map = map;
  res.map_seconds = map_sw.elapsed();
  std::optional<GroundTruth> truth;
  if (!config.ground_truth_file.empty()) {
    truth.emplace(config.resolve(config.ground_truth_file, "ground_truth_path_file"), config.source,
                  "ground_truth_path_file");
  }

  MonteCarloLocalization mcl(*map, o);
  mcl.initialize();
  res.snapshots.push_back({std::nullopt, "initial", mcl.particles()});
  res.peak_particles = mcl.particles().size();
  Runner runner(res, mcl, config, options, truth, rawlog_path);
  const detail::LogRead read = detail::read_entries(
      rawlog_path, options.reader, [&](const RawlogEntry& e, std::uint64_t at) { return runner.feed(e, at); });
  res.format = read.format;
  res.entries = read.entries;
  res.read_seconds = read.seconds;
  if (res.steps.empty()) {
    if (runner.step_count() > 0 && config.rawlog_offset >= runner.step_count()) {
      throw SelectionError("rawlog_offset",
                           fmt::format("rawlog_offset {} skips every step of {}: it has {} steps",
                                       config.rawlog_offset, rawlog_path, runner.step_count()));
    }
    throw SelectionError("", fmt::format("{} holds no step for the localization ({} entries; an "
                                         "action collection before a sensory frame, or "
                                         "observations)",
                                         rawlog_path, res.entries));
  }
  const PfLocalizationStep& last = res.steps.back();
  const bool final_taken = !res.snapshots.empty() && res.snapshots.back().step == last.index;
  if (!final_taken) res.snapshots.push_back({last.index, "final", mcl.particles()});
  conclude(res, runner, o);
  return res;
}

}  // namespace rove
