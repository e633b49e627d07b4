#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/bearing_range.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/imu_observation.h"
#include "rove/obs/obs_registry.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/angle.h"
#include "rove/serialization/memory_stream.h"
#include "rove/serialization/object_io.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {
namespace {

void fill_header(Observation& o, const char* label) {
  o.timestamp = Timestamp::from_ns(1262304000123456700);
  o.sensor_label = label;
  o.T_robot_sensor = Pose3(0.1, -0.2, 0.3, 0.4, -0.5, 0.6);
}

RangeScan2D sample_scan() {
  RangeScan2D s;
  fill_header(s, "LASER");
  s.aperture = deg_to_rad(270.0);
  s.right_to_left = false;
  s.max_range = 30.0f;
  s.set_ranges({1.0f, 2.5f, 0.0f, 29.0f, 31.0f});
  s.intensity = {10, 20, 30, 40, 50};
  s.std_error = 0.02f;
  return s;
}

RangeImage3D sample_rgbd() {
  RangeImage3D r;
  fill_header(r, "KINECT");
  r.depth_camera = {4, 2, 5.0, 6.0, 1.5, 0.5, {0.1, -0.01, 0.001, 0.002, 0.0}};
  r.depth = DepthImage::zeros_u16(4, 2, 5000.0);
  std::get<std::vector<std::uint16_t>>(r.depth.values) = {0, 1, 2, 3, 4, 5, 6, 65535};
  r.range_is_depth = false;
  r.max_range = 8.0;
  r.intensity = Image::zeros(4, 2, 3, PixelType::U8);
  r.intensity->data[5] = 200;
  r.intensity_camera = {4, 2, 4.0, 4.0, 2.0, 1.0, {}};
  r.T_sensor_intensity = Pose3(0.025, 0.0, 0.0, -kPi / 2, 0.0, -kPi / 2);
  return r;
}

OdometryObservation sample_odometry() {
  OdometryObservation o;
  fill_header(o, "ODOMETRY");
  o.odometry = Pose2(1.0, 2.0, 0.5);
  o.encoder_ticks = EncoderTicks{-7, 12};
  o.velocity = Twist2{0.3, 0.0, -0.1};
  return o;
}

ImageObservation sample_image() {
  ImageObservation o;
  fill_header(o, "CAMERA");
  o.camera = {3, 2, 300.0, 300.0, 1.0, 0.5, {}};
  o.image = Image::zeros(3, 2, 1, PixelType::U16);
  o.image.data[3] = 0xAB;
  return o;
}

BeaconRanges sample_beacons() {
  BeaconRanges b;
  fill_header(b, "UWB");
  b.readings = {{1, 3.5f, {0.1, 0.0, 0.2}}, {7, 12.25f, {-0.1, 0.0, 0.2}}};
  b.min_sensor_distance = 0.5f;
  b.max_sensor_distance = 50.0f;
  b.std_error = 0.05f;
  return b;
}

BearingRange sample_bearing() {
  BearingRange b;
  fill_header(b, "STEREO");
  LandmarkMeasurement m1;
  m1.landmark_id = 3;
  m1.range = 2.0f;
  m1.yaw = 0.3f;
  m1.pitch = -0.1f;
  LandmarkMeasurement m2 = m1;
  m2.landmark_id = 4;
  m2.covariance = Eigen::Matrix3d::Identity() * 0.01;
  b.measurements = {m1, m2};
  b.sensor_std_range = 0.1f;
  b.sensor_std_yaw = 0.01f;
  return b;
}

ImuObservation sample_imu() {
  ImuObservation i;
  fill_header(i, "IMU");
  i.angular_velocity = Eigen::Vector3d(0.01, -0.02, 0.3);
  i.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
  return i;
}

GpsObservation sample_gps() {
  GpsObservation g;
  fill_header(g, "GPS");
  g.latitude_deg = 36.8389;
  g.longitude_deg = -2.4597;
  g.altitude_m = 52.5;
  g.fix_quality = GpsFixQuality::RtkFixed;
  g.satellites = 11;
  g.hdop = 0.8;
  g.enu_position = Eigen::Vector3d(10.0, -3.0, 0.5);
  return g;
}

RobotMovement2D sample_movement() {
  MotionModelOptions opts;
  opts.model = MotionModel::Thrun;
  opts.thrun.particle_count = 50;
  RobotMovement2D m(Pose2(0.2, 0.01, 0.05), opts);
  m.timestamp = Timestamp::from_ns(42);
  m.encoder_ticks = EncoderTicks{100, 101};
  Eigen::Matrix3d C = Eigen::Matrix3d::Identity() * 1e-3;
  C(0, 1) = C(1, 0) = 2e-4;
  m.estimated_pose_change = Pose2Gaussian(Pose2(0.21, 0.0, 0.04), C);
  return m;
}

std::vector<std::byte> write(const Serializable& obj) {
  MemoryOutStream out;
  OutArchive ar(out);
  write_object(ar, obj);
  return out.take();
}

std::unique_ptr<Serializable> read(const std::vector<std::byte>& bytes) {
  register_obs_classes();
  MemoryInStream in(bytes, "test");
  InArchive ar(in);
  auto obj = read_object(ar);
  EXPECT_TRUE(ar.at_end());
  return obj;
}

template <typename T>
void expect_round_trip(const T& original) {
  const auto bytes = write(original);
  const std::unique_ptr<Serializable> back = read(bytes);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->class_name(), T::kClassName);
  const auto* typed = dynamic_cast<const T*>(back.get());
  ASSERT_NE(typed, nullptr);
  EXPECT_TRUE(*typed == original) << T::kClassName;
  // Every strict prefix is a ParseError, never a crash.
  for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 40) {
    const std::vector<std::byte> part(bytes.begin(), bytes.begin() + static_cast<long>(cut));
    MemoryInStream in(part, "truncated");
    InArchive ar(in);
    EXPECT_THROW((void)read_object(ar), ParseError) << T::kClassName << " cut at " << cut;
  }
}

