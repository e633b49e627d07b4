// RawlogReader on MRPT's bundled rawlog, compared value by value with what
// MRPT itself reads (tests/data/mrpt_sena_reference.txt, from libmrpt) and
// exports (tests/data/mrpt_sena_export_2d_scans.txt, from rawlog-edit).

#include "rove/io/rawlog_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "rove/core/error.h"
#include "rove/obs/beacon_ranges.h"
#include "rove/obs/bearing_range.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/serialization/input_file.h"
#include "rove/serialization/memory_stream.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kSena =
    ROVE_SOURCE_DIR "/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";
const std::string kTestData = ROVE_SOURCE_DIR "/modules/io/tests/data/";

// The lines of a text file without '#' comment lines; fails the test if the
// file cannot be read.
std::vector<std::string> data_lines(const std::string& path, char comment) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot read " << path;
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != comment) out.push_back(line);
  }
  return out;
}

std::vector<std::byte> decompressed(const std::string& path) {
  auto in = open_input_file(path);
  std::vector<std::byte> out;
  std::byte buf[65536];
  for (std::size_t n; (n = in->read_some(buf)) > 0;) out.insert(out.end(), buf, buf + n);
  return out;
}

const RangeScan2D& scan_of(const RawlogEntry& e) {
  const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&e);
  EXPECT_NE(sf, nullptr);
  const auto scan = (*sf)->find<RangeScan2D>();
  EXPECT_NE(scan, nullptr);
  return *scan;
}

const RobotMovement2D& movement_of(const RawlogEntry& e) {
  const auto* ac = std::get_if<std::shared_ptr<const ActionCollection>>(&e);
  EXPECT_NE(ac, nullptr);
  const auto mv = (*ac)->find<RobotMovement2D>();
  EXPECT_NE(mv, nullptr);
  return *mv;
}

TEST(RawlogReader, SenaCountsAsRawlogEditInfo) {
  // rawlog-edit --info: 449 objects, actions/sensory-frame format, 224
  // observations labeled "" counted after the first action; the file holds
  // 225 frames (the first before any action) and 224 action collections.
  const Rawlog log = load_rawlog(kSena);
  ASSERT_EQ(log.entries.size(), 449u);
  EXPECT_EQ(log.layout, RawlogLayout::ActionsSensoryFrames);
  std::size_t frames = 0, actions = 0;
  for (std::size_t i = 0; i < log.entries.size(); ++i) {
    const auto& e = log.entries[i];
    if (i % 2 == 0) {
      ASSERT_TRUE(std::holds_alternative<std::shared_ptr<const SensoryFrame>>(e)) << i;
      const auto& sf = *std::get<std::shared_ptr<const SensoryFrame>>(e);
      ASSERT_EQ(sf.size(), 1u);
      EXPECT_EQ(scan_of(e).size(), 361u);
      EXPECT_EQ(scan_of(e).sensor_label, "");
      ++frames;
    } else {
      ASSERT_TRUE(std::holds_alternative<std::shared_ptr<const ActionCollection>>(e)) << i;
      EXPECT_EQ(std::get<std::shared_ptr<const ActionCollection>>(e)->size(), 1u);
      movement_of(e);
      ++actions;
    }
  }
  EXPECT_EQ(frames, 225u);
  EXPECT_EQ(actions, 224u);
  // rawlog-edit --info's time span (it starts at the second frame).
  EXPECT_NEAR(scan_of(log.entries[2]).timestamp.to_seconds(), 1137834225.973760, 1e-6);
  EXPECT_NEAR(scan_of(log.entries[448]).timestamp.to_seconds(), 1137834284.788331, 1e-6);
}

TEST(RawlogReader, SenaStreamsToTheEnd) {
  RawlogReader reader(kSena);
  std::size_t n = 0;
  while (reader.next()) ++n;
  EXPECT_EQ(n, 449u);
  EXPECT_EQ(reader.entries_read(), 449u);
  EXPECT_EQ(reader.offset(), 498881u);  // rawlog-edit: "Uncompressed file size 498.88 KB"
  EXPECT_FALSE(reader.next().has_value());
}

