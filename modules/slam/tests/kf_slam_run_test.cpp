#include "rove/slam/kf_slam_run.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "rove/core/error.h"
#include "rove/io/rove_rawlog.h"
#include "rove/obs/bearing_range.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kConfigs = "/usr/share/mrpt/config_files/kf-slam/";

KfSlamResult run_config(const std::string& name, KfSlamRunOptions o = {}) {
  const KfSlamConfig c = load_kf_slam_config(IniFile::load(kConfigs + name));
  return run_kf_slam(c, c.resolve(c.rawlog_file, "rawlog_file"), o);
}

// MRPT's EKF-SLAM_test.ini (odometry ignored, known IDs) on the bundled
// kf-slam demo: every landmark, no wrong pairing, errors against the
// ground-truth files the config names.
TEST(KfSlamRun, DemoAgainstGroundTruth) {
  const std::string ini =
      "[MappingApplication]\nrawlog_file=" + test_data::bundled_file("mrpt/kf-slam_demo.rawlog") +
      "\nground_truth_file=" + test_data::bundled_file("mrpt/kf-slam_demo_ground_truth.txt") +
      "\nground_truth_file_robot=" +
      test_data::bundled_file("mrpt/kf-slam_demo_ground_truth_robot_path.txt") +
      "\nlogOutput_dir=LOG\n[RangeBearingKFSLAM_KalmanFilter]\nmethod = kfEKFNaive\n"
      "[RangeBearingKFSLAM]\nforce_ignore_odometry = true\nstd_sensor_range = 0.02\n"
      "std_sensor_yaw_deg = 0.1\nstd_sensor_pitch_deg = 0.1\n";
  const KfSlamConfig c = load_kf_slam_config(IniFile::parse(ini, "demo.ini"));
  ASSERT_EQ(c.dim, 3);
  const KfSlamResult r = run_kf_slam(c, c.resolve(c.rawlog_file, "rawlog_file"));
  ASSERT_EQ(r.steps.size(), 250u);
  EXPECT_EQ(r.landmarks.size(), 70u);
  EXPECT_EQ(r.landmarks_with_truth, 70u);
  EXPECT_EQ(r.association.wrong, 0u);
  EXPECT_EQ(r.association.by_id, 3537u);
  ASSERT_TRUE(r.landmark_rmse && r.path_rmse);
  // MRPT 2.5.8's CRangeBearingKFSLAM on the same config: 0.017 m landmark
  // RMSE (bench/run_kf_slam_vs_mrpt.sh); rove 0.016 m, path 0.027 m.
  EXPECT_LT(*r.landmark_rmse, 0.025);
  EXPECT_LT(*r.path_rmse, 0.04);
}

// MRPT's 6D data-association demo with its config unchanged (JCBB,
// Mahalanobis): no wrong pairing and no duplicate, checked against the
// ground-truth map through the ground-truth path.
TEST(KfSlamRun, SixDofDataAssociationDemo) {
  const KfSlamResult r = run_config("EKF-SLAM_6D_test_datassoc.ini");
  EXPECT_EQ(r.options.data_association.method, DataAssociationMethod::Jcbb);
  ASSERT_EQ(r.steps.size(), 250u);
  EXPECT_EQ(r.association.by_id, 0u);
  EXPECT_EQ(r.landmarks.size(), 20u);
  EXPECT_EQ(r.association.wrong, 0u);
  EXPECT_EQ(r.association.duplicates, 0u);
  EXPECT_EQ(r.association.with_truth, r.association.readings);
  ASSERT_TRUE(r.landmark_rmse && r.path_rmse);
  // MRPT 2.5.8 on the same config: 0.033 m landmark RMSE (nearest truth);
  // rove 0.012 m, path 0.066 m.
  EXPECT_LT(*r.landmark_rmse, 0.02);
  EXPECT_LT(*r.path_rmse, 0.1);
  EXPECT_TRUE(r.issues.empty()) << r.issues.front().code;
}

// The 6D demo with IDs ignored: nearest-neighbour pairing, checked against
// the log's IDs.
TEST(KfSlamRun, SixDofDemoWithIdsIgnored) {
  KfSlamRunOptions o;
  o.use_landmark_ids = false;
  const KfSlamResult ids = run_config("EKF-SLAM_6D_test.ini");
  const KfSlamResult r = run_config("EKF-SLAM_6D_test.ini", o);
  EXPECT_EQ(r.association.by_id, 0u);
  EXPECT_EQ(r.association.with_truth, r.association.readings);
  EXPECT_GT(r.association.correct, 5000u);
  EXPECT_EQ(r.association.wrong, 0u);
  // A true pairing fails the 99 % individual gate about once in a hundred;
  // the few that do start duplicates, and are counted as such.
  EXPECT_EQ(r.landmarks.size(), ids.landmarks.size() + r.association.duplicates);
  EXPECT_LE(r.association.duplicates, r.association.correct / 100);
  ASSERT_TRUE(r.landmark_rmse && ids.landmark_rmse);
  EXPECT_LT(*r.landmark_rmse, 1.5 * *ids.landmark_rmse);
}