TEST(ObsSerialization, RoundTripEveryObservationType) {
  expect_round_trip(sample_scan());
  expect_round_trip(sample_rgbd());
  expect_round_trip(sample_odometry());
  expect_round_trip(sample_image());
  expect_round_trip(sample_beacons());
  expect_round_trip(sample_bearing());
  expect_round_trip(sample_imu());
  expect_round_trip(sample_gps());
}

TEST(ObsSerialization, RoundTripFloatDepthAndEmptyOptionals) {
  RangeImage3D r = sample_rgbd();
  r.depth = DepthImage::zeros_f32(4, 2, 1.0);
  std::get<std::vector<float>>(r.depth.values)[3] = 1.5f;
  r.intensity.reset();
  expect_round_trip(r);
  OdometryObservation o;
  o.odometry = Pose2(-1.0, 0.0, -3.0);
  expect_round_trip(o);
  expect_round_trip(ImuObservation{});
  expect_round_trip(RangeScan2D{});
}

TEST(ObsSerialization, RoundTripActionsAndFrames) {
  expect_round_trip(sample_movement());
  RobotMovement2D plain(Pose2(1.0, 0.0, 0.0), MotionModelOptions{});
  expect_round_trip(plain);

  SensoryFrame sf;
  sf.add(std::make_shared<RangeScan2D>(sample_scan()));
  sf.add(std::make_shared<RangeImage3D>(sample_rgbd()));
  sf.add(std::make_shared<OdometryObservation>(sample_odometry()));
  sf.add(std::make_shared<ImageObservation>(sample_image()));
  sf.add(std::make_shared<BeaconRanges>(sample_beacons()));
  sf.add(std::make_shared<BearingRange>(sample_bearing()));
  sf.add(std::make_shared<ImuObservation>(sample_imu()));
  sf.add(std::make_shared<GpsObservation>(sample_gps()));
  expect_round_trip(sf);
  expect_round_trip(SensoryFrame{});

  ActionCollection ac;
  ac.add(std::make_shared<RobotMovement2D>(sample_movement()));
  ac.add(std::make_shared<RobotMovement2D>(plain));
  expect_round_trip(ac);
}

TEST(ObsSerialization, ValueRecordsRoundTrip) {
  MemoryOutStream out;
  OutArchive oa(out);
  const PinholeCamera cam = sample_rgbd().depth_camera;
  MotionModelOptions opts;
  opts.model = MotionModel::Thrun;
  opts.gaussian.a4_rad_per_rad = 0.2;
  opts.thrun.particle_count = 7;
  oa << cam << sample_rgbd().depth << *sample_rgbd().intensity << opts << EncoderTicks{1, -2}
     << Twist2{1.0, 2.0, 3.0} << sample_beacons().readings << sample_bearing().measurements;
  MemoryInStream in(out.take(), "values");
  InArchive ia(in);
  PinholeCamera cam2;
  DepthImage depth2;
  Image image2;
  MotionModelOptions opts2;
  EncoderTicks ticks2;
  Twist2 twist2;
  std::vector<BeaconRange> beacons2;
  std::vector<LandmarkMeasurement> marks2;
  ia >> cam2 >> depth2 >> image2 >> opts2 >> ticks2 >> twist2 >> beacons2 >> marks2;
  EXPECT_TRUE(ia.at_end());
  EXPECT_EQ(cam2, cam);
  EXPECT_EQ(depth2, sample_rgbd().depth);
  EXPECT_EQ(image2, *sample_rgbd().intensity);
  EXPECT_EQ(opts2, opts);
  EXPECT_EQ(ticks2, (EncoderTicks{1, -2}));
  EXPECT_EQ(twist2, (Twist2{1.0, 2.0, 3.0}));
  EXPECT_EQ(beacons2, sample_beacons().readings);
  EXPECT_EQ(marks2, sample_bearing().measurements);
}

