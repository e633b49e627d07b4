// CARMEN → rawlog conversion, convert / cut / decimate, and the text exports
// compared value by value with MRPT 2.5.8's rawlog-edit output on the same
// files (references in tests/data/, see tests/data/README_rawlog.md).
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/carmen_log.h"
#include "rove/io/carmen_to_rawlog.h"
#include "rove/io/rawlog_tools.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/action_collection.h"
#include "rove/obs/odometry_observation.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/robot_movement_2d.h"
#include "rove/obs/sensory_frame.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kData = std::string(ROVE_SOURCE_DIR) + "/modules/io/tests/data/";
const std::string kCarmen = kData + "carmen_intel_head.clf";
const std::string kMrptIntel = kData + "mrpt_carmen2rawlog_intel_head.rawlog";
const std::string kSena = std::string(ROVE_SOURCE_DIR) +
                          "/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";


std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("rove_rawlog_tools_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

std::vector<std::string> lines_of(const std::string& path, char skip_prefix = '\0') {
  std::ifstream f(path);
  EXPECT_TRUE(f.good()) << "missing file " << path;
  std::vector<std::string> out;
  std::string line;
  while (std::getline(f, line)) {
    if (skip_prefix != '\0' && !line.empty() && line[0] == skip_prefix) continue;
    out.push_back(line);
  }
  return out;
}

std::string file_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  EXPECT_TRUE(f.good()) << "missing file " << path;
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

std::vector<double> numbers(const std::string& line) {
  std::istringstream s(line);
  std::vector<double> v;
  double x;
  while (s >> x) v.push_back(x);
  return v;
}

// The row without its time column.
std::string data_columns(const std::string& row) {
  const std::size_t start = row.find_first_not_of(' ');
  return row.substr(row.find(' ', start) + 1);
}

TEST(CarmenToRawlog, Layout1FramesAndOdometryIncrements) {
  CarmenRawlogSource source = CarmenRawlogSource::open(kCarmen);
  std::vector<Pose2> scan_poses;
  {
    CarmenLogReader reader = CarmenLogReader::open(kCarmen);
    CarmenRecord r;
    while (reader.next(r)) {
      if (r.scan) scan_poses.push_back(r.robot_pose);
    }
  }
  ASSERT_EQ(scan_poses.size(), 24u);
  std::size_t frames = 0, actions = 0;
  bool expect_frame = true;
  while (auto e = source.next()) {
    if (auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&*e)) {
      EXPECT_TRUE(expect_frame);
      ASSERT_EQ((*sf)->size(), 1u);
      EXPECT_NE((*sf)->find<RangeScan2D>(), nullptr);
      ++frames;
      expect_frame = false;
    } else {
      auto ac = std::get<std::shared_ptr<const ActionCollection>>(*e);
      EXPECT_FALSE(expect_frame);
      ASSERT_EQ(ac->size(), 1u);
      auto move = ac->find<RobotMovement2D>();
      ASSERT_NE(move, nullptr);
      // pose_k ⊖ pose_{k-1}, with MRPT's default Gaussian motion model.
      const Pose2 expected = scan_poses[frames] - scan_poses[frames - 1];
      EXPECT_NEAR(move->odometry_increment.x(), expected.x(), 1e-12);
      EXPECT_NEAR(move->odometry_increment.y(), expected.y(), 1e-12);
      EXPECT_NEAR(move->odometry_increment.phi(), expected.phi(), 1e-12);
      EXPECT_EQ(move->motion_model, MotionModelOptions{});
      EXPECT_TRUE(move->timestamp.valid());
      ++actions;
      expect_frame = true;
    }
  }
  const CarmenRawlogStats& s = source.stats();
  EXPECT_EQ(frames, 24u);
  EXPECT_EQ(actions, 23u);
  EXPECT_EQ(s.scans, 24u);
  EXPECT_EQ(s.sensory_frames, 24u);
  EXPECT_EQ(s.action_collections, 23u);
  EXPECT_EQ(s.odom_not_used, 45u);
  EXPECT_EQ(s.log.flaser, 24u);
  EXPECT_EQ(s.log.odom, 45u);
  EXPECT_EQ(s.log.param, 2u);
}

