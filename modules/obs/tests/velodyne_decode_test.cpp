// decode_velodyne_scan on packets built here, against the geometry and
// timing written out (velodyne_decode.h); MRPT's own output is the oracle
// of the io tests (velodyne_mrpt_test.cpp).
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/obs/velodyne_decode.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// Lasers at the given elevations (degrees), with optional offsets.
std::vector<VelodyneLaserCalibration> calibration(int lasers, double distance = 0.0, double vertical = 0.0,
                                                  double horizontal = 0.0) {
  std::vector<VelodyneLaserCalibration> c(static_cast<std::size_t>(lasers));
  for (int i = 0; i < lasers; ++i) {
    auto& l = c[static_cast<std::size_t>(i)];
    l.vertical_correction = lasers == 16 ? (i % 2 == 0 ? -15.0 + i : i) : -30.0 + i;
    l.sin_vert_correction = std::sin(l.vertical_correction * kDeg);
    l.cos_vert_correction = std::cos(l.vertical_correction * kDeg);
    l.distance_correction = distance;
    l.vertical_offset_correction = vertical;
    l.horizontal_offset_correction = horizontal;
    l.sin_vert_offset_correction = vertical * l.sin_vert_correction;
    l.cos_vert_offset_correction = vertical * l.cos_vert_correction;
  }
  return c;
}

// A packet whose block b has azimuth a0 + step · b (hundredths of a degree;
// dual: a0 + step · (b / 2)) and no returns.
VelodynePacket packet(int a0, int step, bool dual = false) {
  VelodynePacket p{};
  for (int b = 0; b < 12; ++b) {
    const int a = (a0 + step * (dual ? b / 2 : b)) % 36000;
    p[static_cast<std::size_t>(100 * b)] = 0xFF;
    p[static_cast<std::size_t>(100 * b + 1)] = 0xEE;
    p[static_cast<std::size_t>(100 * b + 2)] = static_cast<std::uint8_t>(a & 0xFF);
    p[static_cast<std::size_t>(100 * b + 3)] = static_cast<std::uint8_t>(a >> 8);
  }
  p[1204] = dual ? 0x39 : 0x37;
  p[1205] = 0x22;
  return p;
}

void set_return(VelodynePacket& p, int block, int ret, std::uint16_t raw, std::uint8_t intensity) {
  const auto at = static_cast<std::size_t>(100 * block + 4 + 3 * ret);
  p[at] = static_cast<std::uint8_t>(raw & 0xFF);
  p[at + 1] = static_cast<std::uint8_t>(raw >> 8);
  p[at + 2] = intensity;
}

// The expected point (velodyne_decode.h) of a return at azimuth `a`
// (hundredths of a degree).
Eigen::Vector3d expected(const VelodyneLaserCalibration& c, std::uint16_t raw, double a) {
  const double d = raw * 0.002 + c.distance_correction, alpha = a / 100.0 * kDeg;
  const double r = d * c.cos_vert_correction + c.vertical_offset_correction * c.sin_vert_correction;
  const double h = c.horizontal_offset_correction;
  return {r * std::cos(alpha) + h * std::sin(alpha), -(r * std::sin(alpha) - h * std::cos(alpha)),
          d * c.sin_vert_correction + c.vertical_offset_correction};
}

void expect_point(const VelodyneDecodeResult& r, std::size_t i, const Eigen::Vector3d& want) {
  ASSERT_LT(i, r.cloud.x.size());
  EXPECT_NEAR(r.cloud.x[i], want.x(), 1e-5);
  EXPECT_NEAR(r.cloud.y[i], want.y(), 1e-5);
  EXPECT_NEAR(r.cloud.z[i], want.z(), 1e-5);
}

TEST(VelodyneDecode, Vlp16ReturnsAtTheirFiringTimes) {
  VelodyneScan s;
  s.calibration = calibration(16);
  VelodynePacket p = packet(35990, 20);  // wraps past 0 after the first block
  set_return(p, 0, 3, 5000, 7);          // laser 3, first firing sequence
  set_return(p, 2, 16 + 5, 12345, 9);    // laser 5, second firing sequence
  set_return(p, 4, 0, 0, 1);             // no return
  s.packets.push_back(p);
  const VelodyneDecodeResult r = decode_velodyne_scan(s);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.cloud.x.size(), 2u);
  EXPECT_EQ(r.returns, 2u);
  expect_point(r, 0, expected(s.calibration[3], 5000, 35990 + 20 * (3 * 2.304) / 110.592));
  expect_point(r, 1, expected(s.calibration[5], 12345, 30 + 20 * (55.296 + 5 * 2.304) / 110.592));
  EXPECT_EQ(r.cloud.intensity[0], 7);
  EXPECT_EQ(r.cloud.laser_id[1], 5);
  EXPECT_NEAR(r.cloud.azimuth[0], (35990 + 20 * (3 * 2.304) / 110.592) / 100.0 * kDeg, 1e-6);
  // The ray's length is the corrected distance (no offsets here).
  EXPECT_NEAR(std::hypot(r.cloud.x[1], r.cloud.y[1], r.cloud.z[1]), 12345 * 0.002, 1e-5);
  // MRPT's decoding keeps the first firing sequence only.
  const VelodyneDecodeResult m = decode_velodyne_scan(s, {.decoding = VelodyneDecoding::Mrpt});
  ASSERT_TRUE(m.ok());
  ASSERT_EQ(m.cloud.x.size(), 1u);
  EXPECT_NEAR(m.cloud.x[0], r.cloud.x[0], 5000 * 0.002 * 1e-4);
  EXPECT_NEAR(m.cloud.y[0], r.cloud.y[0], 5000 * 0.002 * 2e-4);
}