// A hand-written RangeScan2D record whose validity flags do not match its
// ranges must be rejected with a ParseError naming the field.
TEST(ObsSerialization, MismatchedValiditySizeIsAParseError) {
  MemoryOutStream out;
  OutArchive ar(out);
  save(ar, std::string(RangeScan2D::kClassName));
  ar.write_scalar(std::uint8_t{1});  // class version
  write_version(ar, 1);              // observation header
  ar.write_scalar(std::int64_t{0});
  save(ar, std::string("LASER"));
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  ar.write_scalars(std::span<const double>(R.data(), 9));
  const double t[3] = {0, 0, 0};
  ar.write_scalars(std::span<const double>(t, 3));
  save(ar, std::vector<float>{1.0f, 2.0f, 3.0f});
  save(ar, std::vector<bool>{true, false});
  MemoryInStream in(out.take(), "bad.bin");
  InArchive ia(in);
  register_obs_classes();
  try {
    (void)read_object(ia);
    FAIL() << "mismatched validity accepted";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "valid");
    EXPECT_EQ(e.location().source, "bad.bin");
  }
}

TEST(ObsSerialization, NonRotationSensorPoseIsAParseError) {
  RangeScan2D s = sample_scan();
  auto bytes = write(s);
  // The header's rotation starts after: name (4 + 11), version (1), header
  // version (1), timestamp (8), label (4 + 5). Scale R(0,0) to 2.
  const std::size_t r00 = 4 + 11 + 1 + 1 + 8 + 4 + 5;
  const double two = 2.0;
  std::memcpy(bytes.data() + r00, &two, sizeof two);
  MemoryInStream in(bytes, "scaled.bin");
  InArchive ia(in);
  EXPECT_THROW((void)read_object(ia), ParseError);
}

// Found by rove_any_rawlog_fuzz: a rove rawlog whose RangeImage3D held a
// 4x2 depth image with a 4x40450 depth camera read without complaint; every
// use of the observation then failed its precondition check.
TEST(ObsSerialization, InconsistentRangeImageIsAParseError_Regression) {
  register_obs_classes();
  RangeImage3D camera_mismatch = sample_rgbd();
  camera_mismatch.depth_camera.height = 40450;
  RangeImage3D no_range = sample_rgbd();
  no_range.max_range = 0.0;
  for (const RangeImage3D* bad : {&camera_mismatch, &no_range}) {
    EXPECT_THROW(bad->check(), InvalidArgument);
    const auto bytes = write(*bad);  // saving does not check
    MemoryInStream in(bytes, "bad_rgbd.bin");
    InArchive ia(in);
    try {
      (void)read_object(ia);
      ADD_FAILURE() << "an inconsistent RangeImage3D read back";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, "bad_rgbd.bin");
      EXPECT_EQ(e.location().field, "RangeImage3D");
    }
  }
}

// Found while fixing the RangeImage3D case above: a stored GpsObservation
// with a latitude of 91 degrees (or a NaN hdop) read back as if valid.
TEST(ObsSerialization, OutOfRangeGpsIsAParseError_Regression) {
  register_obs_classes();
  GpsObservation bad_latitude = sample_gps();
  bad_latitude.latitude_deg = 91.0;
  GpsObservation nan_hdop = sample_gps();
  nan_hdop.hdop = std::numeric_limits<double>::quiet_NaN();
  for (const GpsObservation* bad : {&bad_latitude, &nan_hdop}) {
    const auto bytes = write(*bad);  // saving does not check
    MemoryInStream in(bytes, "bad_gps.bin");
    InArchive ia(in);
    try {
      (void)read_object(ia);
      ADD_FAILURE() << "an out-of-range GpsObservation read back";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, "bad_gps.bin");
      EXPECT_EQ(e.location().field, "GpsObservation");
    }
  }
  expect_round_trip(GpsObservation{});
}

TEST(ObsSerialization, CloneAndEquals) {
  const GpsObservation g = sample_gps();
  const std::unique_ptr<Observation> c = g.clone();
  EXPECT_TRUE(c->equals(g));
  EXPECT_FALSE(c->equals(sample_imu()));
  GpsObservation h = g;
  h.sensor_label = "GPS2";
  EXPECT_FALSE(c->equals(h));
  const std::unique_ptr<Action> a = sample_movement().clone();
  EXPECT_TRUE(a->equals(sample_movement()));
}

}  // namespace
}  // namespace rove