TEST(CarmenToRawlog, Layout2AsCarmen2rawlogPlusOdomLines) {
  CarmenToRawlogOptions o;
  o.layout = RawlogLayout::Observations;
  CarmenRawlogSource source = CarmenRawlogSource::open(kCarmen, o);
  std::size_t odometry = 0, scans = 0;
  while (auto e = source.next()) {
    auto obs = std::get<std::shared_ptr<const Observation>>(*e);
    if (dynamic_cast<const OdometryObservation*>(obs.get()) != nullptr) {
      EXPECT_EQ(obs->sensor_label, "ODOMETRY");
      ++odometry;
    } else {
      EXPECT_NE(dynamic_cast<const RangeScan2D*>(obs.get()), nullptr);
      ++scans;
    }
  }
  EXPECT_EQ(scans, 24u);
  EXPECT_EQ(odometry, 24u + 45u);
  EXPECT_EQ(source.stats().odom_lines_used, 45u);
  EXPECT_EQ(source.stats().observations, 24u * 2 + 45u);
}

// Against MRPT's carmen2rawlog (layout #2 output committed in tests/data):
// the same ranges, validity and odometry, scan by scan.
TEST(CarmenToRawlog, ScansAndOdometryMatchMrptCarmen2rawlog) {
  const AnyRawlog mrpt = load_any_rawlog(kMrptIntel);
  CarmenToRawlogOptions o;
  o.layout = RawlogLayout::Observations;
  o.odom_lines = false;  // carmen2rawlog ignores ODOM lines
  AnyRawlogOptions ro;
  ro.carmen = o;
  const AnyRawlog rove = load_any_rawlog(kCarmen, ro);
  ASSERT_EQ(mrpt.entries.size(), 48u);
  ASSERT_EQ(rove.entries.size(), 48u);
  for (std::size_t i = 0; i < 48; ++i) {
    auto a = std::get<std::shared_ptr<const Observation>>(mrpt.entries[i]);
    auto b = std::get<std::shared_ptr<const Observation>>(rove.entries[i]);
    ASSERT_EQ(a->class_name(), b->class_name()) << i;
    if (auto* sa = dynamic_cast<const RangeScan2D*>(a.get())) {
      auto* sb = dynamic_cast<const RangeScan2D*>(b.get());
      EXPECT_EQ(sa->ranges, sb->ranges) << i;
      EXPECT_EQ(sa->valid, sb->valid) << i;
      EXPECT_NEAR(sa->T_robot_sensor.x(), sb->T_robot_sensor.x(), 1e-9);
      EXPECT_NEAR(sa->T_robot_sensor.yaw(), sb->T_robot_sensor.yaw(), 1e-9);
    } else {
      auto* oa = dynamic_cast<const OdometryObservation*>(a.get());
      auto* ob = dynamic_cast<const OdometryObservation*>(b.get());
      EXPECT_NEAR(oa->odometry.x(), ob->odometry.x(), 1e-12) << i;
      EXPECT_NEAR(oa->odometry.y(), ob->odometry.y(), 1e-12) << i;
      EXPECT_NEAR(oa->odometry.phi(), ob->odometry.phi(), 1e-12) << i;
    }
  }
}

TEST(RawlogTools, ExportsOfAnMrptRawlogEqualRawlogEditsByteForByte) {
  const std::string scans = temp_path("scans.txt");
  const RawlogJobResult r = export_scans_txt(kMrptIntel, scans);
  ASSERT_EQ(r.files.size(), 1u);
  EXPECT_EQ(r.rows[0], 24u);
  EXPECT_EQ(file_text(scans), file_text(kData + "mrpt_carmen2rawlog_intel_head_FLASER.txt"));
  const std::string odo = temp_path("odo.txt");
  const RawlogJobResult ro = export_odometry_txt(kMrptIntel, odo);
  ASSERT_EQ(ro.rows.size(), 1u);
  EXPECT_EQ(ro.rows[0], 24u);
  EXPECT_EQ(file_text(odo), file_text(kData + "mrpt_carmen2rawlog_intel_head_ODOMETRY.txt"));
  std::filesystem::remove(scans);
  std::filesystem::remove(odo);
}

