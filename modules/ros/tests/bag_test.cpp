// ROS 1 bags: bags written with the rosbag C++ API read back exactly by
// rove's own parser (checked against rosbag::View), every supported message
// type, compressed chunks, unknown topics, truncated files, and the round
// trip rove rawlog → bag → rove.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "bag_file.h"
#include "ros_convert.h"
#include "ros_messages.h"
#include "ros_plain.h"
#include "rove/core/error.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/image_observation.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_image_3d.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/poses/angle.h"
#include "rove/ros/bag_reader.h"
#include "rove/ros/bag_writer.h"

namespace fs = std::filesystem;
using namespace rove;
using namespace rove::bag_detail;

namespace {

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           (std::string("rove_ros_") + info->test_suite_name() + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~TempDir() { fs::remove_all(dir_); }
  std::string operator/(const std::string& name) const { return (dir_ / name).string(); }

 private:
  fs::path dir_;
};

MsgHeader header(std::uint32_t sec, std::uint32_t nsec, const std::string& frame) {
  MsgHeader h;
  h.sec = sec;
  h.nsec = nsec;
  h.frame_id = frame;
  return h;
}

LaserScanMsg sample_scan(std::uint32_t sec) {
  LaserScanMsg m;
  m.header = header(sec, 250, "laser");
  m.angle_min = static_cast<float>(-kPi / 2);
  m.angle_max = static_cast<float>(kPi / 2);
  m.angle_increment = static_cast<float>(kPi / 4);
  m.range_min = 0.1f;
  m.range_max = 30.0f;
  m.ranges = {1.5f, 0.05f, 29.0f, std::numeric_limits<float>::infinity(), 2.25f};
  m.intensities = {10.0f, 20.0f, 30.0f, 40.0f, 50.0f};
  return m;
}

OdometryMsg sample_odometry(std::uint32_t sec, double x, double y, double yaw) {
  OdometryMsg m;
  m.header = header(sec, 0, "odom");
  m.child_frame_id = "base_link";
  m.position = {x, y, 0.0};
  m.orientation = {0.0, 0.0, std::sin(yaw / 2), std::cos(yaw / 2)};
  m.linear = {0.5, 0.0, 0.0};
  m.angular = {0.0, 0.0, 0.25};
  return m;
}

TfMsg sample_tf(std::uint32_t sec) {
  TfMsg tf;
  TransformMsg t;
  t.header = header(sec, 0, "base_link");
  t.child_frame_id = "laser";
  t.translation = {0.2, 0.0, 0.3};
  t.rotation = {0.0, 0.0, 0.0, 1.0};
  tf.transforms.push_back(t);
  t.child_frame_id = "camera_depth_optical_frame";
  t.translation = {0.1, 0.05, 0.8};
  // The optical frame of a camera looking forward: yaw −90°, roll −90°.
  pose3_to_ros(Pose3(0.1, 0.05, 0.8, 0, 0, 0) + sensor_from_optical(), t.translation, t.rotation);
  tf.transforms.push_back(t);
  t.child_frame_id = "camera_rgb_optical_frame";
  pose3_to_ros(Pose3(0.1, 0.02, 0.8, 0, 0, 0) + sensor_from_optical(), t.translation, t.rotation);
  tf.transforms.push_back(t);
  return tf;
}

CameraInfoMsg sample_info(std::uint32_t sec, const std::string& frame) {
  PinholeCamera c;
  c.width = 4;
  c.height = 3;
  c.fx = 525.0;
  c.fy = 524.0;
  c.cx = 1.5;
  c.cy = 1.0;
  c.distortion = {0.1, -0.05, 0.001, 0.002, 0.0};
  CameraInfoMsg m = camera_to_ros(c);
  m.header = header(sec, 0, frame);
  return m;
}

ImageMsg sample_depth(std::uint32_t sec) {
  ImageMsg m;
  m.header = header(sec, 0, "camera_depth_optical_frame");
  m.width = 4;
  m.height = 3;
  m.encoding = "16UC1";
  m.step = 10;  // two bytes of row padding
  m.data.assign(30, 0);
  for (std::uint32_t v = 0; v < 3; ++v) {
    for (std::uint32_t u = 0; u < 4; ++u) {
      const std::uint16_t mm = static_cast<std::uint16_t>(1000 + 100 * v + u);
      m.data[v * 10 + 2 * u] = static_cast<std::uint8_t>(mm & 0xff);
      m.data[v * 10 + 2 * u + 1] = static_cast<std::uint8_t>(mm >> 8);
    }
  }
  return m;
}

ImageMsg sample_color(std::uint32_t sec) {
  ImageMsg m;
  m.header = header(sec, 0, "camera_rgb_optical_frame");
  m.width = 4;
  m.height = 3;
  m.encoding = "bgr8";
  m.step = 12;
  for (std::uint8_t i = 0; i < 36; ++i) m.data.push_back(i);
  return m;
}

PointCloud2Msg sample_cloud(std::uint32_t sec) {
  RangeImagePoints p;
  p.p_sensor = {{1.0f, 2.0f, 3.0f}, {-1.5f, 0.25f, 4.0f}};
  PointCloud2Msg m = cloud_to_ros(p);
  m.header = header(sec, 0, "laser");
  return m;
}

// Writes one message of every supported type (and an unsupported one).
void write_every_type(const std::string& path, ChunkCompression compression) {
  RosbagWriter bag(path, compression);
  bag.write("/tf_static", 100, 0, sample_tf(100));
  bag.write("/camera/depth/camera_info", 100, 0, sample_info(100, "camera_depth_optical_frame"));
  bag.write("/camera/rgb/camera_info", 100, 0, sample_info(100, "camera_rgb_optical_frame"));
  bag.write("/odom", 100, 0, sample_odometry(100, 0.0, 0.0, 0.0));
  bag.write_text("/chatter", 100, 5, "hello");
  bag.write("/scan", 100, 250, sample_scan(100));
  bag.write("/odom", 101, 0, sample_odometry(101, 1.0, 0.5, 0.3));
  bag.write("/scan", 101, 250, sample_scan(101));
  bag.write("/velodyne/points", 102, 0, sample_cloud(102));
  bag.write("/camera/depth/image_raw", 103, 0, sample_depth(103));
  bag.write("/camera/rgb/image_raw", 103, 0, sample_color(103));
  bag.write_text("/chatter", 104, 0, "bye");
  bag.close();
}

std::vector<RawlogEntry> read_all(BagReader& r) {
  std::vector<RawlogEntry> out;
  while (auto e = r.next()) out.push_back(std::move(*e));
  return out;
}

template <typename T>
std::shared_ptr<const T> bare(const RawlogEntry& e) {
  const auto* o = std::get_if<std::shared_ptr<const Observation>>(&e);
  return o ? std::dynamic_pointer_cast<const T>(*o) : nullptr;
}

bool has_line(const std::vector<std::string>& lines, const std::string& part) {
  for (const auto& l : lines) {
    if (l.find(part) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

TEST(RosMessageTypes, Md5SumsAreThoseOfTheInstalledDefinitions) {
  const auto infos = ros_type_infos();
  ASSERT_EQ(infos.size(), 6u);
  const std::pair<std::string_view, std::string_view> ours[] = {
      {kLaserScanType, kLaserScanMd5},   {kOdometryType, kOdometryMd5},
      {kPointCloud2Type, kPointCloud2Md5}, {kImageType, kImageMd5},
      {kCameraInfoType, kCameraInfoMd5}, {kTfType, kTfMd5}};
  for (std::size_t i = 0; i < infos.size(); ++i) {
    EXPECT_EQ(infos[i].datatype, ours[i].first);
    EXPECT_EQ(infos[i].md5sum, ours[i].second);
  }
}

TEST(BagFile, ReadsWhatRosbagViewReads) {
  TempDir dir;
  for (auto c : {ChunkCompression::None, ChunkCompression::Bz2, ChunkCompression::Lz4}) {
    const std::string path = dir / "every.bag";
    write_every_type(path, c);
    // rosbag::View orders messages of equal time by connection; compare
    // both as sorted lists of (time, topic, type, size).
    using Row = std::tuple<std::uint32_t, std::uint32_t, std::string, std::string, std::uint32_t>;
    std::vector<Row> want, got;
    for (const auto& v : read_with_rosbag_view(path)) {
      want.emplace_back(v.sec, v.nsec, v.topic, v.datatype, v.size);
    }
    BagFile file(path);
    std::uint32_t last_sec = 0;
    while (auto m = file.next()) {
      EXPECT_GE(m->sec, last_sec);  // time order
      last_sec = m->sec;
      got.emplace_back(m->sec, m->nsec, m->connection->topic, m->connection->datatype,
                       static_cast<std::uint32_t>(m->data.size()));
    }
    std::sort(want.begin(), want.end());
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, want);
    EXPECT_EQ(got.size(), 12u);
    EXPECT_FALSE(file.stats().stopped_at);
    EXPECT_TRUE(file.stats().indexed);
    const char* name = c == ChunkCompression::None ? "none" : c == ChunkCompression::Bz2 ? "bz2" : "lz4";
    EXPECT_EQ(file.stats().chunks_by_compression.size(), 1u);
    EXPECT_GE(file.stats().chunks_by_compression.at(name), 1u);
  }
}

TEST(BagFile, MessagesParseToTheFieldsWritten) {
  TempDir dir;
  const std::string path = dir / "every.bag";
  write_every_type(path, ChunkCompression::None);
  BagFile file(path);
  int seen = 0;
  while (auto m = file.next()) {
    const std::string& type = m->connection->datatype;
    if (type == kLaserScanType) {
      LaserScanMsg s;
      parse(m->data, "test", s);
      const LaserScanMsg want = sample_scan(m->sec);
      EXPECT_EQ(s.header.frame_id, "laser");
      EXPECT_EQ(s.header.nsec, 250u);
      EXPECT_EQ(s.angle_increment, want.angle_increment);
      EXPECT_EQ(s.range_min, want.range_min);
      EXPECT_EQ(s.intensities, want.intensities);
      ASSERT_EQ(s.ranges.size(), want.ranges.size());
      for (std::size_t i = 0; i < s.ranges.size(); ++i) EXPECT_EQ(s.ranges[i], want.ranges[i]);
      ++seen;
    } else if (type == kCameraInfoType) {
      CameraInfoMsg ci;
      parse(m->data, "test", ci);
      const CameraInfoMsg want = sample_info(100, ci.header.frame_id);
      EXPECT_EQ(ci.K, want.K);
      EXPECT_EQ(ci.P, want.P);
      EXPECT_EQ(ci.D, want.D);
      EXPECT_EQ(ci.distortion_model, "plumb_bob");
      ++seen;
    } else if (type == kImageType) {
      ImageMsg im;
      parse(m->data, "test", im);
      const ImageMsg want = im.encoding == "16UC1" ? sample_depth(103) : sample_color(103);
      EXPECT_EQ(im.data, want.data);
      EXPECT_EQ(im.step, want.step);
      ++seen;
    }
  }
  EXPECT_EQ(seen, 6);
}

TEST(BagReader, EveryTypeAsObservations) {
  TempDir dir;
  const std::string path = dir / "every.bag";
  write_every_type(path, ChunkCompression::Lz4);
  BagReadOptions o;
  o.layout = RawlogLayout::Observations;
  BagReader reader(path, o);
  const auto entries = read_all(reader);
  // odom, scan, odom, scan, cloud, RGB-D.
  ASSERT_EQ(entries.size(), 6u);

  auto odo = bare<OdometryObservation>(entries[2]);
  ASSERT_TRUE(odo);
  EXPECT_EQ(odo->timestamp, Timestamp::from_ns(101'000'000'000));
  EXPECT_EQ(odo->sensor_label, "odom");
  EXPECT_EQ(odo->odometry.x(), 1.0);
  EXPECT_EQ(odo->odometry.y(), 0.5);
  EXPECT_NEAR(odo->odometry.phi(), 0.3, 1e-15);
  ASSERT_TRUE(odo->velocity);
  EXPECT_EQ(odo->velocity->vx, 0.5);
  EXPECT_EQ(odo->velocity->omega, 0.25);

  auto scan = bare<RangeScan2D>(entries[1]);
  ASSERT_TRUE(scan);
  const LaserScanMsg want = sample_scan(100);
  EXPECT_EQ(scan->timestamp, Timestamp::from_ns(100'000'000'250));
  EXPECT_EQ(scan->sensor_label, "scan");
  EXPECT_EQ(scan->ranges, want.ranges);
  EXPECT_EQ(scan->valid, (std::vector<bool>{true, false, true, false, true}));
  EXPECT_EQ(scan->intensity, (std::vector<std::int32_t>{10, 20, 30, 40, 50}));
  EXPECT_EQ(scan->aperture, 2.0 * double(static_cast<float>(kPi / 2)));  // angle_max − angle_min
  EXPECT_TRUE(scan->right_to_left);
  EXPECT_EQ(scan->max_range, 30.0f);
  // The sensor pose from /tf_static: base_link ← laser.
  EXPECT_EQ(scan->T_robot_sensor.x(), 0.2);
  EXPECT_EQ(scan->T_robot_sensor.z(), 0.3);
  EXPECT_EQ(scan->T_robot_sensor.yaw(), 0.0);
  for (std::size_t i = 0; i < scan->size(); ++i) {
    EXPECT_NEAR(scan->ray_angle(i), want.angle_min + i * double(want.angle_increment), 1e-6);
  }

  auto cloud = bare<RangeImage3D>(entries[4]);
  ASSERT_TRUE(cloud);
  ASSERT_TRUE(cloud->points);
  EXPECT_EQ(cloud->sensor_label, "velodyne");
  EXPECT_EQ(cloud->points->p_sensor.size(), 2u);
  EXPECT_EQ(cloud->points->p_sensor[1], Eigen::Vector3f(-1.5f, 0.25f, 4.0f));
  EXPECT_EQ(cloud->T_robot_sensor.x(), 0.2);  // frame "laser"

  auto rgbd = bare<RangeImage3D>(entries[5]);
  ASSERT_TRUE(rgbd);
  EXPECT_EQ(rgbd->sensor_label, "camera");
  EXPECT_EQ(rgbd->depth.width, 4u);
  EXPECT_EQ(rgbd->depth.scale, 1000.0);
  EXPECT_DOUBLE_EQ(rgbd->depth.meters(3, 2), 1.203);
  EXPECT_EQ(rgbd->depth_camera.fx, 525.0);
  EXPECT_EQ(rgbd->depth_camera.cy, 1.0);
  EXPECT_EQ(rgbd->depth_camera.distortion[1], -0.05);
  ASSERT_TRUE(rgbd->intensity);
  EXPECT_EQ(rgbd->intensity->channels, 3u);
  // bgr8 → RGB: pixel 0 was (B, G, R) = (0, 1, 2).
  EXPECT_EQ(rgbd->intensity->data[0], 2);
  EXPECT_EQ(rgbd->intensity->data[2], 0);
  EXPECT_EQ(rgbd->intensity->data[4], 4);
  // Depth sensor frame x forward at (0.1, 0.05, 0.8); colour camera 3 cm
  // to its right: T_sensor_intensity = (0, -0.03, 0) ⊕ optical.
  EXPECT_NEAR(rgbd->T_robot_sensor.x(), 0.1, 1e-12);
  EXPECT_NEAR(rgbd->T_robot_sensor.y(), 0.05, 1e-12);
  EXPECT_NEAR(rgbd->T_robot_sensor.yaw(), 0.0, 1e-12);
  EXPECT_NEAR(rgbd->T_robot_sensor.roll(), 0.0, 1e-12);
  EXPECT_NEAR(rgbd->T_sensor_intensity.y(), -0.03, 1e-12);
  EXPECT_LT((rgbd->T_sensor_intensity.rotation() - sensor_from_optical().rotation()).norm(), 1e-12);
  EXPECT_NO_THROW(rgbd->check());

  // The unknown topic is counted, not fatal.
  const auto skipped = reader.skipped();
  EXPECT_TRUE(has_line(skipped, "2 messages on /chatter (std_msgs/String): unsupported message type"))
      << ::testing::PrintToString(skipped);
  EXPECT_EQ(reader.stats().read_by_topic.at("/scan"), 2u);
  EXPECT_EQ(reader.stats().read_by_topic.at("/tf_static"), 1u);
}

TEST(BagReader, OdometryBecomesIncrementsBeforeEachFrame) {
  TempDir dir;
  const std::string path = dir / "every.bag";
  write_every_type(path, ChunkCompression::Bz2);
  BagReader reader(path);  // layout #1
  const auto entries = read_all(reader);
  // SF(scan), AC, SF(scan), AC(0), SF(cloud), AC(0), SF(rgbd).
  ASSERT_EQ(entries.size(), 7u);
  ASSERT_TRUE(std::holds_alternative<std::shared_ptr<const SensoryFrame>>(entries[0]));
  const auto& ac = std::get<std::shared_ptr<const ActionCollection>>(entries[1]);
  auto move = ac->find<RobotMovement2D>();
  ASSERT_TRUE(move);
  // From (0, 0, 0) to (1, 0.5, 0.3): the increment in the first pose's frame.
  EXPECT_NEAR(move->odometry_increment.x(), 1.0, 1e-15);
  EXPECT_NEAR(move->odometry_increment.y(), 0.5, 1e-15);
  EXPECT_NEAR(move->odometry_increment.phi(), 0.3, 1e-15);
  EXPECT_EQ(move->timestamp, Timestamp::from_ns(101'000'000'000));
  const auto& ac2 = std::get<std::shared_ptr<const ActionCollection>>(entries[3]);
  EXPECT_EQ(ac2->find<RobotMovement2D>()->odometry_increment, Pose2());
}

TEST(BagReader, TopicsSelectTheSensors) {
  TempDir dir;
  const std::string path = dir / "every.bag";
  write_every_type(path, ChunkCompression::None);
  BagReadOptions o;
  o.layout = RawlogLayout::Observations;
  o.topics = {"/scan"};
  BagReader reader(path, o);
  const auto entries = read_all(reader);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_TRUE(bare<RangeScan2D>(entries[0]));
  EXPECT_TRUE(has_line(reader.skipped(), "2 messages on /odom (nav_msgs/Odometry): not among --topics"));
}

TEST(BagReader, TruncatedBagReadsItsCompleteMessagesAndSaysWhere) {
  TempDir dir;
  const std::string full = dir / "full.bag";
  {
    RosbagWriter bag(full, ChunkCompression::None);
    for (std::uint32_t i = 0; i < 200; ++i) bag.write("/scan", 100 + i, 250, sample_scan(100 + i));
    bag.close();
  }
  BagReadOptions o;
  o.layout = RawlogLayout::Observations;
  BagReader all(full, o);
  const auto every = read_all(all);
  ASSERT_EQ(every.size(), 200u);
  // Only the note that no /tf gives the laser's pose.
  ASSERT_EQ(all.skipped().size(), 1u) << ::testing::PrintToString(all.skipped());
  EXPECT_TRUE(has_line(all.skipped(), "no transform base_link <- laser"));

  // Cut the file inside its (single) chunk: the index and the later
  // messages are gone.
  const auto size = fs::file_size(full);
  for (const double keep : {0.3, 0.7}) {
    const std::string cut = dir / "cut.bag";
    fs::copy_file(full, cut, fs::copy_options::overwrite_existing);
    const auto kept = static_cast<std::uintmax_t>(keep * static_cast<double>(size));
    fs::resize_file(cut, kept);
    EXPECT_THROW(read_with_rosbag_view(cut), std::runtime_error);  // rosbag refuses it
    BagReader r(cut, o);
    const auto some = read_all(r);
    EXPECT_GT(some.size(), keep < 0.5 ? 10u : 100u);
    EXPECT_LT(some.size(), keep < 0.5 ? 100u : 200u);
    for (std::size_t i = 0; i < some.size(); ++i) {
      EXPECT_TRUE(bare<RangeScan2D>(some[i])->equals(*bare<RangeScan2D>(every[i])));
    }
    ASSERT_TRUE(r.stats().stopped_at);
    EXPECT_TRUE(has_line(r.skipped(), "stopped at byte")) << ::testing::PrintToString(r.skipped());
    EXPECT_TRUE(has_line(r.skipped(), fmt::format("of {}:", kept)));
  }
}

TEST(BagReader, TruncatedCompressedChunksKeepTheirDecompressedPrefix) {
  TempDir dir;
  for (auto c : {ChunkCompression::Bz2, ChunkCompression::Lz4}) {
    const std::string full = dir / "full.bag";
    {
      // Scans of 200 pseudo-random rays: about 1 MB in two chunks that do
      // not compress away, so that half the file ends inside a chunk.
      RosbagWriter bag(full, c);
      std::uint32_t lcg = 12345;
      for (std::uint32_t i = 0; i < 1200; ++i) {
        LaserScanMsg s = sample_scan(100 + i);
        s.ranges.resize(200);
        for (float& r : s.ranges) {
          lcg = lcg * 1664525u + 1013904223u;
          r = static_cast<float>(lcg >> 8) / 16777216.0f * 29.0f;
        }
        s.angle_increment = static_cast<float>(kPi / 199);
        s.intensities.clear();
        bag.write("/scan", 100 + i, 250, s);
      }
      bag.close();
    }
    BagReadOptions o;
    o.layout = RawlogLayout::Observations;
    const std::string cut = dir / "cut.bag";
    fs::copy_file(full, cut, fs::copy_options::overwrite_existing);
    // The first chunk (rosbag closes one at 768 KiB) stays whole, the
    // second is cut: bz2 and lz4 decompress only whole blocks, so its
    // messages are lost and reported.
    fs::resize_file(cut, fs::file_size(full) * 9 / 10);
    BagReader r(cut, o);
    const auto some = read_all(r);
    EXPECT_GT(some.size(), 300u);
    EXPECT_LT(some.size(), 1200u);
    for (std::size_t i = 0; i < some.size(); ++i) {
      EXPECT_EQ(bare<RangeScan2D>(some[i])->timestamp, Timestamp::from_ns((100 + i) * 1'000'000'000LL + 250));
    }
    EXPECT_TRUE(has_line(r.skipped(), "stopped at byte")) << ::testing::PrintToString(r.skipped());
    EXPECT_TRUE(has_line(r.skipped(), c == ChunkCompression::Bz2 ? "into a bz2 chunk" : "into a lz4 chunk"))
        << ::testing::PrintToString(r.skipped());
  }
}

TEST(BagReader, MalformedMessageIsSkippedWithItsField) {
  TempDir dir;
  const std::string path = dir / "bad.bag";
  {
    RosbagWriter bag(path, ChunkCompression::None);
    LaserScanMsg bad = sample_scan(100);
    bad.ranges = {1.0f};  // one ray: not a scan rove can use
    bag.write("/scan", 100, 0, bad);
    bag.write("/scan", 101, 0, sample_scan(101));
    bag.close();
  }
  BagReadOptions o;
  o.layout = RawlogLayout::Observations;
  BagReader r(path, o);
  EXPECT_EQ(read_all(r).size(), 1u);
  EXPECT_TRUE(has_line(r.skipped(), "1 messages on /scan (sensor_msgs/LaserScan): not convertible"))
      << ::testing::PrintToString(r.skipped());
}

TEST(BagReader, NotABagIsAParseError) {
  TempDir dir;
  const std::string path = dir / "text.bag";
  std::ofstream(path) << "#ROSBAG V2.0\nthis is not a record";
  EXPECT_THROW(BagReader r(path), ParseError);
  const std::string other = dir / "v1.bag";
  std::ofstream(other) << "#ROSRECORD V1.2\n";
  EXPECT_THROW(BagReader r(other), ParseError);
}

TEST(BagRoundTrip, RoveEntriesThroughABagComeBackEqual) {
  TempDir dir;
  const std::string in = dir / "in.rawlog";
  RangeScan2D scan;
  scan.timestamp = Timestamp::from_ns(1'700'000'000'123'456'789);
  scan.sensor_label = "LASER";
  scan.T_robot_sensor = Pose3(0.3, -0.1, 0.25, 0.0, 0.0, 0.0);
  scan.aperture = 270.0 * kPi / 180.0;
  scan.right_to_left = false;
  scan.max_range = 20.0f;
  scan.set_ranges({1.0f, 2.5f, 19.5f, 21.0f, 3.25f, 0.0f});
  scan.valid[4] = false;  // a range that would read as valid, flagged invalid
  scan.intensity = {1, 2, 3, 4, 5, 6};
  RangeImage3D rgbd;
  rgbd.timestamp = Timestamp::from_ns(1'700'000'001'000'000'000);
  rgbd.sensor_label = "kinect";
  rgbd.T_robot_sensor = Pose3(0.1, 0.0, 0.5, 0.0, 0.0, 0.0);
  rgbd.depth = DepthImage::zeros_u16(4, 3, 1000.0);
  rgbd.depth.set_meters(1, 1, 1.234);
  rgbd.depth_camera = {4, 3, 520.0, 521.0, 2.0, 1.5, {}};
  rgbd.max_range = std::numeric_limits<double>::infinity();
  rgbd.intensity = Image::zeros(4, 3, 3, PixelType::U8);
  rgbd.intensity->data[7] = 200;
  rgbd.intensity_camera = rgbd.depth_camera;
  RangeImage3D cloud;
  cloud.timestamp = Timestamp::from_ns(1'700'000'002'000'000'000);
  cloud.sensor_label = "lidar";
  cloud.points = RangeImagePoints{{{1.0f, 2.0f, 3.0f}, {4.0f, 5.0f, 6.5f}}, {}, {}};
  cloud.max_range = std::numeric_limits<double>::infinity();
  {
    RoveRawlogWriterOptions w;
    w.gzip = false;
    RoveRawlogWriter out(in, w);
    auto write_frame = [&](const Observation& o) {
      SensoryFrame sf;
      sf.add(o.clone());
      out.write(sf);
    };
    write_frame(scan);
    ActionCollection ac;
    auto move = std::make_shared<RobotMovement2D>(Pose2(0.5, 0.1, 0.2), MotionModelOptions{});
    move->timestamp = Timestamp::from_ns(1'700'000'000'900'000'000);
    ac.add(move);
    out.write(ac);
    write_frame(rgbd);
    ActionCollection ac2;
    auto move2 = std::make_shared<RobotMovement2D>(*move);
    move2->timestamp = Timestamp::from_ns(1'700'000'001'900'000'000);
    ac2.add(move2);
    out.write(ac2);
    write_frame(cloud);
    out.close();
  }
  for (auto c : {BagCompression::None, BagCompression::Bz2, BagCompression::Lz4}) {
    const std::string bag = dir / "out.bag";
    BagWriteOptions wo;
    wo.compression = c;
    const BagWriteResult wr = write_bag(in, bag, wo);
    EXPECT_EQ(wr.entries_in, 5u);
    EXPECT_EQ(wr.messages_by_topic.at("/LASER"), 1u);
    EXPECT_EQ(wr.messages_by_topic.at("/odom"), 3u);  // identity + two increments
    EXPECT_EQ(wr.messages_by_topic.at("/kinect/depth/image_raw"), 1u);
    EXPECT_EQ(wr.messages_by_topic.at("/lidar/points"), 1u);
    // python3-rosbag and rosbag::View read what rove wrote.
    EXPECT_EQ(read_with_rosbag_view(bag).size(), 13u);

    BagReader r(bag);
    const auto entries = read_all(r);
    ASSERT_EQ(entries.size(), 5u) << ::testing::PrintToString(r.skipped());
    const auto& sf0 = std::get<std::shared_ptr<const SensoryFrame>>(entries[0]);
    auto s = sf0->find<RangeScan2D>();
    ASSERT_TRUE(s);
    EXPECT_EQ(s->timestamp, scan.timestamp);
    EXPECT_EQ(s->sensor_label, "LASER");
    EXPECT_EQ(s->aperture, double(static_cast<float>(scan.aperture / 2)) * 2.0);  // float32 in a bag
    EXPECT_EQ(s->right_to_left, false);
    EXPECT_EQ(s->max_range, 20.0f);
    EXPECT_EQ(s->valid, scan.valid);
    EXPECT_EQ(s->intensity, scan.intensity);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (i == 4 || i == 5) {
        EXPECT_TRUE(std::isinf(s->ranges[i]));  // written as "no return"
      } else {
        EXPECT_EQ(s->ranges[i], scan.ranges[i]);
      }
    }
    EXPECT_LT((s->T_robot_sensor.matrix() - scan.T_robot_sensor.matrix()).norm(), 1e-15);
    for (int k : {1, 3}) {
      auto m = std::get<std::shared_ptr<const ActionCollection>>(entries[k])->find<RobotMovement2D>();
      ASSERT_TRUE(m);
      EXPECT_EQ(m->timestamp, Timestamp::from_ns(k == 1 ? 1'700'000'000'900'000'000 : 1'700'000'001'900'000'000));
      EXPECT_NEAR(m->odometry_increment.x(), 0.5, 1e-12);
      EXPECT_NEAR(m->odometry_increment.y(), 0.1, 1e-12);
      EXPECT_NEAR(m->odometry_increment.phi(), 0.2, 1e-12);
    }
    auto d = std::get<std::shared_ptr<const SensoryFrame>>(entries[2])->find<RangeImage3D>();
    ASSERT_TRUE(d);
    EXPECT_EQ(d->sensor_label, "kinect");
    EXPECT_EQ(d->depth, rgbd.depth);
    EXPECT_EQ(d->depth_camera, rgbd.depth_camera);
    EXPECT_EQ(d->intensity, rgbd.intensity);
    EXPECT_EQ(d->intensity_camera, rgbd.intensity_camera);
    EXPECT_LT((d->T_robot_sensor.matrix() - rgbd.T_robot_sensor.matrix()).norm(), 1e-12);
    EXPECT_LT((d->T_sensor_intensity.matrix() - rgbd.T_sensor_intensity.matrix()).norm(), 1e-12);
    auto p = std::get<std::shared_ptr<const SensoryFrame>>(entries[4])->find<RangeImage3D>();
    ASSERT_TRUE(p);
    EXPECT_EQ(p->points, cloud.points);
    EXPECT_EQ(p->sensor_label, "lidar");
  }
}

TEST(BagRoundTrip, AnyRawlogReaderReadsBagsOnceRegistered) {
  TempDir dir;
  const std::string path = dir / "every.bag";
  write_every_type(path, ChunkCompression::Lz4);
  EXPECT_EQ(detect_rawlog_format(path), RawlogFormat::RosBag);
  register_rawlog_source(RawlogFormat::RosBag, {});
  EXPECT_FALSE(rawlog_format_available(RawlogFormat::RosBag));
  EXPECT_THROW(AnyRawlogReader r(path), ParseError);
  register_bag_reader();
  EXPECT_TRUE(rawlog_format_available(RawlogFormat::RosBag));
  AnyRawlogReader reader(path);
  EXPECT_EQ(reader.format(), RawlogFormat::RosBag);
  EXPECT_EQ(reader.declared_layout(), RawlogLayout::ActionsSensoryFrames);
  std::size_t n = 0;
  while (reader.next()) ++n;
  EXPECT_EQ(n, 7u);
  EXPECT_TRUE(has_line(reader.skipped(), "/chatter"));
  EXPECT_EQ(reader.position(), fs::file_size(path));
}

// MRPT's Telecom Faculty loop (bundled in data/mrpt) through a bag: the same
// entries, observation by observation.
TEST(BagTelecom, RawlogThroughABagMatchesTheRawlog) {
  TempDir dir;
  const std::string rawlog =
      std::string(ROVE_SOURCE_DIR) + "/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";
  const std::string bag = dir / "telecom.bag";
  const BagWriteResult w = write_bag(rawlog, bag);
  EXPECT_EQ(w.input_format, RawlogFormat::Mrpt);
  EXPECT_EQ(w.entries_in, 449u);
  EXPECT_EQ(w.messages_by_topic.at("/scan"), 225u);
  EXPECT_EQ(w.messages_by_topic.at("/odom"), 225u);  // the identity + 224 increments
  EXPECT_EQ(w.messages_by_topic.at("/tf_static"), 1u);
  EXPECT_TRUE(w.dropped.empty());

  const AnyRawlog want = load_any_rawlog(rawlog);
  BagReader reader(bag);
  const auto got = read_all(reader);
  EXPECT_TRUE(reader.skipped().empty()) << ::testing::PrintToString(reader.skipped());
  ASSERT_EQ(got.size(), want.entries.size());
  std::size_t scans = 0, moves = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].index(), want.entries[i].index()) << "entry " << i;
    if (const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&want.entries[i])) {
      auto a = (*sf)->find<RangeScan2D>();
      auto b = std::get<std::shared_ptr<const SensoryFrame>>(got[i])->find<RangeScan2D>();
      ASSERT_TRUE(a && b);
      EXPECT_EQ(b->timestamp, a->timestamp) << "entry " << i;
      EXPECT_EQ(b->sensor_label, "scan");  // unlabelled scans go to /scan
      EXPECT_EQ(b->aperture, a->aperture);
      EXPECT_EQ(b->right_to_left, a->right_to_left);
      EXPECT_EQ(b->max_range, a->max_range);
      EXPECT_EQ(b->valid, a->valid) << "entry " << i;
      EXPECT_EQ(b->intensity, a->intensity);
      for (std::size_t k = 0; k < a->size(); ++k) {
        if (a->valid[k]) {
          EXPECT_EQ(b->ranges[k], a->ranges[k]) << "entry " << i << " ray " << k;
        }
      }
      EXPECT_LT((b->T_robot_sensor.matrix() - a->T_robot_sensor.matrix()).norm(), 1e-15);
      EXPECT_EQ(b->points_2d(), a->points_2d());
      ++scans;
    } else {
      auto a = std::get<std::shared_ptr<const ActionCollection>>(want.entries[i])->find<RobotMovement2D>();
      auto b = std::get<std::shared_ptr<const ActionCollection>>(got[i])->find<RobotMovement2D>();
      ASSERT_TRUE(a && b);
      EXPECT_EQ(b->timestamp, a->timestamp) << "entry " << i;
      // Integrated then differenced: equal to rounding.
      EXPECT_NEAR(b->odometry_increment.x(), a->odometry_increment.x(), 1e-12) << "entry " << i;
      EXPECT_NEAR(b->odometry_increment.y(), a->odometry_increment.y(), 1e-12) << "entry " << i;
      EXPECT_NEAR(b->odometry_increment.phi(), a->odometry_increment.phi(), 1e-12) << "entry " << i;
      ++moves;
    }
  }
  EXPECT_EQ(scans, 225u);
  EXPECT_EQ(moves, 224u);
}

// A message larger than a chunk's usual 768 KiB: the chunk's output buffer
// grows past its first MiB (bz2) or is allocated whole (lz4).
TEST(BagReader, LargeImagesInEveryCompression) {
  TempDir dir;
  for (auto c : {ChunkCompression::None, ChunkCompression::Bz2, ChunkCompression::Lz4}) {
    const std::string path = dir / "big.bag";
    ImageMsg im;
    im.header = header(100, 0, "cam_optical");
    im.width = 1200;
    im.height = 1000;
    im.encoding = "rgb8";
    im.step = 3600;
    im.data.resize(3'600'000);
    std::uint32_t lcg = 7;
    for (auto& b : im.data) {
      lcg = lcg * 1664525u + 1013904223u;
      b = static_cast<std::uint8_t>(lcg >> 24);
    }
    {
      RosbagWriter bag(path, c);
      bag.write("/cam/image_raw", 100, 0, im);
      bag.close();
    }
    BagReadOptions o;
    o.layout = RawlogLayout::Observations;
    BagReader r(path, o);
    const auto entries = read_all(r);
    ASSERT_EQ(entries.size(), 1u) << ::testing::PrintToString(r.skipped());
    auto img = bare<ImageObservation>(entries[0]);
    ASSERT_TRUE(img);
    EXPECT_EQ(img->image.data, im.data);
    EXPECT_EQ(img->sensor_label, "cam");
  }
}
