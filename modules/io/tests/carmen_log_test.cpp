#include "rove/io/carmen_log.h"

#include <bzlib.h>

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

std::vector<CarmenRecord> read_all(CarmenLogReader& reader) {
  std::vector<CarmenRecord> out;
  CarmenRecord r;
  while (reader.next(r)) out.push_back(std::move(r));
  return out;
}

std::string bzip2(const std::string& text) {
  std::string out(text.size() + text.size() / 100 + 1024, '\0');
  unsigned int len = static_cast<unsigned int>(out.size());
  const int rc = BZ2_bzBuffToBuffCompress(out.data(), &len, const_cast<char*>(text.data()),
                                          static_cast<unsigned int>(text.size()), 9, 0, 0);
  EXPECT_EQ(rc, BZ_OK);
  out.resize(len);
  return out;
}

// One line of every kind the reader knows, plus lines it skips.
const std::string kLog =
    "# CARMEN Logfile\n"
    "PARAM robot_front_laser_max 81.9 nohost 0\n"
    "SYNC tag1 1.0 nohost 0.5\n"
    "\n"
    "FLASER 3 1.5 2.5 90.0 1.0 2.0 0.5 0.9 2.0 0.5 100.25 hostA 0.125\n"
    "RLASER 2 0.5 0.75 1.0 2.0 -3.0 1.0 2.0 -3.0 101.5 hostB 1.5\r\n"
    "ODOM 1.0 -2.0 0.25 0.3 -0.1 0.05 102.0 hostA 2.0\n"
    "NMEA-GGA 1 2 3 hostC 2.1\n"
    "ROBOTLASER1 0 -1.5 3.0 1.5 50.0 0.01 0 3 1.0 2.0 3.0 2 10 20 "
    "1.1 2.0 0.0 1.0 2.0 0.0 0.4 0.2 0.5 0.3 0.1 103.0 hostA 3.0\n"
    "TRUEPOS 5.0 6.0 -0.5 4.0 5.0 -0.25 104.0 sim 4.0\n"
    "\t  \n"
    "ODOM 2 3 0.1 0 0 0 105 hostA 5.0";  // no final newline