// Compares `log` with a reference written by mrpt_reference_generator.cc.
void expect_equal_to_libmrpt(const Rawlog& log, const std::string& reference,
                             std::size_t reference_lines) {
  const auto lines = data_lines(kTestData + reference, '#');
  ASSERT_EQ(lines.size(), reference_lines);
  for (const std::string& line : lines) {
    std::istringstream in(line);
    std::string kind;
    std::size_t index = 0;
    std::uint64_t ticks = 0;
    in >> kind >> index >> ticks;
    ASSERT_LT(index, log.entries.size());
    SCOPED_TRACE(line.substr(0, 40));
    if (kind == "S") {
      const RangeScan2D& s = scan_of(log.entries[index]);
      std::size_t n = 0;
      int rtl = 0;
      float aperture = 0, max_range = 0, std_error = 0, beam = 0;
      double pose[6];
      in >> n >> aperture >> rtl >> max_range >> std_error >> beam;
      for (double& v : pose) in >> v;
      EXPECT_EQ(s.timestamp.to_mrpt(), ticks);
      ASSERT_EQ(s.size(), n);
      EXPECT_EQ(static_cast<float>(s.aperture), aperture);
      EXPECT_EQ(s.right_to_left, rtl != 0);
      EXPECT_EQ(s.max_range, max_range);
      EXPECT_EQ(s.std_error, std_error);
      EXPECT_EQ(s.beam_aperture, beam);
      EXPECT_NEAR(s.T_robot_sensor.x(), pose[0], 1e-12);
      EXPECT_NEAR(s.T_robot_sensor.y(), pose[1], 1e-12);
      EXPECT_NEAR(s.T_robot_sensor.z(), pose[2], 1e-12);
      EXPECT_NEAR(s.T_robot_sensor.yaw(), pose[3], 1e-12);
      EXPECT_NEAR(s.T_robot_sensor.pitch(), pose[4], 1e-12);
      EXPECT_NEAR(s.T_robot_sensor.roll(), pose[5], 1e-12);
      for (std::size_t i = 0; i < n; ++i) {
        float r = 0;
        in >> r;
        EXPECT_EQ(s.ranges[i], r) << "ray " << i;
      }
      for (std::size_t i = 0; i < n; ++i) {
        int v = 0;
        in >> v;
        EXPECT_EQ(s.valid[i], v != 0) << "ray " << i;
      }
    } else if (kind == "B" || kind == "R") {
      const auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&log.entries[index]);
      ASSERT_NE(sf, nullptr);
      std::string label;
      std::size_t n = 0;
      float min_d = 0, max_d = 0;
      in >> label >> n >> min_d >> max_d;
      ASSERT_EQ(label.substr(0, 2), "L=");
      if (kind == "B") {
        const auto b = (*sf)->find<BearingRange>();
        ASSERT_NE(b, nullptr);
        float fov_yaw = 0, fov_pitch = 0;
        double xyz[3];
        in >> fov_yaw >> fov_pitch >> xyz[0] >> xyz[1] >> xyz[2];
        EXPECT_EQ(b->timestamp.to_mrpt(), ticks);
        EXPECT_EQ(b->sensor_label, label.substr(2));
        EXPECT_EQ(b->min_sensor_distance, min_d);
        EXPECT_EQ(b->max_sensor_distance, max_d);
        EXPECT_EQ(b->field_of_view_yaw, fov_yaw);
        EXPECT_EQ(b->field_of_view_pitch, fov_pitch);
        EXPECT_NEAR(b->T_robot_sensor.x(), xyz[0], 1e-12);
        EXPECT_NEAR(b->T_robot_sensor.y(), xyz[1], 1e-12);
        EXPECT_NEAR(b->T_robot_sensor.z(), xyz[2], 1e-12);
        ASSERT_EQ(b->measurements.size(), n);
        for (const LandmarkMeasurement& m : b->measurements) {
          std::int32_t id = 0;
          float range = 0, yaw = 0, pitch = 0;
          in >> id >> range >> yaw >> pitch;
          EXPECT_EQ(m.landmark_id, id);
          EXPECT_EQ(m.range, range);
          EXPECT_EQ(m.yaw, yaw);
          EXPECT_EQ(m.pitch, pitch);
        }
      } else {
        const auto r = (*sf)->find<BeaconRanges>();
        ASSERT_NE(r, nullptr);
        float std_error = 0;
        in >> std_error;
        EXPECT_EQ(r->timestamp.to_mrpt(), ticks);
        EXPECT_EQ(r->sensor_label, label.substr(2));
        EXPECT_EQ(r->min_sensor_distance, min_d);
        EXPECT_EQ(r->max_sensor_distance, max_d);
        EXPECT_EQ(r->std_error, std_error);
        ASSERT_EQ(r->readings.size(), n);
        for (const BeaconRange& b : r->readings) {
          std::int32_t id = 0;
          float range = 0;
          double xyz[3];
          in >> id >> range >> xyz[0] >> xyz[1] >> xyz[2];
          EXPECT_EQ(b.beacon_id, id);
          EXPECT_EQ(b.range, range);
          EXPECT_NEAR(b.position_on_robot.x(), xyz[0], 1e-12);
          EXPECT_NEAR(b.position_on_robot.y(), xyz[1], 1e-12);
          EXPECT_NEAR(b.position_on_robot.z(), xyz[2], 1e-12);
        }
      }
    } else {
      ASSERT_EQ(kind, "A");
      const RobotMovement2D& m = movement_of(log.entries[index]);
      double inc[3];
      for (double& v : inc) in >> v;
      EXPECT_EQ(m.timestamp.to_mrpt(), ticks);
      EXPECT_NEAR(m.odometry_increment.x(), inc[0], 1e-15);
      EXPECT_NEAR(m.odometry_increment.y(), inc[1], 1e-15);
      EXPECT_NEAR(m.odometry_increment.phi(), inc[2], 1e-15);
      EXPECT_FALSE(m.estimated_pose_change.has_value());
      // The Gaussian motion model rove derives from the stored parameters
      // equals the covariance MRPT derives (computeFromOdometry).
      const auto cov = m.gaussian().covariance();
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          double v = 0;
          in >> v;
          EXPECT_NEAR(cov(r, c), v, 1e-12 + 1e-9 * std::abs(v)) << r << "," << c;
        }
      }
    }
    EXPECT_FALSE(in.fail()) << "reference line too short";
  }
}

