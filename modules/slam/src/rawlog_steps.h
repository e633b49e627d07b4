#pragma once
// The steps of a filter fed by a rawlog, as MRPT's applications take them
// (CRawlog::getActionObservationPairOrObservation): in a log of actions
// and sensory frames (layout #1) a step is an action collection with the
// sensory frame after it, and frames met before the first action are passed
// over; in an observation-only log (layout #2) odometry readings are
// accumulated and every other observation is a step whose motion is the
// odometry increment since the previous step, with a Gaussian model (MRPT's
// [DummyOdometryParams]). Shared by pf-localization and rbpf-slam.

#include <memory>
#include <optional>

#include "rove/io/rawlog_reader.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/motion_model_options.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/obs/timestamp.h"
#include "rove/poses/pose2.h"

namespace rove::detail {

/// One step of a filter.
struct RawlogStep {
  /// The motion since the previous step; none when the action collection
  /// holds no 2D movement.
  std::optional<RobotMovement2D> motion;
  /// The observations of the step.
  SensoryFrame frame;
  /// Time of the step's first observation with a time (invalid if none).
  Timestamp time;
};

/// Turns log entries into steps (see the file comment).
class RawlogStepAssembler {
 public:
  /// `dummy_odometry` models the increments of an observation-only log.
  explicit RawlogStepAssembler(const GaussianMotionOptions& dummy_odometry);
  /// Feeds one entry; returns the step it completes, if any.
  std::optional<RawlogStep> feed(const RawlogEntry& entry);

 private:
  MotionModelOptions dummy_;
  std::shared_ptr<const ActionCollection> pending_;
  std::optional<Pose2> last_odometry_reading_, latest_odometry_reading_;
};

}  // namespace rove::detail
