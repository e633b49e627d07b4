#include "rove/obs/sensory_frame.h"

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/bearing_range.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/imu_observation.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"

namespace rove {
namespace {

template <typename T>
std::shared_ptr<T> make(const char* label) {
  auto o = std::make_shared<T>();
  o->sensor_label = label;
  return o;
}

TEST(SensoryFrame, FindByTypeAndLabel) {
  SensoryFrame sf;
  const auto front = make<RangeScan2D>("LASER_FRONT");
  const auto rear = make<RangeScan2D>("LASER_REAR");
  const auto odo = make<OdometryObservation>("ODOMETRY");
  const auto imu = make<ImuObservation>("IMU");
  sf.add(front);
  sf.add(odo);
  sf.add(rear);
  sf.add(imu);
  EXPECT_EQ(sf.size(), 4u);

  EXPECT_EQ(sf.find<RangeScan2D>(), front);
  EXPECT_EQ(sf.find<RangeScan2D>(1), rear);
  EXPECT_EQ(sf.find<RangeScan2D>(2), nullptr);
  EXPECT_EQ(sf.find<OdometryObservation>(), odo);
  EXPECT_EQ(sf.find<GpsObservation>(), nullptr);
  EXPECT_EQ(sf.find<Observation>(3), imu);
  EXPECT_EQ(sf.find_all<RangeScan2D>().size(), 2u);

  EXPECT_EQ(sf.find_by_label("LASER_REAR"), rear);
  EXPECT_EQ(sf.find_by_label("laser_rear"), nullptr);  // exact match
  EXPECT_EQ(sf.find_by_label<ImuObservation>("IMU"), imu);
  EXPECT_EQ(sf.find_by_label<RangeScan2D>("IMU"), nullptr);

  EXPECT_THROW(sf.add(nullptr), InvalidArgument);
}

TEST(SensoryFrame, EqualityComparesObservationsPolymorphically) {
  SensoryFrame a, b;
  a.add(make<BearingRange>("CAM"));
  b.add(make<BearingRange>("CAM"));
  EXPECT_TRUE(a == b);
  b.add(make<GpsObservation>("GPS"));
  EXPECT_FALSE(a == b);
  SensoryFrame c;
  c.add(make<GpsObservation>("CAM"));
  EXPECT_FALSE(a == c);
}

TEST(ActionCollection, FindsActions) {
  ActionCollection ac;
  EXPECT_TRUE(ac.empty());
  auto m = std::make_shared<RobotMovement2D>(Pose2(1.0, 0.0, 0.0), MotionModelOptions{});
  ac.add(m);
  EXPECT_EQ(ac.find<RobotMovement2D>(), m);
  EXPECT_EQ(ac.find<RobotMovement2D>(1), nullptr);
  EXPECT_THROW(ac.add(nullptr), InvalidArgument);
}

}  // namespace
}  // namespace rove
