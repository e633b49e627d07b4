// The Radish CARMEN logs (intel.clf.bz2, fr079.clf.bz2) read with every
// FLASER and ODOM line accounted for. The expected counts come from an
// independent pass (libbz2's high-level BZ2_bzRead and a line-prefix count),
// not from the reader under test.

#include <bzlib.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rove/io/carmen_log.h"
#include "rove/test_data.h"

namespace rove {
namespace {

std::string dataset(const char* name) {
  return test_data::shared_dataset(std::string("radish/") + name);
}

struct IndependentCount {
  std::size_t flaser = 0, odom = 0, lines = 0;
  std::string first_flaser, first_odom;
};

IndependentCount count_independently(const std::string& path) {
  IndependentCount c;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    ADD_FAILURE() << "cannot open " << path;
    return c;
  }
  int err = BZ_OK;
  BZFILE* bz = BZ2_bzReadOpen(&err, f, 0, 0, nullptr, 0);
  EXPECT_EQ(err, BZ_OK);
  std::string line;
  std::vector<char> buf(1 << 16);
  auto finish_line = [&] {
    ++c.lines;
    if (line.rfind("FLASER ", 0) == 0) {
      if (c.flaser++ == 0) c.first_flaser = line;
    } else if (line.rfind("ODOM ", 0) == 0) {
      if (c.odom++ == 0) c.first_odom = line;
    }
    line.clear();
  };
  while (err == BZ_OK) {
    const int n = BZ2_bzRead(&err, bz, buf.data(), static_cast<int>(buf.size()));
    if (err != BZ_OK && err != BZ_STREAM_END) break;
    for (int i = 0; i < n; ++i) {
      if (buf[static_cast<std::size_t>(i)] == '\n') {
        finish_line();
      } else {
        line.push_back(buf[static_cast<std::size_t>(i)]);
      }
    }
  }
  EXPECT_EQ(err, BZ_STREAM_END) << path;
  if (!line.empty()) finish_line();
  BZ2_bzReadClose(&err, bz);
  std::fclose(f);
  return c;
}

std::vector<double> numbers_of(const std::string& line, std::string& host) {
  std::istringstream in(line);
  std::string word;
  in >> word;  // message name
  std::vector<double> values;
  while (in >> word) {
    try {
      values.push_back(std::stod(word));
    } catch (const std::exception&) {
      host = word;
      values.push_back(0.0);
    }
  }
  return values;
}

void check_dataset(const char* name, std::size_t readme_scans, std::size_t expected_rays) {
  const std::string path = dataset(name);
  ASSERT_TRUE(std::filesystem::exists(path))
      << "dataset missing: " << path;
  const IndependentCount expected = count_independently(path);
  EXPECT_EQ(expected.flaser, readme_scans);  // the dataset README's count

  CarmenLogReader reader = CarmenLogReader::open(path);
  CarmenRecord r;
  std::size_t scans = 0, odoms = 0;
  bool first_scan = true, first_odom = true;
  while (reader.next(r)) {
    if (r.type == CarmenMessage::Flaser) {
      ASSERT_NE(r.scan, nullptr);
      ASSERT_EQ(r.scan->size(), expected_rays) << "line " << r.line;
      ++scans;
      if (first_scan) {
        first_scan = false;
        std::string host;
        const std::vector<double> v = numbers_of(expected.first_flaser, host);
        ASSERT_EQ(v.size(), 1 + expected_rays + 9);
        EXPECT_EQ(static_cast<std::size_t>(v[0]), expected_rays);
        for (std::size_t i = 0; i < expected_rays; ++i) {
          ASSERT_EQ(r.scan->ranges[i], static_cast<float>(v[1 + i])) << "ray " << i;
        }
        const std::size_t p = 1 + expected_rays;
        EXPECT_DOUBLE_EQ(r.laser_pose.x(), v[p]);
        EXPECT_DOUBLE_EQ(r.laser_pose.y(), v[p + 1]);
        EXPECT_DOUBLE_EQ(r.laser_pose.phi(), v[p + 2]);
        EXPECT_DOUBLE_EQ(r.robot_pose.x(), v[p + 3]);
        EXPECT_DOUBLE_EQ(r.robot_pose.y(), v[p + 4]);
        EXPECT_DOUBLE_EQ(r.robot_pose.phi(), v[p + 5]);
        EXPECT_DOUBLE_EQ(r.ipc_timestamp, v[p + 6]);
        EXPECT_EQ(r.ipc_hostname, host);
        EXPECT_DOUBLE_EQ(r.logger_timestamp, v[p + 8]);
        EXPECT_NEAR(r.timestamp.to_seconds(), v[p + 8], 1e-9);
      }
    } else if (r.type == CarmenMessage::Odom) {
      ASSERT_NE(r.odometry, nullptr);
      ++odoms;
      if (first_odom) {
        first_odom = false;
        std::string host;
        const std::vector<double> v = numbers_of(expected.first_odom, host);
        ASSERT_EQ(v.size(), 9u);
        EXPECT_DOUBLE_EQ(r.odometry->odometry.x(), v[0]);
        EXPECT_DOUBLE_EQ(r.odometry->odometry.y(), v[1]);
        EXPECT_DOUBLE_EQ(r.odometry->odometry.phi(), v[2]);
        EXPECT_DOUBLE_EQ(r.odometry->velocity->vx, v[3]);
        EXPECT_DOUBLE_EQ(r.odometry->velocity->omega, v[4]);
        EXPECT_DOUBLE_EQ(r.logger_timestamp, v[8]);
      }
    }
  }
  const CarmenLogStats& s = reader.stats();
  EXPECT_EQ(scans, expected.flaser);
  EXPECT_EQ(odoms, expected.odom);
  EXPECT_EQ(s.flaser, expected.flaser);
  EXPECT_EQ(s.odom, expected.odom);
  EXPECT_EQ(s.lines, expected.lines);
  EXPECT_EQ(s.malformed, 0u);
  // Every line is accounted for by exactly one counter.
  EXPECT_EQ(s.flaser + s.rlaser + s.odom + s.robotlaser1 + s.truepos + s.comments + s.blank +
                s.param + s.sync + s.other,
            s.lines);
}

TEST(CarmenDatasets, IntelImportsEveryScanAndOdometryLine) {
  check_dataset("intel.clf.bz2", 13631, 180);
}

TEST(CarmenDatasets, Fr079ImportsEveryScanAndOdometryLine) {
  check_dataset("fr079.clf.bz2", 4934, 360);
}

TEST(CarmenDatasets, IntelFirstScanMatchesTheText) {
  // FLASER 180 1.07 1.07 1.08 ... 1.05 1.05 0.000000 0.000000 -0.002458
  //   0.000000 0.000000 -0.002458 976052857.337530 nohost 0.000246 (line 13)
  CarmenLogReader reader = CarmenLogReader::open(dataset("intel.clf.bz2"));
  CarmenRecord r;
  while (reader.next(r) && r.type != CarmenMessage::Flaser) {
  }
  ASSERT_EQ(r.type, CarmenMessage::Flaser);
  EXPECT_EQ(r.line, 13u);
  ASSERT_EQ(r.scan->size(), 180u);
  EXPECT_EQ(r.scan->ranges[0], 1.07f);
  EXPECT_EQ(r.scan->ranges[2], 1.08f);
  EXPECT_EQ(r.scan->ranges[179], 1.05f);
  EXPECT_DOUBLE_EQ(r.laser_pose.phi(), -0.002458);
  EXPECT_EQ(r.ipc_hostname, "nohost");
  EXPECT_EQ(r.timestamp.ns, 246000);
  EXPECT_EQ(reader.stats().odom, 1u);     // line 12 is the first ODOM
  EXPECT_EQ(reader.stats().param, 2u);
}

TEST(CarmenDatasets, Fr079FirstScanMatchesTheText) {
  // FLASER 360 1.67 1.65 1.64 ... 1.01 1.00 -2.994295 8.292039 -3.120965
  //   -3.034287 8.291214 -3.120965 1211.520329 magnum 0.015885 (line 199)
  CarmenLogReader reader = CarmenLogReader::open(dataset("fr079.clf.bz2"));
  CarmenRecord r;
  while (reader.next(r) && r.type != CarmenMessage::Flaser) {
  }
  ASSERT_EQ(r.type, CarmenMessage::Flaser);
  EXPECT_EQ(r.line, 199u);
  ASSERT_EQ(r.scan->size(), 360u);
  EXPECT_EQ(r.scan->ranges[0], 1.67f);
  EXPECT_EQ(r.scan->ranges[359], 1.00f);
  EXPECT_DOUBLE_EQ(r.laser_pose.x(), -2.994295);
  EXPECT_DOUBLE_EQ(r.robot_pose.x(), -3.034287);
  EXPECT_EQ(r.ipc_hostname, "magnum");
  EXPECT_DOUBLE_EQ(r.ipc_timestamp, 1211.520329);
  // laser ⊖ robot: the robot heads −3.121 rad and the laser lies 0.04 m
  // further along world x, so 0.04 m behind the robot's origin.
  const Pose2 sensor(r.scan->T_robot_sensor);
  EXPECT_NEAR(sensor.x(), -0.04, 0.001);
  EXPECT_NEAR(sensor.y(), 0.0, 0.001);
  EXPECT_NEAR(sensor.phi(), 0.0, 1e-9);
}

}  // namespace
}  // namespace rove
