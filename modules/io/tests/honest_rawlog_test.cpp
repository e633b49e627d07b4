// Regression tests for rawlog input that is not what it claims to be, jobs
// that select nothing, outputs that would overwrite their input, partial
// outputs, Ctrl-C, and the CARMEN maximum range ("no return" readings).
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/core/interrupt.h"
#include "rove/io/any_rawlog.h"
#include "rove/io/carmen_log.h"
#include "rove/io/carmen_to_rawlog.h"
#include "rove/io/rawlog_tools.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/selection_error.h"
#include "rove/test_data.h"

namespace rove {
namespace {

namespace fs = std::filesystem;

const std::string kData = std::string(ROVE_SOURCE_DIR) + "/modules/io/tests/data/";
const std::string kCarmen = kData + "carmen_intel_head.clf";
const std::string kSena = std::string(ROVE_SOURCE_DIR) +
                          "/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";
const std::string kDatasets = test_data::shared_datasets_dir() + "/";

// A fresh folder per test, removed at the end.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : dir_(fs::temp_directory_path() /
             ("rove_honest_rawlog_" + std::to_string(::getpid()) + "_" + name)) {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream f(path(name), std::ios::binary);
    f << text;
    return path(name);
  }
  // Every file in the folder (temporary files included).
  std::vector<std::string> files() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    return out;
  }

 private:
  fs::path dir_;
};

std::string file_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// ------------------------------------------------------------ format detection

TEST(AnyRawlogFormat, TextIsNotReadAsAnEmptyCarmenLog_Regression) {
  TempDir tmp("text");
  for (const std::string& text :
       {std::string("hello world\n"), std::string("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n"),
        std::string("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nPOINTS 0\nDATA ascii\n")}) {
    const std::string file = tmp.write("input.txt", text);
    try {
      AnyRawlogReader reader(file);
      while (reader.next()) {
      }
      ADD_FAILURE() << "read as a log: " << text;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, file);
      EXPECT_NE(e.message().find("not a rove rawlog, MRPT rawlog or CARMEN log"), std::string::npos)
          << e.message();
    }
  }
}

TEST(AnyRawlogFormat, BinaryThatIsNotMrptIsRefused_Regression) {
  TempDir tmp("binary");
  for (const std::string& bytes :
       {std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16), std::string("\x85\x01\x02\x03\x04\x05", 6),
        std::string("\xff\xfe\x00\x01", 4)}) {
    const std::string file = tmp.write("input.bin", bytes);
    try {
      detect_rawlog_format(file);
      ADD_FAILURE() << "binary data taken for an MRPT rawlog";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().source, file);
      EXPECT_EQ(e.location().field, "format");
    }
  }
}

TEST(AnyRawlogFormat, CarmenLogWithoutRecordsIsAnError_Regression) {
  TempDir tmp("norecords");
  const std::string file =
      tmp.write("params.clf", "# CARMEN Logfile\nPARAM robot_use_laser on nohost 0\n");
  AnyRawlogReader reader(file);
  EXPECT_EQ(reader.format(), RawlogFormat::Carmen);
  try {
    while (reader.next()) {
    }
    ADD_FAILURE() << "a log without a record read as empty";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, file);
    EXPECT_EQ(e.location().field, "records");
  }
}