TEST(RawlogTools, ExportsOfTheCarmenLogMatchRawlogEditsValues) {
  // Layout #1 straight from CARMEN: the scan rows carry the same data
  // columns as rawlog-edit's export of carmen2rawlog's file; the odometry
  // integrated from the actions is MRPT's absolute odometry seen from the
  // first scan's pose.
  const std::string scans = temp_path("carmen_scans.txt");
  export_scans_txt(kCarmen, scans);
  const auto ours = lines_of(scans);
  const auto ref = lines_of(kData + "mrpt_carmen2rawlog_intel_head_FLASER.txt");
  ASSERT_EQ(ours.size(), ref.size());
  EXPECT_EQ(ours[0], ref[0]);
  for (std::size_t i = 1; i < ref.size(); ++i) {
    EXPECT_EQ(data_columns(ours[i]), data_columns(ref[i])) << "row " << i;
  }
  // Our time column is the CARMEN logger time (seconds since the log began).
  EXPECT_EQ(ours[1].substr(0, 16), "        0.000246");

  const std::string odo = temp_path("carmen_odo.txt");
  export_odometry_txt(kCarmen, odo);
  const auto integrated = lines_of(odo, '%');
  const auto absolute = lines_of(kData + "mrpt_carmen2rawlog_intel_head_ODOMETRY.txt", '%');
  ASSERT_EQ(integrated.size(), absolute.size());
  const std::vector<double> first = numbers(absolute[0]);
  const Pose2 origin(first[1], first[2], first[3]);
  for (std::size_t i = 0; i < absolute.size(); ++i) {
    const std::vector<double> a = numbers(absolute[i]);
    const std::vector<double> b = numbers(integrated[i]);
    ASSERT_EQ(a.size(), 11u);
    ASSERT_EQ(b.size(), 11u);
    const Pose2 p = origin + Pose2(b[1], b[2], b[3]);
    EXPECT_NEAR(p.x(), a[1], 2e-5) << "row " << i;
    EXPECT_NEAR(p.y(), a[2], 2e-5) << "row " << i;
    EXPECT_NEAR(p.phi(), a[3], 2e-5) << "row " << i;
  }
  std::filesystem::remove(scans);
  std::filesystem::remove(odo);
}

// The bundled Telecom rawlog against tests/data/mrpt_sena_export_2d_scans.txt
// (rawlog-edit's first and last 5 rows; rawlog-edit leaves out the frame
// before the first action, rove exports it as row 1).
TEST(RawlogTools, TelecomScansMatchRawlogEdit) {
  const std::string out = temp_path("sena.txt");
  const RawlogJobResult r = export_scans_txt(kSena, out);
  ASSERT_EQ(r.rows.size(), 1u);
  EXPECT_EQ(r.rows[0], 225u);
  const auto ours = lines_of(out);
  const auto ref = lines_of(kData + "mrpt_sena_export_2d_scans.txt", '#');
  ASSERT_EQ(ref.size(), 11u);
  ASSERT_EQ(ours.size(), 226u);
  EXPECT_EQ(ours[0], ref[0]);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(ours[2 + i], ref[1 + i]) << "first rows " << i;
    EXPECT_EQ(ours[221 + i], ref[6 + i]) << "last rows " << i;
  }
  std::filesystem::remove(out);
}

TEST(RawlogTools, LocalizationDemoScansMatchRawlogEdit) {
  const std::string in = test_data::bundled_file("mrpt/localization_demo.rawlog");
  ASSERT_TRUE(std::filesystem::exists(in)) << "dataset missing: " << in;
  const std::string out = temp_path("loc.txt");
  const RawlogJobResult r = export_scans_txt(in, out);
  ASSERT_EQ(r.rows.size(), 1u);
  // This log starts with an action: rawlog-edit and rove export all 37.
  EXPECT_EQ(r.rows[0], 37u);
  const auto ours = lines_of(out);
  const auto ref = lines_of(kData + "mrpt_localization_demo_export_2d_scans.txt", '#');
  ASSERT_EQ(ref.size(), 6u);
  ASSERT_EQ(ours.size(), 38u);
  EXPECT_EQ(ours[0], ref[0]);
  for (std::size_t i = 1; i <= 3; ++i) EXPECT_EQ(ours[i], ref[i]) << i;
  EXPECT_EQ(ours[36], ref[4]);
  EXPECT_EQ(ours[37], ref[5]);
  std::filesystem::remove(out);
}