// A log of two steps: landmark 1 seen twice, landmark 2 once, a reading
// of range 0 (no direction); `bad_yaw` makes the second step's reading NaN.
std::string write_small_log(const std::string& name, float bad_yaw) {
  const std::string path =
      (std::filesystem::temp_directory_path() / (name + std::to_string(::getpid()))).string();
  RoveRawlogWriterOptions wo;
  wo.layout = RawlogLayout::Observations;
  RoveRawlogWriter w(path, wo);
  for (int k = 0; k < 2; ++k) {
    BearingRange b;
    LandmarkMeasurement m;
    m.landmark_id = 1, m.range = 3.0f, m.yaw = k == 0 ? 0.2f : bad_yaw;
    b.measurements.push_back(m);
    if (k == 0) {
      m.landmark_id = 2, m.range = 4.0f, m.yaw = -0.5f;
      b.measurements.push_back(m);
      m.landmark_id = 3, m.range = 0.0f, m.yaw = 0.0f;
      b.measurements.push_back(m);
    }
    w.write(b);
  }
  w.close();
  return path;
}

TEST(KfSlamRun, BadReadingsAreNamedOrFlagged) {
  const KfSlamConfig c = load_kf_slam_config(IniFile::parse("[RangeBearingKFSLAM]\n", "x.ini"));
  const std::string ok = write_small_log("rove_kf_slam_small_", 0.2f);
  const KfSlamResult r = run_kf_slam(c, ok);
  ASSERT_EQ(r.steps.size(), 2u);
  EXPECT_EQ(r.landmarks.size(), 2u);
  EXPECT_EQ(r.association.skipped, 1u);
  std::vector<std::string> codes;
  for (const auto& i : r.issues) codes.push_back(i.code);
  EXPECT_EQ(codes, (std::vector<std::string>{"landmarks-seen-once", "skipped-readings"}));
  const std::string nan = write_small_log("rove_kf_slam_nan_", std::nanf(""));
  try {
    run_kf_slam(c, nan);
    ADD_FAILURE() << "no error";
  } catch (const ParseError& e) {
    EXPECT_NE(e.message().find("step 1"), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("not finite"), std::string::npos) << e.message();
  }
  std::filesystem::remove(ok);
  std::filesystem::remove(nan);
}

TEST(KfSlamConfig, RejectsWhatItCannotRun) {
  const auto load = [](const std::string& text) {
    return load_kf_slam_config(IniFile::parse(text, "bad.ini"));
  };
  EXPECT_THROW(load("[Other]\nx=1\n"), ConfigError);                       // not a kf-slam config
  EXPECT_THROW(load("[RangeBearingKFSLAM]\nstd_sensor_rnge=0.1\n"), ConfigError);  // typo
  EXPECT_THROW(load("[RangeBearingKFSLAM]\nstd_sensor_range=0\n"), ConfigError);
  EXPECT_THROW(load("[RangeBearingKFSLAM]\nstds_Q_no_odo=0.1 0.1 0.1\n"), ConfigError);  // 3D: 7
  EXPECT_THROW(load("[RangeBearingKFSLAM]\ndata_assoc_method=assocXYZ\n"), ConfigError);
  EXPECT_THROW(load("[RangeBearingKFSLAM]\ndata_assoc_IC_chi2_thres=1.5\n"), ConfigError);
  EXPECT_THROW(load("[RangeBearingKFSLAM_KalmanFilter]\nmethod=kfIKFFull\n"), ConfigError);
  EXPECT_THROW(load("[MappingApplication]\nkf_implementation=CFoo\n"), ConfigError);
  const KfSlamConfig c = load(
      "[MappingApplication]\nkf_implementation=CRangeBearingKFSLAM2D\n[RangeBearingKFSLAM]\n"
      "stds_Q_no_odo=0.2 0.3 10\nstdXY_no_odo=0.1\ndata_assoc_method=assocJCBB\n"
      "data_assoc_metric=metricML\n[RangeBearingKFSLAM_KalmanFilter]\nmethod=1\nverbose=1\n");
  EXPECT_EQ(c.dim, 2);
  EXPECT_EQ(c.options.update, EkfSlamUpdate::Sequential);
  EXPECT_EQ(c.options.data_association.metric, DataAssociationMetric::MaximumLikelihood);
  ASSERT_EQ(c.options.stds_no_odometry.size(), 3u);
  EXPECT_NEAR(c.options.stds_no_odometry[2], 10.0 * M_PI / 180.0, 1e-12);
  EXPECT_EQ(c.ignored_keys.size(), 2u);  // stdXY_no_odo, verbose
  // The run names a missing ground-truth file.
  KfSlamConfig g = c;
  g.ground_truth_file = "no-such-file.txt";
  EXPECT_THROW(run_kf_slam(g, test_data::bundled_file("mrpt/kf-slam_demo.rawlog")), ConfigError);
}

// Every MRPT kf-slam config whose log exists loads unchanged.
TEST(KfSlamConfig, MrptConfigsLoad) {
  for (const char* name : {"EKF-SLAM_test.ini", "EKF-SLAM_test_2d.ini", "EKF-SLAM_6D_test.ini",
                           "EKF-SLAM_6D_test_datassoc.ini", "EKF-SLAM_6D_noncentered_test.ini",
                           "EKF-SLAM_6D_test_no_odometry.ini", "partition_EKF-SLAM_test.ini"}) {
    EXPECT_NO_THROW(load_kf_slam_config(IniFile::load(kConfigs + name))) << name;
  }
}

}  // namespace
}  // namespace rove