// Found by rove_any_rawlog_fuzz: a CARMEN log of ODOM lines only read as an
// empty rawlog in layout #1 (odometry only goes between two scans), though a
// log without records was already an error.
TEST(AnyRawlogFormat, CarmenLogWithoutEntriesIsAnError_Regression) {
  TempDir tmp("noentries");
  const std::string file = tmp.write(
      "odom.clf", "PARAM robot_front_laser_max 50.0 nohost 0\n"
                  "ODOM 0.0 0.0 0.0 0.0 0.0 0.0 1.0 host 1.0\n"
                  "TRUEPOS 0 0 0 0 0 0 2.0 host 2.0\n");
  AnyRawlogReader reader(file);
  EXPECT_EQ(reader.format(), RawlogFormat::Carmen);
  try {
    while (reader.next()) {
    }
    ADD_FAILURE() << "ODOM and TRUEPOS lines read as an empty rawlog";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().source, file);
    EXPECT_EQ(e.location().field, "records");
    EXPECT_NE(std::string(e.what()).find("1 ODOM, 1 TRUEPOS"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_any_rawlog(file), ParseError);
  // In layout #2 the ODOM line is an odometry observation: one entry.
  AnyRawlogOptions o;
  o.carmen.layout = RawlogLayout::Observations;
  EXPECT_EQ(load_any_rawlog(file, o).entries.size(), 1u);
}

TEST(AnyRawlogFormat, DevicesAndFoldersAreRefused_Regression) {
  EXPECT_THROW(detect_rawlog_format("/dev/zero"), IoError);
  EXPECT_THROW(AnyRawlogReader("/dev/null"), IoError);
  TempDir tmp("folder");
  EXPECT_THROW(AnyRawlogReader(tmp.path("")), IoError);
}

TEST(AnyRawlogFormat, RealLogsAreStillDetected) {
  EXPECT_EQ(detect_rawlog_format(kCarmen), RawlogFormat::Carmen);
  EXPECT_EQ(detect_rawlog_format(kSena), RawlogFormat::Mrpt);
}

// ------------------------------------------------------------ selections

TEST(RawlogTools, CutOutsideTheLogIsAnError_Regression) {
  TempDir tmp("cut");
  CutOptions o;
  o.from_index = 100000;
  try {
    cut_rawlog(kSena, tmp.path("cut.rawlog"), o);
    ADD_FAILURE() << "an empty cut was written";
  } catch (const SelectionError& e) {
    EXPECT_EQ(e.option(), "from_index");
    EXPECT_NE(e.message().find("449 entries (indices 0..448)"), std::string::npos) << e.message();
  }
  EXPECT_TRUE(tmp.files().empty());
  CutOptions t;
  t.from_time = 1.0;
  t.to_time = 2.0;
  EXPECT_THROW(cut_rawlog(kSena, tmp.path("cut.rawlog"), t), SelectionError);
  EXPECT_TRUE(tmp.files().empty());
}

TEST(RawlogTools, ExportOfAMissingLabelIsAnError_Regression) {
  TempDir tmp("label");
  TextExportOptions o;
  o.label = "NOPE";
  try {
    export_scans_txt(kCarmen, tmp.path("scans.txt"), o);
    ADD_FAILURE() << "an empty export succeeded";
  } catch (const SelectionError& e) {
    EXPECT_EQ(e.option(), "label");
    EXPECT_NE(e.message().find("'LASER' (24)"), std::string::npos) << e.message();
  }
  EXPECT_THROW(export_odometry_txt(kCarmen, tmp.path("odo.txt"), o), SelectionError);
  EXPECT_TRUE(tmp.files().empty());
}

TEST(RawlogTools, ExportOfALogWithoutScansIsAnError_Regression) {
  TempDir tmp("noscans");
  const std::string odom_only = tmp.write(
      "odom.clf", "ODOM 0 0 0 0 0 0 1.0 host 1.0\nODOM 1 0 0 0 0 0 2.0 host 2.0\n");
  TextExportOptions o;
  o.read.carmen.layout = RawlogLayout::Observations;
  EXPECT_THROW(export_scans_txt(odom_only, tmp.path("scans.txt"), o), SelectionError);
  EXPECT_FALSE(fs::exists(tmp.path("scans.txt")));
}

// ------------------------------------------------------------ outputs

TEST(RawlogTools, OutputEqualToInputIsRefused_Regression) {
  TempDir tmp("same");
  const std::string copy = tmp.path("log.clf");
  fs::copy_file(kCarmen, copy);
  const std::string before = file_text(copy);
  CutOptions cut;
  cut.from_index = 0;
  EXPECT_THROW(cut_rawlog(copy, copy, cut), IoError);
  DecimateOptions dec;
  dec.every = 2;
  EXPECT_THROW(decimate_rawlog(copy, copy, dec), IoError);
  EXPECT_THROW(convert_rawlog(copy, copy), IoError);
  EXPECT_THROW(export_scans_txt(copy, copy), IoError);
  // Through another spelling of the same path.
  EXPECT_THROW(convert_rawlog(copy, tmp.path("./log.clf")), IoError);
  EXPECT_EQ(file_text(copy), before);
  EXPECT_EQ(tmp.files(), std::vector<std::string>{"log.clf"});
}

TEST(RawlogTools, FailedJobLeavesNoPartialFile_Regression) {
  TempDir tmp("partial");
  // A valid head, then a malformed line: the job fails part way.
  std::string text = file_text(kCarmen);
  text += "FLASER 3 1.0 2.0 abc 0 0 0 0 0 0 1.0 host 1.0\n";
  const std::string bad = tmp.write("bad.clf", text);
  const std::string out = tmp.write("out.rawlog", "older result");
  EXPECT_THROW(convert_rawlog(bad, out), ParseError);
  EXPECT_EQ(file_text(out), "older result");
  EXPECT_THROW(export_scans_txt(bad, tmp.path("scans.txt")), ParseError);
  std::vector<std::string> files = tmp.files();
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"bad.clf", "out.rawlog"}));
}

TEST(RawlogTools, CtrlCStopsAJobAndWritesNothing_Regression) {
  TempDir tmp("interrupt");
  install_interrupt_handler();
  std::raise(SIGINT);
  EXPECT_THROW(convert_rawlog(kCarmen, tmp.path("out.rawlog")), Interrupted);
  reset_interrupted();
  EXPECT_TRUE(tmp.files().empty());
  // And the flag cleared, the same job runs to the end.
  const RawlogJobResult r = convert_rawlog(kCarmen, tmp.path("out.rawlog"));
  EXPECT_EQ(r.entries_out, 47u);
  EXPECT_EQ(tmp.files(), std::vector<std::string>{"out.rawlog"});
}

// ------------------------------------------------------------ CARMEN max range