TEST(RawlogTools, ConvertBetweenLayoutsIsConsistent) {
  // CARMEN → #2 (carmen2rawlog's stream) → #1 gives the entries CARMEN → #1
  // gives directly.
  const std::string l2 = temp_path("l2.rawlog");
  const std::string l1 = temp_path("l1.rawlog");
  ConvertOptions o2;
  o2.layout = RawlogLayout::Observations;
  o2.read.carmen.odom_lines = false;
  const RawlogJobResult r2 = convert_rawlog(kCarmen, l2, o2);
  EXPECT_EQ(r2.entries_out, 48u);
  EXPECT_EQ(r2.kept.at("RangeScan2D"), 24u);
  EXPECT_EQ(r2.dropped.at("CARMEN ODOM line (odometry taken from laser lines)"), 45u);
  ConvertOptions o1;
  o1.layout = RawlogLayout::ActionsSensoryFrames;
  const RawlogJobResult r1 = convert_rawlog(l2, l1, o1);
  EXPECT_EQ(r1.entries_out, 47u);
  EXPECT_EQ(r1.dropped.at("OdometryObservation (-> actions)"), 24u);
  const RoveRawlog via = load_rove_rawlog(l1);
  EXPECT_EQ(via.metadata.at("source_format"), "rove");
  AnyRawlog direct = load_any_rawlog(kCarmen);
  ASSERT_EQ(via.entries.size(), direct.entries.size());
  for (std::size_t i = 0; i < direct.entries.size(); ++i) {
    if (auto* a = std::get_if<std::shared_ptr<const SensoryFrame>>(&direct.entries[i])) {
      EXPECT_TRUE(**a == *std::get<std::shared_ptr<const SensoryFrame>>(via.entries[i])) << i;
    } else {
      auto ma = std::get<std::shared_ptr<const ActionCollection>>(direct.entries[i])
                    ->find<RobotMovement2D>();
      auto mb = std::get<std::shared_ptr<const ActionCollection>>(via.entries[i])
                    ->find<RobotMovement2D>();
      EXPECT_NEAR(ma->odometry_increment.x(), mb->odometry_increment.x(), 1e-12);
      EXPECT_NEAR(ma->odometry_increment.phi(), mb->odometry_increment.phi(), 1e-12);
    }
  }
  // And back: #1 → #2 turns actions into absolute odometry.
  const std::string back = temp_path("back.rawlog");
  ConvertOptions ob;
  ob.layout = RawlogLayout::Observations;
  const RawlogJobResult rb = convert_rawlog(l1, back, ob);
  EXPECT_EQ(rb.kept.at("OdometryObservation"), 23u);
  EXPECT_EQ(rb.kept.at("RangeScan2D"), 24u);
  for (const auto& p : {l1, l2, back}) std::filesystem::remove(p);
}

TEST(RawlogTools, CutByIndexAndTime) {
  const std::string out = temp_path("cut.rawlog");
  CutOptions o;
  o.from_index = 10;
  o.to_index = 19;
  RawlogJobResult r = cut_rawlog(kSena, out, o);
  EXPECT_EQ(r.entries_out, 10u);
  EXPECT_EQ(r.entries_in, 20u);  // reading stops after to_index
  const Rawlog all = load_rawlog(kSena);
  const RoveRawlog cut = load_rove_rawlog(out);
  ASSERT_EQ(cut.entries.size(), 10u);
  EXPECT_TRUE(*std::get<std::shared_ptr<const SensoryFrame>>(all.entries[10]) ==
              *std::get<std::shared_ptr<const SensoryFrame>>(cut.entries[0]));

  // Times: the Telecom log spans 1137834225.75 .. 1137834291.26 s.
  CutOptions t;
  t.from_time = 1137834230.0;
  t.to_time = 1137834240.0;
  r = cut_rawlog(kSena, out, t);
  const RoveRawlog timed = load_rove_rawlog(out);
  ASSERT_GT(timed.entries.size(), 0u);
  for (const auto& e : timed.entries) {
    if (auto* sf = std::get_if<std::shared_ptr<const SensoryFrame>>(&e)) {
      for (const auto& obs : (*sf)->observations) {
        EXPECT_GE(obs->timestamp.to_seconds(), 1137834230.0);
        EXPECT_LE(obs->timestamp.to_seconds(), 1137834240.0);
      }
    }
  }
  // Every scan is either kept or dropped.
  EXPECT_EQ(r.kept.at("RangeScan2D") + r.dropped.at("RangeScan2D"), 225u);
  t.from_time = 5.0;
  t.to_time = 1.0;
  EXPECT_THROW(cut_rawlog(kSena, out, t), InvalidArgument);
  std::filesystem::remove(out);
}

