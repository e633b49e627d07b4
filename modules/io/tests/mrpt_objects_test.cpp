// read_mrpt_object on hand-built MRPT records: each class's field order per
// MRPT's serializeFrom, layout #2 rawlogs, and rejection of bad input.

#include "rove/io/mrpt_objects.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "rove/core/error.h"
#include "rove/io/rawlog_reader.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/serialization/memory_stream.h"

namespace rove {
namespace {

// Writes MRPT's encoding: little-endian scalars and framed objects.
struct Bytes {
  std::vector<std::byte> data;
  template <typename T>
  Bytes& put(T v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // the test hosts are little-endian
    for (unsigned char c : b) data.push_back(static_cast<std::byte>(c));
    return *this;
  }
  Bytes& str(const std::string& s) {
    put<std::uint32_t>(static_cast<std::uint32_t>(s.size()));
    for (char c : s) data.push_back(static_cast<std::byte>(c));
    return *this;
  }
  Bytes& begin(const std::string& cls, std::uint8_t version) {
    put<std::uint8_t>(static_cast<std::uint8_t>(0x80 | cls.size()));
    for (char c : cls) data.push_back(static_cast<std::byte>(c));
    return put<std::uint8_t>(version);
  }
  Bytes& end() { return put<std::uint8_t>(0x88); }
  Bytes& pose2(double x, double y, double phi) {
    return begin("CPose2D", 1).put(x).put(y).put(phi).end();
  }
};

MrptObject read_all(const Bytes& b) {
  MemoryInStream s(std::span<const std::byte>(b.data), "test");
  InArchive ar(s);
  MrptObject o = read_mrpt_object(ar);
  EXPECT_TRUE(ar.at_end());
  return o;
}

Bytes odometry_v2(double x, std::uint64_t ticks) {
  Bytes b;
  b.begin("CObservationOdometry", 2).pose2(x, 2.0, 0.5).str("ODO").put<std::uint64_t>(ticks);
  b.put<std::uint8_t>(1).put<std::int32_t>(-3).put<std::int32_t>(7);  // encoders
  b.put<std::uint8_t>(1).put(0.25).put(0.0).put(-0.125);              // velocity
  return b.end();
}

TEST(MrptObjects, OdometryVersion2) {
  const auto o = read_all(odometry_v2(1.0, 127823078257133856ULL));
  const auto& obs = std::get<std::shared_ptr<Observation>>(o);
  const auto* odo = dynamic_cast<const OdometryObservation*>(obs.get());
  ASSERT_NE(odo, nullptr);
  EXPECT_EQ(odo->odometry, Pose2(1.0, 2.0, 0.5));
  EXPECT_EQ(odo->sensor_label, "ODO");
  EXPECT_EQ(odo->timestamp.to_mrpt(), 127823078257133856ULL);
  ASSERT_TRUE(odo->encoder_ticks.has_value());
  EXPECT_EQ(odo->encoder_ticks->left, -3);
  EXPECT_EQ(odo->encoder_ticks->right, 7);
  ASSERT_TRUE(odo->velocity.has_value());
  EXPECT_EQ(odo->velocity->vx, 0.25);
  EXPECT_EQ(odo->velocity->omega, -0.125);
}

TEST(MrptObjects, LayoutTwoRawlog) {
  Bytes b = odometry_v2(1.0, 127823078257133856ULL);
  const Bytes second = odometry_v2(2.0, 127823078258133856ULL);
  b.data.insert(b.data.end(), second.data.begin(), second.data.end());
  RawlogReader reader(std::make_unique<MemoryInStream>(b.data, "layout2"));
  std::vector<RawlogEntry> entries;
  while (auto e = reader.next()) entries.push_back(*e);
  ASSERT_EQ(entries.size(), 2u);
  const auto& o = std::get<std::shared_ptr<const Observation>>(entries[1]);
  EXPECT_EQ(dynamic_cast<const OdometryObservation&>(*o).odometry, Pose2(2.0, 2.0, 0.5));
}

TEST(MrptObjects, Pose3Versions) {
  Bytes q;  // v2: x y z qw qx qy qz (90° about z)
  q.begin("CPose3D", 2).put(1.0).put(2.0).put(3.0);
  q.put(std::sqrt(0.5)).put(0.0).put(0.0).put(std::sqrt(0.5)).end();
  const Pose3 a = std::get<Pose3>(read_all(q));
  EXPECT_NEAR(a.yaw(), std::numbers::pi / 2, 1e-12);
  EXPECT_EQ(a.z(), 3.0);
  Bytes m;  // v3: x y z, rotation row by row
  m.begin("CPose3D", 3).put(1.0).put(2.0).put(3.0);
  for (double v : {0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0}) m.put(v);
  m.end();
  const Pose3 b = std::get<Pose3>(read_all(m));
  EXPECT_NEAR(b.yaw(), std::numbers::pi / 2, 1e-12);
  EXPECT_EQ(b.x(), 1.0);
}

TEST(MrptObjects, PosePdfGaussianSymmetricCovariance) {
  Bytes b;  // v2: mean, diagonal, then upper triangle row by row
  b.begin("CPosePDFGaussian", 2).pose2(1.0, 0.0, 0.0);
  for (double v : {4.0, 5.0, 6.0, 0.1, 0.2, 0.3}) b.put(v);
  b.end();
  const auto g = std::get<Pose2Gaussian>(read_all(b));
  EXPECT_EQ(g.covariance()(0, 0), 4.0);
  EXPECT_EQ(g.covariance()(2, 2), 6.0);
  EXPECT_EQ(g.covariance()(0, 1), 0.1);
  EXPECT_EQ(g.covariance()(2, 0), 0.2);
  EXPECT_EQ(g.covariance()(1, 2), 0.3);
}

TEST(MrptObjects, UnknownClassNamesClassAndOffset) {
  Bytes b;
  b.put<std::uint8_t>(0).begin("CObservationMystery", 0).end();
  MemoryInStream s(std::span<const std::byte>(b.data), "mystery.rawlog");
  InArchive ar(s);
  ar.read_scalar<std::uint8_t>();
  try {
    read_mrpt_object(ar);
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, "mystery.rawlog");
    EXPECT_EQ(e.location().offset, 1u);
    EXPECT_NE(std::string(e.what()).find("CObservationMystery"), std::string::npos) << e.what();
  }
}

TEST(MrptObjects, UnknownVersionAndBadValuesAreParseErrors) {
  Bytes v;
  v.begin("CPose2D", 9).put(1.0).put(2.0).put(3.0).end();
  EXPECT_THROW(read_all(v), ParseError);
  Bytes nan;
  nan.pose2(std::nan(""), 0.0, 0.0);
  EXPECT_THROW(read_all(nan), ParseError);
  Bytes rot;  // not a rotation
  rot.begin("CPose3D", 3);
  for (int i = 0; i < 12; ++i) rot.put(2.0);
  rot.end();
  EXPECT_THROW(read_all(rot), ParseError);
  Bytes huge;  // a scan declaring 2^31 rays with no data behind them
  huge.begin("CObservation2DRangeScan", 6).put(3.14f).put<std::uint8_t>(1).put(80.0f);
  huge.begin("CPose3D", 3);
  for (double x : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) huge.put(x);
  huge.end().put<std::uint32_t>(0x80000000u);
  EXPECT_THROW(read_all(huge), ParseError);
  Bytes wrong_nested;  // a sensory frame holding a pose
  wrong_nested.begin("CSensoryFrame", 2).put<std::uint32_t>(1).pose2(0, 0, 0).end();
  EXPECT_THROW(read_all(wrong_nested), ParseError);
}

TEST(MrptObjects, SupportedClasses) {
  EXPECT_TRUE(is_supported_mrpt_class("CSensoryFrame"));
  EXPECT_TRUE(is_supported_mrpt_class("CActionRobotMovement2D"));
  EXPECT_FALSE(is_supported_mrpt_class("CObservationMystery"));
}

}  // namespace
}  // namespace rove