void check_log(CarmenLogReader& reader) {
  const std::vector<CarmenRecord> recs = read_all(reader);
  ASSERT_EQ(recs.size(), 6u);

  const CarmenRecord& fl = recs[0];
  EXPECT_EQ(fl.type, CarmenMessage::Flaser);
  EXPECT_EQ(fl.line, 5u);
  ASSERT_NE(fl.scan, nullptr);
  EXPECT_EQ(fl.odometry, nullptr);
  EXPECT_EQ(fl.scan->ranges, (std::vector<float>{1.5f, 2.5f, 90.0f}));
  EXPECT_EQ(fl.scan->valid, (std::vector<bool>{true, true, false}));  // 90 >= 81 m
  EXPECT_DOUBLE_EQ(fl.scan->aperture, kPi);
  EXPECT_TRUE(fl.scan->right_to_left);
  EXPECT_FLOAT_EQ(fl.scan->max_range, 81.9f);  // the PARAM robot_front_laser_max line
  EXPECT_EQ(fl.scan->sensor_label, "LASER");
  EXPECT_DOUBLE_EQ(fl.laser_pose.x(), 1.0);
  EXPECT_DOUBLE_EQ(fl.laser_pose.y(), 2.0);
  EXPECT_DOUBLE_EQ(fl.laser_pose.phi(), 0.5);
  EXPECT_DOUBLE_EQ(fl.robot_pose.x(), 0.9);
  // laser ⊖ robot: the 0.1 m world-x offset seen from the robot, which is
  // turned by 0.5 rad.
  const Pose2 sensor(fl.scan->T_robot_sensor);
  EXPECT_NEAR(sensor.x(), 0.1 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(sensor.y(), -0.1 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(sensor.phi(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(fl.ipc_timestamp, 100.25);
  EXPECT_EQ(fl.ipc_hostname, "hostA");
  EXPECT_DOUBLE_EQ(fl.logger_timestamp, 0.125);
  EXPECT_EQ(fl.timestamp.ns, 125000000);
  EXPECT_EQ(fl.scan->timestamp, fl.timestamp);

  const CarmenRecord& rl = recs[1];
  EXPECT_EQ(rl.type, CarmenMessage::Rlaser);
  EXPECT_EQ(rl.line, 6u);
  ASSERT_NE(rl.scan, nullptr);
  EXPECT_EQ(rl.scan->sensor_label, "LASER_REAR");
  EXPECT_EQ(rl.scan->ranges, (std::vector<float>{0.5f, 0.75f}));
  EXPECT_EQ(rl.ipc_hostname, "hostB");  // the '\r' of a CRLF line is dropped
  EXPECT_EQ(rl.timestamp.ns, 1500000000);

  const CarmenRecord& od = recs[2];
  EXPECT_EQ(od.type, CarmenMessage::Odom);
  EXPECT_EQ(od.line, 7u);
  ASSERT_NE(od.odometry, nullptr);
  EXPECT_EQ(od.scan, nullptr);
  EXPECT_DOUBLE_EQ(od.odometry->odometry.x(), 1.0);
  EXPECT_DOUBLE_EQ(od.odometry->odometry.y(), -2.0);
  EXPECT_DOUBLE_EQ(od.odometry->odometry.phi(), 0.25);
  ASSERT_TRUE(od.odometry->velocity.has_value());
  EXPECT_DOUBLE_EQ(od.odometry->velocity->vx, 0.3);
  EXPECT_DOUBLE_EQ(od.odometry->velocity->omega, -0.1);
  EXPECT_DOUBLE_EQ(od.accel, 0.05);
  EXPECT_EQ(od.odometry->sensor_label, "ODOMETRY");
  EXPECT_EQ(od.odometry->timestamp.ns, 2000000000);

  const CarmenRecord& rb = recs[3];
  EXPECT_EQ(rb.type, CarmenMessage::RobotLaser1);
  EXPECT_EQ(rb.line, 9u);
  ASSERT_NE(rb.scan, nullptr);
  EXPECT_EQ(rb.scan->ranges, (std::vector<float>{1.0f, 2.0f, 3.0f}));
  EXPECT_DOUBLE_EQ(rb.scan->aperture, 3.0);
  EXPECT_FLOAT_EQ(rb.scan->max_range, 50.0f);
  EXPECT_EQ(rb.remissions, (std::vector<float>{10.0f, 20.0f}));
  EXPECT_DOUBLE_EQ(rb.start_angle, -1.5);
  EXPECT_DOUBLE_EQ(rb.angular_resolution, 1.5);
  EXPECT_DOUBLE_EQ(rb.tv, 0.4);
  EXPECT_DOUBLE_EQ(rb.rv, 0.2);
  // Laser 0.1 m ahead of the robot; start_angle + fov/2 = 0, so ray 0 of
  // the scan points at -1.5 rad from the laser's x axis.
  const Pose2 rb_sensor(rb.scan->T_robot_sensor);
  EXPECT_NEAR(rb_sensor.x(), 0.1, 1e-12);
  EXPECT_NEAR(rb_sensor.y(), 0.0, 1e-12);
  EXPECT_NEAR(rb_sensor.phi(), 0.0, 1e-12);
  EXPECT_NEAR(rb.scan->ray_angle(0), -1.5, 1e-12);
  EXPECT_NEAR(rb.scan->ray_angle(2), 1.5, 1e-12);
  EXPECT_EQ(rb.timestamp.ns, 3000000000);

  const CarmenRecord& tp = recs[4];
  EXPECT_EQ(tp.type, CarmenMessage::TruePos);
  EXPECT_EQ(tp.line, 10u);
  EXPECT_EQ(tp.scan, nullptr);
  EXPECT_EQ(tp.odometry, nullptr);
  EXPECT_DOUBLE_EQ(tp.true_pose.x(), 5.0);
  EXPECT_DOUBLE_EQ(tp.true_pose.y(), 6.0);
  EXPECT_DOUBLE_EQ(tp.true_pose.phi(), -0.5);
  EXPECT_DOUBLE_EQ(tp.robot_pose.x(), 4.0);
  EXPECT_DOUBLE_EQ(tp.robot_pose.phi(), -0.25);
  EXPECT_EQ(tp.ipc_hostname, "sim");
  EXPECT_EQ(tp.timestamp.ns, 4000000000);

  EXPECT_EQ(recs[5].type, CarmenMessage::Odom);
  EXPECT_EQ(recs[5].line, 12u);

  const CarmenLogStats& s = reader.stats();
  EXPECT_EQ(s.lines, 12u);
  EXPECT_EQ(s.flaser, 1u);
  EXPECT_EQ(s.rlaser, 1u);
  EXPECT_EQ(s.odom, 2u);
  EXPECT_EQ(s.robotlaser1, 1u);
  EXPECT_EQ(s.truepos, 1u);
  EXPECT_EQ(s.comments, 1u);
  EXPECT_EQ(s.blank, 2u);
  EXPECT_EQ(s.param, 1u);
  EXPECT_EQ(s.sync, 1u);
  EXPECT_EQ(s.other, 1u);
  EXPECT_EQ(s.malformed, 0u);
}

TEST(CarmenLog, ReadsEveryMessageTypePlain) {
  CarmenLogReader reader = CarmenLogReader::from_memory(kLog);
  check_log(reader);
}

TEST(CarmenLog, ReadsEveryMessageTypeBzip2) {
  CarmenLogReader reader = CarmenLogReader::from_memory(bzip2(kLog));
  check_log(reader);
}

TEST(CarmenLog, ReadsConcatenatedBzip2Streams) {
  const std::size_t cut = kLog.find("ODOM 1.0");
  CarmenLogReader reader =
      CarmenLogReader::from_memory(bzip2(kLog.substr(0, cut)) + bzip2(kLog.substr(cut)));
  check_log(reader);
}

TEST(CarmenLog, LongLogStreamsAcrossBufferBoundaries) {
  std::string text;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    text += "ODOM " + std::to_string(i) + " 0 0 0 0 0 1 h " + std::to_string(i) + "\n";
  }
  for (const std::string& bytes : {text, bzip2(text)}) {
    CarmenLogReader reader = CarmenLogReader::from_memory(bytes);
    CarmenRecord r;
    int i = 0;
    while (reader.next(r)) {
      ASSERT_DOUBLE_EQ(r.robot_pose.x(), i);
      ++i;
    }
    EXPECT_EQ(i, n);
    EXPECT_EQ(reader.stats().odom, static_cast<std::size_t>(n));
  }
}

TEST(CarmenLog, StartTimeShiftsTimestamps) {
  CarmenLogOptions opts;
  opts.start_time = Timestamp::from_ns(1000);
  CarmenLogReader reader =
      CarmenLogReader::from_memory("ODOM 0 0 0 0 0 0 1 h 2.5\n", "<t>", opts);
  CarmenRecord r;
  ASSERT_TRUE(reader.next(r));
  EXPECT_EQ(r.timestamp.ns, 2500001000);
}

TEST(CarmenLog, EmptyInputHasNoRecords) {
  CarmenLogReader reader = CarmenLogReader::from_memory("");
  CarmenRecord r;
  EXPECT_FALSE(reader.next(r));
  EXPECT_EQ(reader.stats().lines, 0u);
}

TEST(CarmenLog, MissingFileIsIoError) {
  EXPECT_THROW(CarmenLogReader::open("no/such/carmen.log"), IoError);
}

struct BadLine {
  std::string line;
  std::string field;
};

class CarmenMalformed : public ::testing::TestWithParam<BadLine> {};

TEST_P(CarmenMalformed, ThrowsWithLineAndFieldOrSkips) {
  const BadLine& bad = GetParam();
  const std::string text = "# header\nODOM 0 0 0 0 0 0 1 h 1\n" + bad.line + "\nODOM 1 0 0 0 0 0 1 h 2\n";
  {
    CarmenLogReader reader = CarmenLogReader::from_memory(text, "bad.clf");
    CarmenRecord r;
    ASSERT_TRUE(reader.next(r));
    try {
      reader.next(r);
      FAIL() << "no error for: " << bad.line;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, "bad.clf");
      ASSERT_TRUE(e.location().line.has_value());
      EXPECT_EQ(*e.location().line, 3u);
      EXPECT_EQ(e.location().field, bad.field) << e.what();
    }
  }
  {
    CarmenLogOptions opts;
    opts.skip_malformed = true;
    CarmenLogReader reader = CarmenLogReader::from_memory(text, "bad.clf", opts);
    CarmenRecord r;
    std::size_t n = 0;
    while (reader.next(r)) ++n;
    EXPECT_EQ(n, 2u);
    EXPECT_EQ(reader.stats().malformed, 1u);
    EXPECT_EQ(reader.stats().odom, 2u);
    EXPECT_EQ(reader.stats().lines, 4u);
  }
}

INSTANTIATE_TEST_SUITE_P(
    EveryError, CarmenMalformed,
    ::testing::Values(
        // too few fields
        BadLine{"FLASER", "FLASER.num_readings"},
        BadLine{"FLASER 2 1.0 2.0 0 0 0 0 0 0 1 h", "FLASER.num_readings"},
        BadLine{"ODOM 1 2 3", "ODOM.tv"},
        BadLine{"TRUEPOS 1 2 3 4 5", "TRUEPOS.odom_theta"},
        BadLine{"RLASER 1 1.0 0 0", "RLASER.num_readings"},
        // wrong count
        BadLine{"FLASER 5 1.0 2.0 0 0 0 0 0 0 1 h 2", "FLASER.num_readings"},
        BadLine{"FLASER 1 1.0 2.0 0 0 0 0 0 0 1 h 2", "FLASER.num_readings"},
        BadLine{"FLASER 2.5 1.0 2.0 0 0 0 0 0 0 1 h 2", "FLASER.num_readings"},
        BadLine{"FLASER -1 0 0 0 0 0 0 1 h 2", "FLASER.num_readings"},
        BadLine{"FLASER 99999999999999999999 0 0 0 0 0 0 1 h 2", "FLASER.num_readings"},
        BadLine{"ODOM 0 0 0 0 0 0 1 h 1 extra", "ODOM.logger_timestamp"},
        BadLine{"ROBOTLASER1 0 -1.5 3.0 1.5 50 0.01 0 2 1 2 5 1 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "ROBOTLASER1.num_remissions"},
        // not a number, NaN, infinity, overflow
        BadLine{"FLASER 2 1.0 abc 0 0 0 0 0 0 1 h 2", "FLASER.range[1]"},
        BadLine{"FLASER 2 1.0 nan 0 0 0 0 0 0 1 h 2", "FLASER.range[1]"},
        BadLine{"FLASER 2 1.0 2.0 0 0 NaN 0 0 0 1 h 2", "FLASER.theta"},
        BadLine{"FLASER 2 1.0 1e39 0 0 0 0 0 0 1 h 2", "FLASER.range[1]"},
        BadLine{"ODOM 0 0 0 inf 0 0 1 h 1", "ODOM.tv"},
        BadLine{"ODOM 0 0 0 0 0 0 1 h 1e999", "ODOM.logger_timestamp"},
        BadLine{"ODOM 0 0 0 0 0 0 1 h 1e15", "ODOM.logger_timestamp"},
        BadLine{"ODOM 0 0 0x1 0 0 0 1 h 1", "ODOM.theta"},
        BadLine{"ODOM 0 0 +-1 0 0 0 1 h 1", "ODOM.theta"},
        BadLine{"TRUEPOS 1 2 3 4 5 6 seven h 1", "TRUEPOS.ipc_timestamp"},
        BadLine{"ROBOTLASER1 0 -1.5 0 1.5 50 0.01 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "ROBOTLASER1.field_of_view"},
        BadLine{"ROBOTLASER1 0 -1.5 3 1.5 -5 0.01 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "ROBOTLASER1.maximum_range"},
        BadLine{"ROBOTLASER1 0 -1.5 3 1.5 50 0.01 0 1 1 1 x 0 0 0 0 0 0 0 0 0 0 0 1 h 1",
                "ROBOTLASER1.remission[0]"}));

TEST(CarmenLog, OverlongLineIsMalformed) {
  CarmenLogOptions opts;
  opts.max_line_bytes = 16;
  const std::string text = "ODOM 0 0 0 0 0 0 1 h 1 0 0 0 0 0 0 0 0 0 0 0 0 0\nODOM 1 0 0 0 0 0 1 h 2\n";
  {
    CarmenLogReader reader = CarmenLogReader::from_memory(text, "long.clf", opts);
    CarmenRecord r;
    try {
      reader.next(r);
      FAIL() << "overlong line accepted";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().line, std::optional<std::size_t>(1));
    }
  }
  opts.max_line_bytes = 30;
  opts.skip_malformed = true;
  CarmenLogReader reader = CarmenLogReader::from_memory(text, "long.clf", opts);
  CarmenRecord r;
  ASSERT_TRUE(reader.next(r));
  EXPECT_EQ(r.line, 2u);
  EXPECT_DOUBLE_EQ(r.robot_pose.x(), 1.0);
  EXPECT_EQ(reader.stats().malformed, 1u);
}

TEST(CarmenLog, CorruptBzip2IsParseErrorWithOffset) {
  std::string bytes = bzip2(kLog);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x55);
  CarmenLogReader reader = CarmenLogReader::from_memory(bytes, "corrupt.bz2");
  CarmenRecord r;
  try {
    while (reader.next(r)) {
    }
    FAIL() << "corruption not detected";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().field, "bzip2");
    EXPECT_TRUE(e.location().offset.has_value());
  }
}

TEST(CarmenLog, TruncatedBzip2IsParseError) {
  const std::string bytes = bzip2(kLog);
  CarmenLogReader reader = CarmenLogReader::from_memory(bytes.substr(0, bytes.size() - 10));
  CarmenRecord r;
  EXPECT_THROW(
      {
        while (reader.next(r)) {
        }
      },
      ParseError);
}

TEST(CarmenLog, GarbageAfterBzip2StreamIsParseError) {
  CarmenLogReader reader = CarmenLogReader::from_memory(bzip2(kLog) + "junk");
  CarmenRecord r;
  EXPECT_THROW(
      {
        while (reader.next(r)) {
        }
      },
      ParseError);
}

TEST(CarmenLog, MessageNames) {
  EXPECT_EQ(to_string(CarmenMessage::Flaser), "FLASER");
  EXPECT_EQ(to_string(CarmenMessage::Rlaser), "RLASER");
  EXPECT_EQ(to_string(CarmenMessage::Odom), "ODOM");
  EXPECT_EQ(to_string(CarmenMessage::RobotLaser1), "ROBOTLASER1");
  EXPECT_EQ(to_string(CarmenMessage::TruePos), "TRUEPOS");
}

}  // namespace
}  // namespace rove
