// Frozen bytes of version-1 records, written out by hand from the documented
// encoding (little-endian; strings and vectors as u32 count + elements). They
// pin the on-disk format: a change that breaks reading old files fails here.

#include <gtest/gtest.h>

#include <cstddef>
#include <string_view>
#include <vector>

#include "rove/obs/beacon_ranges.h"
#include "rove/obs/comment_observation.h"
#include "rove/obs/gps_observation.h"
#include "rove/obs/obs_registry.h"
#include "rove/obs/robot_movement_3d.h"
#include "rove/obs/rotating_scan.h"
#include "rove/obs/velodyne_scan.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/poses/angle.h"
#include "rove/serialization/memory_stream.h"
#include "rove/serialization/object_io.h"

namespace rove {
namespace {

std::vector<std::byte> from_hex(std::string_view hex) {
  std::vector<std::byte> out;
  for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
    const auto digit = [](char c) { return c <= '9' ? c - '0' : c - 'a' + 10; };
    out.push_back(static_cast<std::byte>(digit(hex[i]) * 16 + digit(hex[i + 1])));
  }
  return out;
}

// RangeScan2D v1: timestamp 1000 ns, label "L", identity sensor pose,
// ranges {1.5, 2}, valid {1, 0}, no intensity, aperture π, right to left,
// max_range 80, std_error 0.01, beam_aperture 0.25°.
constexpr std::string_view kScanV1 =
    "0b00000052616e67655363616e32440101e803000000000000010000004c0000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000200"
    "00000000c03f0000004002000000010000000000182d4454fb210940010000a0"
    "420ad7233c35fa8e3b88";

// OdometryObservation v1: invalid timestamp, empty label, identity pose,
// odometry (1, 2, 0.5), encoder ticks {-7, 12}, no velocity.
constexpr std::string_view kOdometryV1 =
    "130000004f646f6d657472794f62736572766174696f6e010100000000000000"
    "8000000000000000000000f03f00000000000000000000000000000000000000"
    "0000000000000000000000f03f00000000000000000000000000000000000000"
    "0000000000000000000000f03f00000000000000000000000000000000000000"
    "0000000000000000000000f03f0000000000000040000000000000e03f0101f9"
    "ffffff0c0000000088";

// RobotMovement3D v1: timestamp 2000 ns, pose change (1, 2, 0.5) with
// covariance 0.5·I, visual odometry, velocity (0.5, 0, 0, 0, 0, 0.25).
constexpr std::string_view kMovement3DV1 =
    "0f000000526f626f744d6f76656d656e7433440101d007000000000000000000"
    "000000f03f000000000000000000000000000000800000000000000000000000"
    "000000f03f000000000000000000000000000000000000000000000000000000"
    "000000f03f000000000000f03f0000000000000040000000000000e03f000000"
    "000000e03f000000000000000000000000000000000000000000000000000000"
    "000000000000000000000000000000000000000000000000000000e03f000000"
    "0000000000000000000000000000000000000000000000000000000000000000"
    "00000000000000000000000000000000000000e03f0000000000000000000000"
    "0000000000000000000000000000000000000000000000000000000000000000"
    "0000000000000000000000e03f00000000000000000000000000000000000000"
    "0000000000000000000000000000000000000000000000000000000000000000"
    "000000e03f000000000000000000000000000000000000000000000000000000"
    "000000000000000000000000000000000000000000000000000000e03f010101"
    "000000000000e03f000000000000000000000000000000000000000000000000"
    "0000000000000000000000000000d03f88";

// CommentObservation v1: timestamp 5 ns, text "hi".
constexpr std::string_view kCommentV1 =
    "12000000436f6d6d656e744f62736572766174696f6e01010500000000000000"
    "00000000000000000000f03f0000000000000000000000000000000000000000"
    "00000000000000000000f03f0000000000000000000000000000000000000000"
    "00000000000000000000f03f0000000000000000000000000000000000000000"
    "0000000002000000686988";

// RotatingScan v1: label "R", 1x2 ranges {10, 20}, intensity {1, 2},
// model "M", other fields default.
constexpr std::string_view kRotatingScanV1 =
    "0c000000526f746174696e675363616e01010000000000000080010000005200"
    "0000000000f03f00000000000000000000000000000000000000000000000000"
    "0000000000f03f00000000000000000000000000000000000000000000000000"
    "0000000000f03f00000000000000000000000000000000000000000000000001"
    "000200020000000a001400020000000102000000007b14ae47e17a843f182d44"
    "54fb2109c0182d4454fb2119400000000000000000000000000000f03f000000"
    "0000406040010000004d00000000000000800088";

// VelodyneScan v1: no packets, one laser calibration (vertical correction
// 0.5), a one-point cloud (1, 2, 3) intensity 9, satellite time.
constexpr std::string_view kVelodyneScanV1 =
    "0c00000056656c6f64796e655363616e01010000000000000080000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000406040000000000100000000000000000000000000"
    "00000000e03f0000000000000000000000000000000000000000000000000000"
    "000000000000000000000000f03f0000000000000000000000000000f03f0101"
    "0000000000803f01000000000000400100000000004040010000000900000000"
    "0000000000000000000000000188";

// BeaconRanges v2: one reading (id 3, 1.5 m, antenna at z 0.5), aux
// estimate (1, 2) without heading.
constexpr std::string_view kBeaconRangesV2 =
    "0c000000426561636f6e52616e67657302010000000000000080000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000100"
    "000001030000000000c03f030000000100000000000000000000000000000000"
    "000000000000000000e03f000000000000c8420ad7233c01000000000000f03f"
    "00000000000000400088";

// BeaconRanges v1 (before aux_estimate): the same reading.
constexpr std::string_view kBeaconRangesV1 =
    "0c000000426561636f6e52616e67657301010000000000000080000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000000"
    "00000000f03f0000000000000000000000000000000000000000000000000100"
    "000001030000000000c03f030000000100000000000000000000000000000000"
    "000000000000000000e03f000000000000c8420ad7233c88";

// GpsObservation v1 (before UTC time, RMC, geoid): lat 36.5, lon −4.5,
// alt 40, RTK fixed, 9 satellites, hdop 0.75.
constexpr std::string_view kGpsV1 =
    "0e0000004770734f62736572766174696f6e0101000000000000008000000000"
    "000000000000f03f000000000000000000000000000000000000000000000000"
    "000000000000f03f000000000000000000000000000000000000000000000000"
    "000000000000f03f000000000000000000000000000000000000000000000000"
    "000000000040424000000000000012c000000000000044400409000000000000"
    "000000e83f000088";

// The same fix written as version 2.
constexpr std::string_view kGpsV2 =
    "0e0000004770734f62736572766174696f6e0201000000000000008000000000"
    "000000000000f03f000000000000000000000000000000000000000000000000"
    "000000000000f03f000000000000000000000000000000000000000000000000"
    "000000000000f03f000000000000000000000000000000000000000000000000"
    "000000000040424000000000000012c000000000000044400409000000000000"
    "000000e83f00000000000000000000000000000000000000800088";

// Reads `hex` (an older version) and compares with `expected`; no write-back.
template <typename T>
void expect_reads(const T& expected, std::string_view hex) {
  register_obs_classes();
  const std::vector<std::byte> bytes = from_hex(hex);
  MemoryInStream in(bytes, "frozen");
  InArchive ia(in);
  const std::unique_ptr<T> read = read_object_as<T>(ia);
  EXPECT_TRUE(ia.at_end());
  EXPECT_TRUE(*read == expected);
}

template <typename T>
void expect_frozen(const T& expected, std::string_view hex) {
  register_obs_classes();
  const std::vector<std::byte> bytes = from_hex(hex);
  MemoryInStream in(bytes, "frozen");
  InArchive ia(in);
  const std::unique_ptr<T> read = read_object_as<T>(ia);
  EXPECT_TRUE(ia.at_end());
  EXPECT_TRUE(*read == expected);
  MemoryOutStream out;
  OutArchive oa(out);
  write_object(oa, expected);
  EXPECT_TRUE(out.data() == bytes);  // the writer still produces the frozen bytes
}

TEST(FrozenFormat, RangeScan2DVersion1) {
  RangeScan2D s;
  s.timestamp = Timestamp::from_ns(1000);
  s.sensor_label.push_back('L');  // (GCC 12 flags `= "L"` with a false -Wrestrict under ASan)
  s.ranges = {1.5f, 2.0f};
  s.valid = {true, false};
  s.aperture = kPi;
  expect_frozen(s, kScanV1);
}

TEST(FrozenFormat, OdometryObservationVersion1) {
  OdometryObservation o;
  o.odometry = Pose2(1.0, 2.0, 0.5);
  o.encoder_ticks = EncoderTicks{-7, 12};
  expect_frozen(o, kOdometryV1);
}

TEST(FrozenFormat, RobotMovement3DVersion1) {
  RobotMovement3D m;
  m.timestamp = Timestamp::from_ns(2000);
  m.pose_change = Pose3Gaussian(Pose3(1.0, 2.0, 0.5, 0.0, 0.0, 0.0),
                                Pose3Gaussian::Matrix::Identity() * 0.5);
  m.source = Movement3DSource::VisualOdometry;
  m.velocity = Twist3{0.5, 0, 0, 0, 0, 0.25};
  expect_frozen(m, kMovement3DV1);
}

TEST(FrozenFormat, CommentObservationVersion1) {
  CommentObservation c;
  c.timestamp = Timestamp::from_ns(5);
  c.text = std::string("hi");
  expect_frozen(c, kCommentV1);
}

TEST(FrozenFormat, RotatingScanVersion1) {
  RotatingScan r;
  r.rows = 1;
  r.columns = 2;
  r.range = {10, 20};
  r.intensity = {1, 2};
  r.lidar_model = std::string("M");
  r.sensor_label.push_back('R');
  expect_frozen(r, kRotatingScanV1);
}

TEST(FrozenFormat, VelodyneScanVersion1) {
  VelodyneScan v;
  v.calibration.resize(1);
  v.calibration[0].vertical_correction = 0.5;
  v.point_cloud.x = {1.0f};
  v.point_cloud.y = {2.0f};
  v.point_cloud.z = {3.0f};
  v.point_cloud.intensity = {9};
  v.has_satellite_timestamp = true;
  expect_frozen(v, kVelodyneScanV1);
}

TEST(FrozenFormat, BeaconRangesVersions1And2) {
  BeaconRanges b;
  b.readings.push_back(BeaconRange{3, 1.5f, Eigen::Vector3d(0, 0, 0.5)});
  expect_reads(b, kBeaconRangesV1);  // version 1 reads as "no aux estimate"
  b.aux_estimate = BeaconAuxEstimate{1.0, 2.0, std::nullopt};
  expect_frozen(b, kBeaconRangesV2);
}

TEST(FrozenFormat, GpsObservationVersions1And2) {
  GpsObservation g;
  g.latitude_deg = 36.5;
  g.longitude_deg = -4.5;
  g.altitude_m = 40;
  g.fix_quality = GpsFixQuality::RtkFixed;
  g.satellites = 9;
  g.hdop = 0.75;
  expect_reads(g, kGpsV1);
  expect_frozen(g, kGpsV2);
}

}  // namespace
}  // namespace rove
