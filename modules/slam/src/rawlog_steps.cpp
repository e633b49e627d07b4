#include "rawlog_steps.h"

#include <utility>
#include <variant>

#include "rove/core/interrupt.h"
#include "rove/core/timer.h"
#include "rove/obs/odometry_observation.h"

namespace rove::detail {
namespace {

Timestamp first_time(const SensoryFrame& frame) {
  for (const auto& o : frame.observations) {
    if (o->timestamp.valid()) return o->timestamp;
  }
  return {};
}

const RobotMovement2D* first_movement(const ActionCollection& actions) {
  for (const auto& a : actions.actions) {
    if (const auto* m = dynamic_cast<const RobotMovement2D*>(a.get())) return m;
  }
  return nullptr;
}

}  // namespace

RawlogStepAssembler::RawlogStepAssembler(const GaussianMotionOptions& dummy_odometry) {
  dummy_.gaussian = dummy_odometry;
}

std::optional<RawlogStep> RawlogStepAssembler::feed(const RawlogEntry& entry) {
  if (const auto* ac = std::get_if<std::shared_ptr<const ActionCollection>>(&entry)) {
    pending_ = *ac;
    return std::nullopt;
  }
  if (const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&entry)) {
    if (!pending_) return std::nullopt;  // before the first action: passed over, as MRPT
    RawlogStep step;
    if (const RobotMovement2D* m = first_movement(*pending_)) step.motion = *m;
    pending_.reset();
    step.frame = **sf;
    step.time = first_time(step.frame);
    return step;
  }
  const auto& obs = std::get<std::shared_ptr<const Observation>>(entry);
  if (const auto* odo = dynamic_cast<const OdometryObservation*>(obs.get())) {
    if (!last_odometry_reading_) last_odometry_reading_ = odo->odometry;
    latest_odometry_reading_ = odo->odometry;
    return std::nullopt;
  }
  const Pose2 increment = latest_odometry_reading_ && last_odometry_reading_
                              ? *latest_odometry_reading_ - *last_odometry_reading_
                              : Pose2();
  last_odometry_reading_ = latest_odometry_reading_;
  RawlogStep step;
  step.motion.emplace(increment, dummy_);
  step.frame.add(obs);
  step.time = obs->timestamp;
  return step;
}

LogRead read_entries(const std::string& path, const AnyRawlogOptions& options,
                     const std::function<bool(const RawlogEntry&, std::uint64_t)>& feed) {
  LogRead out;
  AnyRawlogReader reader(path, options);
  out.format = reader.format();
  Stopwatch sw;
  for (;;) {
    throw_if_interrupted();
    sw.reset();
    const std::uint64_t at = reader.position();
    std::optional<RawlogEntry> entry = reader.next();
    out.seconds += sw.elapsed();
    if (!entry) break;
    ++out.entries;
    if (!feed(*entry, at)) break;
  }
  return out;
}

}  // namespace rove::detail
