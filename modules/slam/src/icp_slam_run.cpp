#include "rove/slam/icp_slam_run.h"

#include <memory>
#include <utility>
#include <variant>

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/timer.h"
#include "rove/obs/odometry_observation.h"

namespace rove {
namespace {

Timestamp first_time(const SensoryFrame& frame) {
  for (const auto& o : frame.observations) {
    if (o->timestamp.valid()) return o->timestamp;
  }
  return {};
}

}  // namespace

IcpSlamRunResult run_icp_slam(IcpSlam& slam, const std::string& rawlog_path,
                              const IcpSlamRunOptions& options) {
  IcpSlamRunResult result;
  AnyRawlogReader reader(rawlog_path, options.reader);
  result.format = reader.format();
  std::shared_ptr<const ActionCollection> pending_action;
  std::uint64_t step_index = 0;
  Pose2 last_odometry;
  Stopwatch read_sw;

  const auto run_step = [&](const auto& work, Timestamp time, std::uint64_t at) {
    const std::uint64_t index = step_index++;
    if (index < options.rawlog_offset) return true;
    if (options.max_steps && result.steps.size() >= *options.max_steps) return false;
    const IcpSlamStats before = slam.stats();
    Stopwatch sw;
    try {
      work();
    } catch (const ParseError&) {
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
          t, at);
    } else {
      const auto& obs = std::get<std::shared_ptr<const Observation>>(*entry);
      go_on = run_step(
          [&] {
            slam.process(obs);
            if (const auto* o = dynamic_cast<const OdometryObservation*>(obs.get())) {
              last_odometry = o->odometry;
            }
          },
          obs->timestamp, at);
    }
    if (!go_on) break;
  }
  return result;
}

}  // namespace rove