TEST(RawlogReader, SenaEqualsLibmrpt) {
  expect_equal_to_libmrpt(load_rawlog(kSena), "mrpt_sena_reference.txt", 20);
}

TEST(RawlogReader, LocalizationDemoEqualsLibmrpt) {
  // data/mrpt/localization_demo.rawlog (MRPT's, bundled with its license).
  const std::string path = test_data::bundled_file("mrpt/localization_demo.rawlog");
  ASSERT_TRUE(std::filesystem::exists(path)) << "dataset missing: " << path;
  const Rawlog log = load_rawlog(path);
  ASSERT_EQ(log.entries.size(), 74u);  // 37 action collections, 37 frames
  EXPECT_EQ(log.layout, RawlogLayout::ActionsSensoryFrames);
  expect_equal_to_libmrpt(log, "mrpt_localization_demo_rawlog_reference.txt", 8);
}

// Loads one of MRPT's rawlogs bundled in data/mrpt; fails the test if the
// file is missing.
Rawlog load_shared_rawlog(const std::string& name) {
  const std::string path = test_data::bundled_file("mrpt/" + name);
  EXPECT_TRUE(std::filesystem::exists(path)) << "dataset missing: " << path;
  return load_rawlog(path);
}

TEST(RawlogReader, KfSlamDemoEqualsLibmrpt) {
  const Rawlog log = load_shared_rawlog("kf-slam_demo.rawlog");
  ASSERT_EQ(log.entries.size(), 500u);  // 250 action collections, 250 frames
  EXPECT_EQ(log.layout, RawlogLayout::ActionsSensoryFrames);
  expect_equal_to_libmrpt(log, "mrpt_kf_slam_demo_rawlog_reference.txt", 8);
}

TEST(RawlogReader, RoSlamDemoEqualsLibmrpt) {
  const Rawlog log = load_shared_rawlog("RO-SLAM_demo.rawlog");
  ASSERT_EQ(log.entries.size(), 200u);  // 100 action collections, 100 frames
  EXPECT_EQ(log.layout, RawlogLayout::ActionsSensoryFrames);
  expect_equal_to_libmrpt(log, "mrpt_ro_slam_demo_rawlog_reference.txt", 8);
}

