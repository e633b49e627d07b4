// The MRPT readers added for 3D, lidar, GNSS and RGB-D data and for
// particle / SOG pose PDFs, on files written by libmrpt 2.5.8
// (tools/mrpt_obs_reference) and on hand-built records: field values,
// CSimpleMap version 2, and the rejection of data rove cannot represent.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <span>
#include <string>
#include <vector>

#include "rove/core/error.h"
#include "rove/io/mrpt_objects.h"
#include "rove/io/mrpt_simplemap.h"
#include "rove/io/rawlog_reader.h"
#include "rove/obs/range_image_3d.h"
#include "rove/serialization/memory_stream.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kData = ROVE_SOURCE_DIR "/modules/io/tests/data/";


// MRPT's encoding: little-endian scalars and framed objects.
struct Bytes {
  std::vector<std::byte> data;
  template <typename T>
  Bytes& put(T v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
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
  // MRPT's null object: the name "nullptr", no version, the end marker.
  Bytes& null_object() {
    put<std::uint8_t>(0x80 | 7);
    for (char c : std::string("nullptr")) data.push_back(static_cast<std::byte>(c));
    return end();
  }
};

std::vector<std::byte> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  EXPECT_TRUE(in.good()) << "missing " << path;
  const std::vector<char> c((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> out(c.size());
  std::memcpy(out.data(), c.data(), c.size());
  return out;
}

// tools/mrpt_obs_reference `synthetic` writes a CPosePDFParticles of three
// particles (1 + i, −0.5 i, 0.1 i) with log-weights −0.5 i, then a
// CPosePDFSOG of two modes.
TEST(MrptSensorObjects, PosePdfParticlesAndSogWrittenByLibmrpt) {
  const std::vector<std::byte> bytes = read_bytes(kData + "mrpt_synthetic_pose_pdfs.bin");
  MemoryInStream s(bytes, "pose_pdfs");
  InArchive ar(s);
  const auto particles = std::get<Pose2Particles>(read_mrpt_object(ar));
  ASSERT_EQ(particles.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const auto& p = particles.particles()[i];
    EXPECT_EQ(p.pose.x(), 1.0 + i);
    EXPECT_EQ(p.pose.y(), -0.5 * i);
    EXPECT_NEAR(p.pose.phi(), 0.1 * i, 1e-15);
    EXPECT_EQ(p.log_weight, -0.5 * i);
  }
  const auto sog = std::get<Pose2SOG>(read_mrpt_object(ar));
  ASSERT_EQ(sog.size(), 2u);
  EXPECT_EQ(sog.modes()[0].log_weight, -0.1);
  const Pose2 m0 = sog.modes()[0].gaussian.mean();
  const Pose2 m1 = sog.modes()[1].gaussian.mean();
  EXPECT_EQ(m0.x(), 1.0);
  EXPECT_EQ(m0.y(), 2.0);
  EXPECT_NEAR(m0.phi(), 0.3, 1e-15);
  EXPECT_EQ(m1.x(), -1.0);
  EXPECT_NEAR(m1.phi(), -2.0, 1e-15);
  EXPECT_EQ(sog.modes()[1].gaussian.covariance()(0, 0), 0.5);
  EXPECT_EQ(sog.modes()[1].gaussian.covariance()(2, 0), 0.01);
  EXPECT_EQ(sog.modes()[1].log_weight, -2.0);
  EXPECT_TRUE(ar.at_end());
}

Bytes pose3_gaussian(double x) {
  Bytes b;
  b.begin("CPose3DPDFGaussian", 1).begin("CPose3D", 2);
  for (double v : {x, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0}) b.put(v);
  b.end();
  for (int i = 0; i < 6; ++i) b.put(0.25);  // diagonal
  for (int i = 0; i < 15; ++i) b.put(0.0);  // upper triangle
  return b.end();
}

// CSimpleMap version 2 (MRPT >= 2.11): each keyframe ends with
// std::optional<TTwist3D>.
TEST(MrptSensorObjects, SimpleMapVersion2LocalTwist) {
  Bytes b;
  b.begin("CSimpleMap", 2).put<std::uint32_t>(2);
  const Bytes g1 = pose3_gaussian(1.0);
  b.data.insert(b.data.end(), g1.data.begin(), g1.data.end());
  b.null_object().str("std::optional").str("TTwist3D").put<std::uint8_t>(1);
  for (double v : {0.5, 0.0, 0.0, 0.0, 0.0, -0.25}) b.put(v);
  const Bytes g2 = pose3_gaussian(2.0);
  b.data.insert(b.data.end(), g2.data.begin(), g2.data.end());
  b.null_object().str("std::optional").str("TTwist3D").put<std::uint8_t>(0);
  b.end();
  MemoryInStream s(b.data, "v2.simplemap");
  InArchive ar(s);
  const SimpleMap map = read_mrpt_simplemap(ar);
  ASSERT_EQ(map.keyframes.size(), 2u);
  EXPECT_EQ(map.keyframes[0].pose.mean().x(), 1.0);
  EXPECT_EQ(map.keyframes[0].pose.covariance()(5, 5), 0.25);
  ASSERT_TRUE(map.keyframes[0].local_twist.has_value());
  EXPECT_EQ(map.keyframes[0].local_twist->vx, 0.5);
  EXPECT_EQ(map.keyframes[0].local_twist->wz, -0.25);
  EXPECT_TRUE(map.keyframes[0].frame->empty());
  EXPECT_FALSE(map.keyframes[1].local_twist.has_value());
  EXPECT_TRUE(ar.at_end());

  Bytes bad;  // a twist stored under another type name
  bad.begin("CSimpleMap", 2).put<std::uint32_t>(1);
  bad.data.insert(bad.data.end(), g1.data.begin(), g1.data.end());
  bad.null_object().str("std::optional").str("TTwist2D").put<std::uint8_t>(0).end();
  MemoryInStream bs(bad.data, "bad.simplemap");
  InArchive bar(bs);
  EXPECT_THROW(read_mrpt_simplemap(bar), ParseError);
}

// The RGB-D frame: depth in millimeters, color converted from MRPT's BGR.
TEST(MrptSensorObjects, RgbdFrameValues) {
  const Rawlog log = load_rawlog(test_data::mrpt_package_file("tests_rgbd.rawlog"));
  ASSERT_EQ(log.entries.size(), 1u);
  const auto& o = std::get<std::shared_ptr<const Observation>>(log.entries[0]);
  const auto& r = dynamic_cast<const RangeImage3D&>(*o);
  EXPECT_EQ(r.depth.width, 640u);
  EXPECT_EQ(r.depth.height, 480u);
  EXPECT_NEAR(r.depth.scale, 1000.0, 1e-3);
  ASSERT_TRUE(r.intensity.has_value());
  EXPECT_EQ(r.intensity->channels, 3u);
  // libmrpt: pixel (0, 0) is B 148, G 135, R 103 (mrpt_ref_tests_rgbd.txt).
  EXPECT_EQ(r.intensity->data[0], 103);
  EXPECT_EQ(r.intensity->data[1], 135);
  EXPECT_EQ(r.intensity->data[2], 148);
  ASSERT_TRUE(r.points.has_value());
  EXPECT_EQ(r.points->p_sensor.size(), 273225u);
  EXPECT_NO_THROW(r.check());
  // Every stored point lies on its pixel's ray within float precision.
  const auto proj = r.project({RangeImageFrame::Sensor, std::nullopt});
  EXPECT_GT(proj.points.size(), 200000u);
}

// Regression: a truncated RGB-D frame (the image cut mid-row) is a
// ParseError naming the file and an offset, not a short read.
TEST(MrptSensorObjects, TruncatedRgbdFrameIsParseError) {
  std::vector<std::byte> bytes = read_bytes(kData + "mrpt_synthetic_sensors.rawlog");
  // Keep the Velodyne scan and the GNSS fix, cut inside the 3D scan.
  RawlogReader full(std::make_unique<MemoryInStream>(bytes, "full"));
  ASSERT_TRUE(full.next());
  ASSERT_TRUE(full.next());
  const std::uint64_t scan_at = full.offset();
  bytes.resize(scan_at + 200);
  RawlogReader cut(std::make_unique<MemoryInStream>(bytes, "cut.rawlog"));
  ASSERT_TRUE(cut.next());
  ASSERT_TRUE(cut.next());
  try {
    cut.next();
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, "cut.rawlog");
    ASSERT_TRUE(e.location().offset.has_value());
    EXPECT_GE(*e.location().offset, scan_at);
  }
}

// Data rove does not decode is rejected with the class named.
TEST(MrptSensorObjects, UnsupportedContentIsRejected) {
  Bytes jpeg;  // CImage v9, color, positive size: a JPEG stream follows
  jpeg.begin("CImage", 9).put<std::uint8_t>(0).put<std::uint8_t>(1);
  jpeg.put<std::int32_t>(2).put<std::int32_t>(2).put<std::uint32_t>(3);
  jpeg.put<std::uint8_t>(1).put<std::uint8_t>(2).put<std::uint8_t>(3).end();
  MemoryInStream js(jpeg.data, "jpeg");
  InArchive jar(js);
  try {
    read_mrpt_object(jar);
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("JPEG"), std::string::npos) << e.what();
  }

  Bytes gnss;  // CObservationGPS v11 with a Novatel message
  gnss.begin("CObservationGPS", 11).put<std::uint64_t>(0).put<std::uint64_t>(0).str("G");
  gnss.begin("CPose3D", 2);
  for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0}) gnss.put(v);
  gnss.end().put<std::uint8_t>(0).put<std::uint32_t>(1).put<std::int32_t>(1042);
  gnss.put<std::uint32_t>(4).put<std::uint32_t>(0).end();
  MemoryInStream gs(gnss.data, "gnss");
  InArchive gar(gs);
  EXPECT_THROW(read_mrpt_object(gar), ParseError);

  Bytes velo;  // a Velodyne scan declaring 2^31 packets with no data
  velo.begin("CObservationVelodyneScan", 2).put<std::uint64_t>(0).str("V").put(1.0).put(2.0);
  velo.begin("CPose3D", 2);
  for (double v : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0}) velo.put(v);
  velo.end().put<std::uint32_t>(0x80000000u);
  MemoryInStream vs(velo.data, "velo");
  InArchive var(vs);
  EXPECT_THROW(read_mrpt_object(var), ParseError);
}

}  // namespace
}  // namespace rove
