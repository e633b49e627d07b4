#include "rove/slam/icp_slam_run.h"

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "log_counts.h"
#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/interrupt.h"
#include "rove/core/timer.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/selection_error.h"

namespace rove {
namespace {

Timestamp first_time(const SensoryFrame& frame) {
  for (const auto& o : frame.observations) {
    if (o->timestamp.valid()) return o->timestamp;
  }
  return {};
}

bool matchable(const Observation& o) {
  return dynamic_cast<const RangeScan2D*>(&o) != nullptr ||
         dynamic_cast<const RangeImage3D*>(&o) != nullptr;
}

}  // namespace

std::vector<IcpSlamIssue> icp_slam_issues(const IcpSlamStats& st, const IcpSlamOptions& options,
                                          double min_accepted_fraction) {
  ROVE_CHECK_MSG(min_accepted_fraction >= 0.0 && min_accepted_fraction <= 1.0,
                 "min_accepted_fraction {} must lie in [0, 1]", min_accepted_fraction);
  std::vector<IcpSlamIssue> issues;
  if (st.icp_runs == 0) return issues;
  const std::string rejected = fmt::format(
      "{} rejected for goodness <= minICPgoodnessToAccept {:g} (best goodness {:.3f}), {} for "
      "diverging",
      st.icp_rejected_goodness, options.min_icp_goodness_to_accept, st.icp_goodness_max,
      st.icp_rejected_invalid);
  if (st.icp_accepted == 0) {
    issues.push_back({"no-icp-accepted",
                      fmt::format("none of {} ICP results was accepted ({}): the path is the "
                                  "odometry and the map holds only scans inserted without "
                                  "matching",
                                  st.icp_runs, rejected)});
  } else if (static_cast<double>(st.icp_accepted) <
             min_accepted_fraction * static_cast<double>(st.icp_runs)) {
    issues.push_back(
        {"few-icp-accepted",
         fmt::format("only {} of {} ICP results were accepted ({:.1f} %, under {:g} %; {}): the "
                     "path follows the odometry wherever ICP was rejected",
                     st.icp_accepted, st.icp_runs,
                     100.0 * static_cast<double>(st.icp_accepted) / static_cast<double>(st.icp_runs),
                     100.0 * min_accepted_fraction, rejected)});
  }
  return issues;
}

IcpSlamRunResult run_icp_slam(IcpSlam& slam, const std::string& rawlog_path,
                              const IcpSlamRunOptions& options) {
  IcpSlamRunResult result;
  AnyRawlogReader reader(rawlog_path, options.reader);
  result.format = reader.format();
  std::shared_ptr<const ActionCollection> pending_action;
  std::uint64_t step_index = 0;
  Pose2 last_odometry;
  std::map<std::string, std::uint64_t> classes;  // what the processed steps held
  Stopwatch read_sw;

  const auto note = [&](const Observation& o) {
    ++classes[std::string(o.class_name())];
    if (matchable(o)) ++result.scans;
  };
  const auto run_step = [&](const auto& work, Timestamp time, std::uint64_t at,
                            const auto& observations) {
    const std::uint64_t index = step_index++;
    if (index < options.rawlog_offset) return true;
    if (options.max_steps && result.steps.size() >= *options.max_steps) return false;
    observations();
    const IcpSlamStats before = slam.stats();
    Stopwatch sw;
    try {
      work();
    } catch (const ParseError&) {
      throw;
    } catch (const ResourceError&) {
      throw;  // names what asked for the memory (a map key), not the step
    } catch (const Interrupted&) {
      throw;
    } catch (const Error& e) {
      throw ParseError({rawlog_path, std::nullopt, at, "step " + std::to_string(index)},
                       fmt::format("ICP-SLAM rejected the step: {}", e.message()));
    }
    IcpSlamStep s;
    s.seconds = sw.elapsed();
    s.index = index;
    s.time = time;
    s.pose = slam.pose();
    s.odometry = last_odometry;
    const IcpSlamStats& after = slam.stats();
    s.icp_runs = static_cast<unsigned>(after.icp_runs - before.icp_runs);
    s.icp_accepted = static_cast<unsigned>(after.icp_accepted - before.icp_accepted);
    s.icp_iterations = static_cast<unsigned>(after.icp_iterations - before.icp_iterations);
    s.insertions = static_cast<unsigned>(after.insertions - before.insertions);
    result.mapping_seconds += s.seconds;
    result.steps.push_back(s);
    if (options.on_step) options.on_step(result.steps.back());
    return true;
  };

  for (;;) {
    throw_if_interrupted();
    read_sw.reset();
    const std::uint64_t at = reader.position();
    std::optional<RawlogEntry> entry = reader.next();
    result.read_seconds += read_sw.elapsed();
    if (!entry) break;
    ++result.entries;
    bool go_on = true;
    if (auto* ac = std::get_if<std::shared_ptr<const ActionCollection>>(&*entry)) {
      pending_action = *ac;
      continue;
    }
    if (auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&*entry)) {
      if (!pending_action) continue;  // before the first action: passed over, as MRPT
      const auto actions = std::move(pending_action);
      pending_action.reset();
      const SensoryFrame& frame = **sf;
      const Timestamp t = first_time(frame);
      go_on = run_step(
          [&] {
            slam.process(*actions, frame, t);
            last_odometry = slam.accumulated_odometry();
          },
          t, at,
          [&] {
            for (const auto& o : frame.observations) note(*o);
          });
    } else {
      const auto& obs = std::get<std::shared_ptr<const Observation>>(*entry);
      go_on = run_step(
          [&] {
            slam.process(obs);
            if (const auto* o = dynamic_cast<const OdometryObservation*>(obs.get())) {
              last_odometry = o->odometry;
            }
          },
          obs->timestamp, at, [&] { note(*obs); });
    }
    if (!go_on) break;
  }
  if (result.steps.empty()) {
    if (step_index > 0 && options.rawlog_offset >= step_index) {
      throw SelectionError("rawlog_offset",
                           fmt::format("rawlog_offset {} skips every step of {}: it has {} steps",
                                       options.rawlog_offset, rawlog_path, step_index));
    }
    throw SelectionError("", fmt::format("{} holds no step for ICP-SLAM ({} entries; layout #1 "
                                         "needs an action collection before a sensory frame)",
                                         rawlog_path, result.entries));
  }
  if (result.scans == 0) {
    throw SelectionError(
        "", fmt::format("{} holds no 2D scan or 3D range image for ICP-SLAM to match (its {} "
                        "processed steps hold: {}); nothing written",
                        rawlog_path, result.steps.size(), detail::describe_counts(classes)));
  }
  result.issues = icp_slam_issues(slam.stats(), slam.options(), options.min_accepted_fraction);
  std::vector<PosedScan> keyframes;
  for (const IcpSlamKeyframe& k : slam.keyframes()) {
    if (const auto* scan = dynamic_cast<const RangeScan2D*>(k.observation.get())) {
      keyframes.push_back({SE2d(k.pose.x(), k.pose.y(), k.pose.phi()), scan});
    }
  }
  result.consistency = scan_consistency(keyframes);
  if (result.consistency.flagged()) {
    result.issues.push_back(
        {"map-contradicts-scans",
         contradiction_message(result.consistency.contradicted, result.consistency.checked, "keyframes", "",
                               "the path drifted where the robot came back, so the map holds passes that "
                               "disagree (ICP-SLAM closes no loop; rove lidar-slam does)")});
  }
  return result;
}

}  // namespace rove