TEST(VelodyneDecode, Hdl32eLasersAndCalibrationOffsets) {
  VelodyneScan s;
  s.calibration = calibration(32, 0.05, 0.02, -0.03);
  VelodynePacket p = packet(9000, 15);
  p[1205] = 0x21;
  set_return(p, 1, 20, 30000, 200);
  s.packets.push_back(p);
  const VelodyneDecodeResult r = decode_velodyne_scan(s);
  ASSERT_TRUE(r.ok()) << r.message;
  ASSERT_EQ(r.cloud.x.size(), 1u);
  expect_point(r, 0, expected(s.calibration[20], 30000, 9015 + 15 * 20 * 1.152 / 46.08));
  EXPECT_EQ(r.cloud.laser_id[0], 20);
  // Lasers 16-31 are beyond MRPT's 16 returns a block.
  EXPECT_TRUE(decode_velodyne_scan(s, {.decoding = VelodyneDecoding::Mrpt}).cloud.x.empty());
}

TEST(VelodyneDecode, DualReturnsDropDuplicatesAndFollowTheKeepFlags) {
  VelodyneScan s;
  s.calibration = calibration(16);
  VelodynePacket p = packet(500, 40, true);
  set_return(p, 2, 1, 4000, 10);  // last return of pair 1
  set_return(p, 3, 1, 4000, 30);  // strongest, the same distance: dropped
  set_return(p, 2, 2, 6000, 11);  // last
  set_return(p, 3, 2, 7000, 50);  // strongest, farther
  s.packets.push_back(p);
  const VelodyneDecodeResult r = decode_velodyne_scan(s);
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(r.cloud.x.size(), 3u);
  // Both blocks of a pair are at the pair's azimuth and timing.
  const double a2 = 540 + 40 * (2 * 2.304) / 110.592;
  expect_point(r, 1, expected(s.calibration[2], 6000, a2));
  expect_point(r, 2, expected(s.calibration[2], 7000, a2));
  EXPECT_EQ(decode_velodyne_scan(s, {.keep_strongest = false}).cloud.x.size(), 2u);
  EXPECT_EQ(decode_velodyne_scan(s, {.keep_last = false}).cloud.x.size(), 1u);
}

TEST(VelodyneDecode, RangesHeadersAndMissingCalibration) {
  VelodyneScan s;
  s.calibration = calibration(16);
  VelodynePacket p = packet(0, 20);
  set_return(p, 0, 0, 400, 1);    // 0.8 m: below the 1 m minimum
  set_return(p, 0, 1, 30000, 1);  // 60 m
  set_return(p, 5, 2, 2000, 1);   // in a block with a foreign header
  p[500] = 0xFF, p[501] = 0xDD;
  s.packets.push_back(p);
  VelodyneDecodeResult r = decode_velodyne_scan(s);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.cloud.x.size(), 1u);
  EXPECT_EQ(r.returns, 2u);
  EXPECT_EQ(r.skipped_blocks, 1u);
  EXPECT_NE(r.message.find("1 blocks skipped"), std::string::npos) << r.message;
  EXPECT_TRUE(decode_velodyne_scan(s, {.max_range_m = 50.0}).cloud.x.empty());
  EXPECT_EQ(decode_velodyne_scan(s, {.min_range_m = 0.5}).cloud.x.size(), 1u);  // the scan's 1 m still holds
  s.min_range_m = 0.3;
  EXPECT_EQ(decode_velodyne_scan(s, {.min_range_m = 0.5}).cloud.x.size(), 2u);
  s.max_range_m = 40.0;  // the scan's own limit applies too
  EXPECT_TRUE(decode_velodyne_scan(s).cloud.x.empty());
  EXPECT_THROW(decode_velodyne_scan(s, {.min_range_m = std::nan("")}), InvalidArgument);

  s.calibration.clear();
  r = decode_velodyne_scan(s);
  EXPECT_EQ(r.termination, VelodyneDecodeTermination::NoCalibration);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message.find("no per-laser calibration"), std::string::npos) << r.message;
  s.calibration = calibration(16);
  s.calibration.resize(20);
  r = decode_velodyne_scan(s);
  EXPECT_EQ(r.termination, VelodyneDecodeTermination::UnsupportedCalibration);
  EXPECT_NE(r.message.find("20 lasers"), std::string::npos) << r.message;
  s.packets.clear();
  EXPECT_TRUE(decode_velodyne_scan(s).ok());
}

}  // namespace
}  // namespace rove
