// ICP-SLAM tells its user when the result is not what it promises: runs that
// accept few or no ICP results carry issues; logs without scans are errors;
// Ctrl-C stops the run; CARMEN's maximum range comes from the config.

#include <unistd.h>

#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "icp_slam_test_util.h"
#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/core/interrupt.h"
#include "rove/obs/selection_error.h"
#include "rove/slam/icp_slam.h"
#include "rove/slam/icp_slam_run.h"

namespace rove {
namespace {

namespace fs = std::filesystem;
using test::data_path;
using test::telecom_rawlog;

std::string file_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

// The demo config with minICPgoodnessToAccept replaced.
IniFile demo_config_with_goodness(const std::string& goodness) {
  std::string text = file_text(data_path("icp-slam_demo_classic.ini"));
  // Replace the value on the key's line (no std::regex: GCC 12 warns inside
  // it under the sanitizers' -O1).
  const std::string key = "minICPgoodnessToAccept";
  const std::size_t at = text.find(key);
  EXPECT_NE(at, std::string::npos);
  const std::size_t eol = text.find('\n', at);
  text.replace(at, eol - at, key + " = " + goodness);
  return IniFile::parse(text, "demo_goodness.ini");
}

IcpSlamRunResult run(const IniFile& ini, IcpSlamStats& stats, std::uint64_t steps,
                     const std::string& rawlog = telecom_rawlog()) {
  IcpSlamConfig cfg = load_icp_slam_config(ini);
  IcpSlam slam(cfg.options, std::move(cfg.map));
  IcpSlamRunOptions o;
  o.max_steps = steps;
  IcpSlamRunResult r = run_icp_slam(slam, rawlog, o);
  stats = slam.stats();
  return r;
}

// The Freiburg clinic case (0 of 6,915 accepted, exit 0 before): here the
// bundled Telecom log with a threshold no ICP result can pass.
TEST(IcpSlamIssues, NoAcceptedIcpResultIsAnIssue_Regression) {
  IcpSlamStats st;
  const IcpSlamRunResult r = run(demo_config_with_goodness("1.0"), st, 40);
  ASSERT_GT(st.icp_runs, 10u);
  EXPECT_EQ(st.icp_accepted, 0u);
  EXPECT_EQ(st.icp_rejected_goodness + st.icp_rejected_invalid, st.icp_runs);
  EXPECT_GT(st.icp_goodness_max, 0.4);
  ASSERT_EQ(r.issues.size(), 1u);
  EXPECT_EQ(r.issues[0].code, "no-icp-accepted");
  EXPECT_NE(r.issues[0].message.find("minICPgoodnessToAccept 1"), std::string::npos)
      << r.issues[0].message;
}

TEST(IcpSlamIssues, FewAcceptedIcpResultsIsAnIssue_Regression) {
  IcpSlamStats st;
  const IcpSlamRunResult good = run(demo_config_with_goodness("0.40"), st, 40);
  ASSERT_GT(st.icp_runs, 10u);
  EXPECT_GE(static_cast<double>(st.icp_accepted), 0.5 * static_cast<double>(st.icp_runs));
  EXPECT_TRUE(good.issues.empty());
  EXPECT_EQ(st.icp_accepted + st.icp_rejected_goodness + st.icp_rejected_invalid, st.icp_runs);

  // The same counters judged with a threshold between the two: few accepted.
  IcpSlamStats few = st;
  few.icp_accepted = st.icp_runs / 4;
  few.icp_rejected_goodness = st.icp_runs - few.icp_accepted;
  const auto issues = icp_slam_issues(few, IcpSlamOptions{});
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].code, "few-icp-accepted");
  EXPECT_TRUE(icp_slam_issues(st, IcpSlamOptions{}).empty());
}

TEST(IcpSlamRun, LogWithoutScansIsAnError_Regression) {
  const fs::path dir = fs::temp_directory_path() / ("rove_icp_honest_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string odom_only = (dir / "odom.clf").string();
  {
    std::ofstream f(odom_only);
    for (int i = 0; i < 20; ++i) {
      f << "ODOM " << 0.1 * i << " 0 0 0 0 0 " << i << ".0 host " << i << ".0\n";
    }
  }
  for (RawlogLayout layout : {RawlogLayout::ActionsSensoryFrames, RawlogLayout::Observations}) {
    IcpSlamConfig cfg =
        load_icp_slam_config(IniFile::load(data_path("icp-slam_demo_classic.ini")));
    IcpSlam slam(cfg.options, std::move(cfg.map));
    IcpSlamRunOptions o;
    o.reader.carmen.layout = layout;
    // Layout #1: the reader refuses a CARMEN log that gives no entry (ODOM
    // lines only go between two scans); layout #2: the odometry entries
    // hold nothing to match.
    if (layout == RawlogLayout::ActionsSensoryFrames) {
      EXPECT_THROW(run_icp_slam(slam, odom_only, o), ParseError);
    } else {
      EXPECT_THROW(run_icp_slam(slam, odom_only, o), SelectionError);
    }
  }
  fs::remove_all(dir);
}

TEST(IcpSlamRun, OffsetPastTheEndIsAnError_Regression) {
  IcpSlamConfig cfg = load_icp_slam_config(IniFile::load(data_path("icp-slam_demo_classic.ini")));
  IcpSlam slam(cfg.options, std::move(cfg.map));
  IcpSlamRunOptions o;
  o.rawlog_offset = 100000;
  try {
    run_icp_slam(slam, telecom_rawlog(), o);
    ADD_FAILURE() << "an empty run succeeded";
  } catch (const SelectionError& e) {
    EXPECT_EQ(e.option(), "rawlog_offset");
  }
}

TEST(IcpSlamRun, CtrlCStopsTheRun_Regression) {
  IcpSlamConfig cfg = load_icp_slam_config(IniFile::load(data_path("icp-slam_demo_classic.ini")));
  IcpSlam slam(cfg.options, std::move(cfg.map));
  install_interrupt_handler();
  IcpSlamRunOptions o;
  int steps = 0;
  o.on_step = [&steps](const IcpSlamStep&) {
    if (++steps == 6) std::raise(SIGINT);
  };
  EXPECT_THROW(run_icp_slam(slam, telecom_rawlog(), o), Interrupted);
  reset_interrupted();
  EXPECT_EQ(steps, 6);
}

TEST(IcpSlamConfig, CarmenMaxRangeKey) {
  std::string text = file_text(data_path("icp-slam_demo_classic.ini"));
  EXPECT_FALSE(load_icp_slam_config(IniFile::parse(text, "a.ini")).carmen_max_range.has_value());
  const IcpSlamConfig cfg =
      load_icp_slam_config(IniFile::parse(text + "\n[CARMEN]\nmaxRange = 50\n", "b.ini"));
  ASSERT_TRUE(cfg.carmen_max_range.has_value());
  EXPECT_FLOAT_EQ(*cfg.carmen_max_range, 50.0f);
  EXPECT_THROW(load_icp_slam_config(IniFile::parse(text + "\n[CARMEN]\nmaxrange_m = 50\n", "c.ini")),
               ConfigError);
  EXPECT_THROW(load_icp_slam_config(IniFile::parse(text + "\n[CARMEN]\nmaxRange = -1\n", "d.ini")),
               ConfigError);
}

}  // namespace
}  // namespace rove