std::vector<RangeScan2D> scans_of(const std::string& log, CarmenLogOptions options = {}) {
  CarmenLogReader reader = CarmenLogReader::from_memory(log, "<test>", options);
  std::vector<RangeScan2D> out;
  CarmenRecord r;
  while (reader.next(r)) {
    if (r.scan) out.push_back(*r.scan);
  }
  return out;
}

const char* kScanLine = "FLASER 4 1.00 50.00 49.99 60.00 0 0 0 0 0 0 1.0 host 1.0\n";

TEST(CarmenMaxRange, ReadingsAtTheConfiguredMaximumAreNoReturn_Regression) {
  CarmenLogOptions o;
  o.flaser_max_range = 50.0f;
  const auto scans = scans_of(kScanLine, o);
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_FLOAT_EQ(scans[0].max_range, 50.0f);
  EXPECT_EQ(scans[0].valid, (std::vector<bool>{true, false, true, false}));
  // The default (81 m) keeps 50 and 60 m.
  EXPECT_EQ(scans_of(kScanLine)[0].valid, (std::vector<bool>{true, true, true, true}));
}

TEST(CarmenMaxRange, ParamLineSetsTheMaximum_Regression) {
  const std::string log = std::string("PARAM robot_front_laser_max 50.0 nohost 0\n") + kScanLine +
                          "PARAM robot_rear_laser_max 2.0 nohost 0\n" +
                          "RLASER 2 1.00 2.00 0 0 0 0 0 0 1.0 host 1.0\n";
  CarmenLogOptions o;
  o.flaser_max_range = 81.0f;
  const auto scans = scans_of(log, o);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[0].valid, (std::vector<bool>{true, false, true, false}));
  EXPECT_FLOAT_EQ(scans[1].max_range, 2.0f);
  EXPECT_EQ(scans[1].valid, (std::vector<bool>{true, false}));
  // A PARAM value that is not a range is named.
  try {
    scans_of("PARAM robot_front_laser_max far nohost 0\n");
    ADD_FAILURE() << "bad PARAM accepted";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().line, 1u);
    EXPECT_EQ(e.location().field, "PARAM robot_front_laser_max");
  }
}

// A malformed PARAM range skipped as malformed is counted once.
TEST(CarmenMaxRange, SkippedBadParamIsCountedOnce) {
  CarmenLogOptions o;
  o.skip_malformed = true;
  CarmenLogReader reader = CarmenLogReader::from_memory(
      std::string("PARAM robot_front_laser_max -3 nohost 0\n") + kScanLine, "<test>", o);
  CarmenRecord r;
  while (reader.next(r)) {
  }
  const CarmenLogStats& s = reader.stats();
  EXPECT_EQ(s.malformed, 1u);
  EXPECT_EQ(s.param, 0u);
  EXPECT_EQ(s.flaser, 1u);
  EXPECT_FLOAT_EQ(s.front_max_range, 81.0f);
  EXPECT_FALSE(s.front_max_range_from_log);
}

// A PARAM range too small for a float (1e-50 m) became a 0 m maximum, which
// made every reading of every later scan "no return" without a word.
TEST(CarmenMaxRange, ParamRangeThatRoundsToZeroIsRefused_Regression) {
  for (const char* value : {"1e-50", "1e-46"}) {
    try {
      scans_of(std::string("PARAM robot_front_laser_max ") + value + " nohost 0\n" + kScanLine);
      ADD_FAILURE() << "PARAM range " << value << " accepted";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().line, 1u);
      EXPECT_EQ(e.location().field, "PARAM robot_front_laser_max");
    }
  }
  // The smallest float above zero is still a (tiny) range.
  const auto scans = scans_of(std::string("PARAM robot_rear_laser_max 1e-44 nohost 0\n") +
                              "RLASER 1 1.00 0 0 0 0 0 0 1.0 host 1.0\n");
  ASSERT_EQ(scans.size(), 1u);
  EXPECT_GT(scans[0].max_range, 0.0f);
}

// ACES: readings of exactly 50.00 m mean "no return" (11,139 of them); with
// the maximum at 50 m none of them is a valid point.
TEST(CarmenMaxRangeDatasets, AcesNoReturnReadingsAreInvalid_Regression) {
  const std::string path = kDatasets + "radish/aces.clf.bz2";
  if (!fs::exists(path)) GTEST_SKIP() << "dataset missing: " << path;
  CarmenLogOptions o;
  o.flaser_max_range = 50.0f;
  CarmenLogReader reader = CarmenLogReader::open(path, o);
  CarmenRecord r;
  std::size_t at_50 = 0, valid_at_50 = 0, valid = 0;
  while (reader.next(r)) {
    if (!r.scan) continue;
    for (std::size_t i = 0; i < r.scan->ranges.size(); ++i) {
      const bool is_50 = r.scan->ranges[i] == 50.0f;
      at_50 += is_50 ? 1 : 0;
      valid_at_50 += is_50 && r.scan->valid[i] ? 1 : 0;
      valid += r.scan->valid[i] ? 1 : 0;
    }
  }
  EXPECT_EQ(at_50, 11139u);
  EXPECT_EQ(valid_at_50, 0u);
  EXPECT_GT(valid, 1000000u);
}

}  // namespace
}  // namespace rove