TEST(RawlogReader, SenaScansEqualRawlogEditExport) {
  const Rawlog log = load_rawlog(kSena);
  const auto rows = data_lines(kTestData + "mrpt_sena_export_2d_scans.txt", '#');
  ASSERT_EQ(rows.size(), 11u);  // MRPT's column header + 10 rows
  // rawlog-edit exports 224 scans: every frame but the one before the first
  // action. Rows 1..5 are frames 1..5, rows 6..10 frames 220..224.
  for (std::size_t r = 1; r < rows.size(); ++r) {
    const std::size_t frame = r <= 5 ? r : 219 + (r - 5);
    const RangeScan2D& s = scan_of(log.entries[2 * frame]);
    std::istringstream in(rows[r]);
    double t = 0;
    in >> t;
    EXPECT_NEAR(s.timestamp.to_seconds(), t, 1e-6) << "row " << r;
    for (std::size_t i = 0; i < s.size(); ++i) {
      double v = 0;
      in >> v;
      EXPECT_NEAR(s.ranges[i], v, 0.0005 + 1e-6) << "row " << r << " ray " << i;
    }
    for (std::size_t i = 0; i < s.size(); ++i) {
      int v = 0;
      in >> v;
      EXPECT_EQ(s.valid[i], v != 0) << "row " << r << " ray " << i;
    }
    ASSERT_FALSE(in.fail()) << "row " << r;
    std::string rest;
    EXPECT_FALSE(in >> rest) << "row " << r << " has more columns than rays";
  }
}

// Every cut of the first `prefix` bytes of `all` (a rawlog) is a
// ParseError, but at entry boundaries, where it leaves a shorter rawlog.
void expect_truncations_are_parse_errors(const std::vector<std::byte>& all, std::size_t prefix) {
  std::set<std::uint64_t> boundaries{0};
  {
    RawlogReader reader(std::make_unique<MemoryInStream>(std::span<const std::byte>(all)));
    while (reader.next() && reader.offset() <= prefix) boundaries.insert(reader.offset());
  }
  ASSERT_GE(boundaries.size(), 3u);
  for (std::size_t cut = 0; cut <= prefix; ++cut) {
    RawlogReader reader(std::make_unique<MemoryInStream>(
        std::span<const std::byte>(all.data(), cut), "truncated"));
    if (boundaries.count(cut) != 0) {
      EXPECT_NO_THROW(while (reader.next()) {}) << "cut " << cut;
    } else {
      EXPECT_THROW(while (reader.next()) {}, ParseError) << "cut " << cut;
    }
  }
}

TEST(RawlogReader, EveryTruncationOfTheFirstKilobytesIsAParseError) {
  const std::vector<std::byte> all = decompressed(kSena);
  ASSERT_EQ(all.size(), 498881u);
  expect_truncations_are_parse_errors(all, 6000);
}

// CObservationBeaconRanges: every cut of the first frames (beacon ranges,
// then an action) is a ParseError, and every single corrupted byte of them
// reads or fails with a ParseError, never anything else (ASan watches).
TEST(RawlogReader, RoSlamDemoTruncatedOrCorruptedBeaconRanges) {
  const std::vector<std::byte> all = decompressed(std::string(ROVE_SOURCE_DIR) + "/data/mrpt/RO-SLAM_demo.rawlog");
  constexpr std::size_t kPrefix = 2000;
  ASSERT_GT(all.size(), kPrefix);
  expect_truncations_are_parse_errors(all, kPrefix);
  std::size_t rejected = 0;
  for (std::size_t at = 0; at < kPrefix; ++at) {
    for (const std::byte flip : {std::byte{0x01}, std::byte{0x80}, std::byte{0xff}}) {
      std::vector<std::byte> bad(all.begin(), all.begin() + kPrefix);
      bad[at] ^= flip;
      RawlogReader reader(std::make_unique<MemoryInStream>(std::span<const std::byte>(bad), "corrupted"));
      try {
        while (reader.next()) {
        }
      } catch (const ParseError&) {
        ++rejected;
      }
    }
  }
  // The prefix ends inside an entry: every variant that reaches the end
  // fails there, so all of them are rejected with a ParseError.
  EXPECT_EQ(rejected, 3 * kPrefix);
}

TEST(RawlogReader, MissingFileIsAnIoError) {
  EXPECT_THROW({ RawlogReader reader(kTestData + "no_such.rawlog"); }, IoError);
}

}  // namespace
}  // namespace rove
