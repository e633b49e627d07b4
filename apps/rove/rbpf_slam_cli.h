#pragma once
/// \file
/// `rove rbpf-slam`'s options, shared by its grid-mapping and range-only
/// halves (rbpf_slam_command.cpp, ro_slam_command.cpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "rove/core/json.h"
#include "rove/core/timer.h"
#include "rove/io/tum_trajectory.h"
#include "rove/slam/rbpf_slam_config.h"
#include "rove/slam/rbpf_slam_run.h"

namespace rove::cli {

/// The command line of `rove rbpf-slam`.
struct RbpfSlamCliOptions {
  std::string config;                       ///< MRPT rbpf-slam config
  std::string rawlog;                       ///< the log (default: the config's)
  std::string out_dir = "rbpf-slam-out";    ///< -o
  bool json = false;                        ///< --json
  bool progress = true;                     ///< !--no-progress
  std::uint64_t seed = 0;                   ///< --seed
  int threads = 0;                          ///< --threads (all hardware threads)
  std::optional<std::uint64_t> max_steps;   ///< --max-steps
  std::optional<std::uint32_t> particles;   ///< --particles
  std::string reference;                    ///< --reference (grids)
  std::string truth;                        ///< --ground-truth (beacons)
};

/// Writes `dir`/path.tum (the estimate) and `dir`/odometry.tum, one pose
/// per step (a step without a time gets its index as seconds: TUM needs
/// one), adding them to `files`.
template <typename Step>
void write_rbpf_paths(const std::filesystem::path& dir, const std::vector<Step>& steps,
                      const std::vector<Pose2>& path, std::vector<std::string>& files) {
  std::vector<TimedPose2> est, odo;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const Step& s = steps[k];
    const Timestamp t = s.time.valid() ? s.time : Timestamp::from_seconds(static_cast<double>(s.index));
    est.push_back({t, path[k]});
    odo.push_back({t, s.odometry});
  }
  for (const auto& [name, poses] : {std::pair{"path.tum", &est}, std::pair{"odometry.tum", &odo}}) {
    write_tum_trajectory((dir / name).string(), *poses);
    files.push_back((dir / name).string());
  }
}

/// Writes the summary keys every rbpf-slam run has, from "steps" to
/// "message": steps, updates, insertions, resamplings, ESS mean and
/// minimum, the most likely particle, termination and message.
template <typename Result>
void write_rbpf_counts(JsonWriter& j, const Result& res) {
  std::size_t resampled = 0;
  double ess_sum = 0.0, ess_min = 1.0;
  for (const auto& s : res.steps) {
    if (!s.updated) continue;
    resampled += s.update.resampled ? 1 : 0;
    ess_sum += s.update.ess;
    ess_min = std::min(ess_min, s.update.ess);
  }
  j.key("steps").value(res.steps.size());
  j.key("updates").value(res.updates);
  j.key("insertions").value(res.insertions);
  j.key("resamplings").value(resampled);
  j.key("ess_mean").value(res.updates ? ess_sum / static_cast<double>(res.updates) : 1.0);
  j.key("ess_min").value(ess_min);
  j.key("best_particle").value(res.best);
  j.key("best_weight").value(std::exp(res.best_log_weight));
  j.key("termination").value(to_string(res.termination));
  j.key("message").value(res.message);
}

/// Writes "ignored_keys": the configuration's keys without effect.
void write_ignored_keys(JsonWriter& j, const RbpfSlamConfig& cfg);

/// Range-only SLAM (a configuration with a beacon map): runs it over
/// `rawlog` with `run` and writes beacons.csv, path.tum, odometry.tum,
/// ess.csv, picture.png and summary.json to -o (see docs/filter-slam.md).
void run_ro_slam_command(const RbpfSlamCliOptions& o, const RbpfSlamConfig& cfg,
                         const std::string& rawlog, RbpfSlamRunOptions run, const Stopwatch& total);

}  // namespace rove::cli
