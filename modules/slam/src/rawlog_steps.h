#pragma once
// The steps of a filter fed by a rawlog, as MRPT's applications take them
// (CRawlog::getActionObservationPairOrObservation): in a log of actions
// and sensory frames (layout #1) a step is an action collection with the
// sensory frame after it, and frames met before the first action are passed
// over; in an observation-only log (layout #2) odometry readings are
// accumulated and every other observation is a step whose motion is the
// odometry increment since the previous step, with a Gaussian model (MRPT's
// [DummyOdometryParams]). Shared by pf-localization and rbpf-slam.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "rove/io/any_rawlog.h"
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

/// What reading a log took.
struct LogRead {
  RawlogFormat format = RawlogFormat::Mrpt;
  std::uint64_t entries = 0;  ///< entries read
  double seconds = 0.0;       ///< time spent reading them
};

/// Reads the log at `path` (any format AnyRawlogReader knows) entry by
/// entry, calling feed(entry, its byte offset) until feed returns false or
/// the log ends, and polling rove::throw_if_interrupted() before each entry.
/// Throws IoError / ParseError from the reader.
LogRead read_entries(const std::string& path, const AnyRawlogOptions& options,
                     const std::function<bool(const RawlogEntry&, std::uint64_t)>& feed);

}  // namespace rove::detail