TEST(RawlogTools, DecimateKeepsOdometryConsistent) {
  const std::string out = temp_path("dec.rawlog");
  DecimateOptions o;
  o.every = 3;
  const RawlogJobResult r = decimate_rawlog(kSena, out, o);
  const Rawlog all = load_rawlog(kSena);
  const RoveRawlog dec = load_rove_rawlog(out);
  // 225 frames → frames 0, 3, ..., 222: 75 kept, 74 merged actions.
  std::size_t frames = 0, actions = 0;
  for (const auto& e : dec.entries) {
    if (std::holds_alternative<std::shared_ptr<const SensoryFrame>>(e)) ++frames;
    else ++actions;
  }
  EXPECT_EQ(frames, 75u);
  EXPECT_EQ(actions, 74u);
  EXPECT_EQ(r.dropped.at("RobotMovement2D (after the last kept frame)"), 1u);
  // Odometry integrated over the decimated log equals the original's at
  // every kept frame.
  auto integrate = [](const std::vector<RawlogEntry>& entries) {
    std::vector<Pose2> at_frames;
    Pose2 p;
    for (const auto& e : entries) {
      if (auto* ac = std::get_if<std::shared_ptr<const ActionCollection>>(&e)) {
        p = p + (*ac)->find<RobotMovement2D>()->odometry_increment;
      } else {
        at_frames.push_back(p);
      }
    }
    return at_frames;
  };
  const auto full = integrate(all.entries);
  const auto kept = integrate(dec.entries);
  ASSERT_EQ(full.size(), 225u);
  ASSERT_EQ(kept.size(), 75u);
  for (std::size_t k = 0; k < kept.size(); ++k) {
    EXPECT_NEAR(kept[k].x(), full[3 * k].x(), 1e-9) << k;
    EXPECT_NEAR(kept[k].y(), full[3 * k].y(), 1e-9) << k;
    EXPECT_NEAR(kept[k].phi(), full[3 * k].phi(), 1e-9) << k;
  }
  std::filesystem::remove(out);
}

TEST(RawlogTools, CorruptInputNamesTheFile) {
  const std::string bad = temp_path("bad.rawlog");
  {
    const std::string text = file_text(kSena);
    std::ofstream f(bad, std::ios::binary);
    f.write(text.data(), static_cast<std::streamsize>(text.size() / 2));
  }
  try {
    convert_rawlog(bad, temp_path("never.rawlog"));
    ADD_FAILURE() << "truncated gzip accepted";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, bad);
    EXPECT_TRUE(e.location().offset.has_value());
  }
  std::filesystem::remove(bad);
  std::filesystem::remove(temp_path("never.rawlog"));
}

// The Radish logs: every laser and ODOM line is accounted for.
void expect_carmen_dataset(const std::string& name, std::uint64_t scans, std::uint64_t odom) {
  const std::string path = test_data::shared_dataset("radish/" + name);
  ASSERT_TRUE(std::filesystem::exists(path)) << "dataset missing: " << path;
  CarmenRawlogSource source = CarmenRawlogSource::open(path);
  std::uint64_t frames = 0, actions = 0;
  while (auto e = source.next()) {
    if (std::holds_alternative<std::shared_ptr<const SensoryFrame>>(*e)) ++frames;
    else ++actions;
  }
  const CarmenRawlogStats& s = source.stats();
  EXPECT_EQ(s.scans, scans);
  EXPECT_EQ(frames, scans);
  EXPECT_EQ(actions, scans - 1);
  EXPECT_EQ(s.odom_not_used, odom);
  EXPECT_EQ(s.log.flaser + s.log.rlaser + s.log.robotlaser1, scans);
  EXPECT_EQ(s.log.odom, odom);
  EXPECT_EQ(s.log.malformed, 0u);
}

TEST(CarmenToRawlogDatasets, IntelEveryLineAccountedFor) { expect_carmen_dataset("intel.clf.bz2", 13631, 26915); }
TEST(CarmenToRawlogDatasets, Fr079EveryLineAccountedFor) { expect_carmen_dataset("fr079.clf.bz2", 4934, 8951); }

}  // namespace
}  // namespace rove
