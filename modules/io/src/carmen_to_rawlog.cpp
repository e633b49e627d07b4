#include "rove/io/carmen_to_rawlog.h"

#include <memory>
#include <utility>

#include "rove/core/check.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"

namespace rove {
namespace {

void check_options(const CarmenToRawlogOptions& options) {
  ROVE_CHECK_MSG(options.layout == RawlogLayout::ActionsSensoryFrames ||
                     options.layout == RawlogLayout::Observations,
                 "CARMEN logs convert to layout #1 or #2");
  options.motion_model.check();
}

}  // namespace

CarmenRawlogSource::CarmenRawlogSource(CarmenLogReader reader, CarmenToRawlogOptions options)
    : reader_(std::move(reader)), options_(std::move(options)) {}

CarmenRawlogSource CarmenRawlogSource::open(const std::string& path,
                                            CarmenToRawlogOptions options) {
  check_options(options);
  CarmenLogReader reader = CarmenLogReader::open(path, options.log);
  return CarmenRawlogSource(std::move(reader), std::move(options));
}

CarmenRawlogSource CarmenRawlogSource::from_memory(std::string bytes, std::string source,
                                                   CarmenToRawlogOptions options) {
  check_options(options);
  CarmenLogReader reader =
      CarmenLogReader::from_memory(std::move(bytes), std::move(source), options.log);
  return CarmenRawlogSource(std::move(reader), std::move(options));
}

void CarmenRawlogSource::convert(CarmenRecord& record) {
  const bool layout1 = options_.layout == RawlogLayout::ActionsSensoryFrames;
  switch (record.type) {
    case CarmenMessage::Flaser:
    case CarmenMessage::Rlaser:
    case CarmenMessage::RobotLaser1: {
      ROVE_CHECK(record.scan != nullptr);
      ++stats_.scans;
      std::shared_ptr<const RangeScan2D> scan(std::move(record.scan));
      if (layout1) {
        if (last_scan_pose_) {
          // The odometry increment between the two laser lines, in the robot
          // frame at the earlier one (MRPT's rawOdometryIncrementReading).
          auto move = std::make_shared<RobotMovement2D>(record.robot_pose - *last_scan_pose_,
                                                        options_.motion_model);
          move->timestamp = record.timestamp;
          auto actions = std::make_shared<ActionCollection>();
          actions->add(std::move(move));
          pending_.emplace_back(std::shared_ptr<const ActionCollection>(std::move(actions)));
          ++stats_.action_collections;
        }
        last_scan_pose_ = record.robot_pose;
        auto frame = std::make_shared<SensoryFrame>();
        frame->add(std::move(scan));
        pending_.emplace_back(std::shared_ptr<const SensoryFrame>(std::move(frame)));
        ++stats_.sensory_frames;
      } else {
        auto odometry = std::make_shared<OdometryObservation>();
        odometry->timestamp = record.timestamp;
        odometry->sensor_label = options_.log.odometry_label;
        odometry->odometry = record.robot_pose;
        pending_.emplace_back(std::shared_ptr<const Observation>(std::move(odometry)));
        pending_.emplace_back(std::shared_ptr<const Observation>(std::move(scan)));
        stats_.observations += 2;
      }
      break;
    }
    case CarmenMessage::Odom: {
      if (layout1 || !options_.odom_lines) {
        ++stats_.odom_not_used;
        break;
      }
      ROVE_CHECK(record.odometry != nullptr);
      pending_.emplace_back(std::shared_ptr<const Observation>(std::move(record.odometry)));
      ++stats_.odom_lines_used;
      ++stats_.observations;
      break;
    }
    case CarmenMessage::TruePos:
      ++stats_.truepos_dropped;
      break;
  }
}

std::optional<RawlogEntry> CarmenRawlogSource::next() {
  while (pending_.empty()) {
    if (!reader_.next(record_)) {
      stats_.log = reader_.stats();
      return std::nullopt;
    }
    convert(record_);
  }
  RawlogEntry e = std::move(pending_.front());
  pending_.pop_front();
  stats_.log = reader_.stats();
  return e;
}

}  // namespace rove
