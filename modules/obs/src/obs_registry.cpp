#include "rove/obs/obs_registry.h"

#include "rove/obs/action_collection.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/bearing_range.h"
#include "rove/obs/comment_observation.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/imu_observation.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/robot_movement_3d.h"
#include "rove/obs/rotating_scan.h"
#include "rove/obs/sensory_frame.h"
#include "rove/obs/velodyne_scan.h"

namespace rove {

void register_obs_classes(ClassRegistry& registry) {
  // replace = true: registering twice (or from several threads) is harmless.
  registry.add<RangeScan2D>(true);
  registry.add<RangeImage3D>(true);
  registry.add<OdometryObservation>(true);
  registry.add<ImageObservation>(true);
  registry.add<BeaconRanges>(true);
  registry.add<BearingRange>(true);
  registry.add<ImuObservation>(true);
  registry.add<GpsObservation>(true);
  registry.add<RobotMovement2D>(true);
  registry.add<RobotMovement3D>(true);
  registry.add<CommentObservation>(true);
  registry.add<RotatingScan>(true);
  registry.add<VelodyneScan>(true);
  registry.add<SensoryFrame>(true);
  registry.add<ActionCollection>(true);
}

}  // namespace rove
