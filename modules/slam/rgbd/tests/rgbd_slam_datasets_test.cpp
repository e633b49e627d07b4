// The RGB-D SLAM pipeline on real sequences with ground truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "rove/io/any_rawlog.h"
#include "rove/maps/kdtree.h"
#include "rove/poses/lie_conversion.h"

#include "rove/slam/rgbd_sequence.h"
#include "rove/slam/rgbd_slam.h"
#include "rove/slam/rgbd_slam_run.h"
#include "rove/test_data.h"

namespace rove {
namespace {

TEST(RgbdSlamDatasets, TumFr1RpyAteWithinTwoCentimeters) {
  const RgbdSequence seq = read_rgbd_sequence(test_data::shared_dataset("rgbd/tum_fr1_rpy"));
  ASSERT_EQ(seq.frames.size(), 205u);
  EXPECT_EQ(seq.camera_source, "tum-fr1");
  RgbdSlam slam(seq.camera, for_sequence({}, seq));
  EXPECT_EQ(slam.options().rolling_shutter_readout, 0.02);
  const RgbdSlamRunResult r = run_rgbd_slam(slam, seq);
  ASSERT_TRUE(r.ate.has_value()) << r.ate_problem;
  const RgbdSlamStats& st = slam.stats();
  std::printf("fr1/rpy: ATE %.4f m (max %.4f) over %zu poses; %zu keyframes, %zu lost, %zu guided, %zu brute, "
              "%zu recovered, loops %zu/%zu; features %.3f s matching %.3f s pnp %.3f s loops %.3f "
              "s graph %.3f s map %.3f s, read %.3f s\n",
              r.ate->translation.rmse, r.ate->translation.max, r.ate->translation.count, st.keyframes, st.lost,
              st.guided_tracked, st.brute_force_tracked, st.recovered, st.loops_accepted,
              st.loop_checks, st.features_seconds, st.matching_seconds, st.pnp_seconds,
              st.loop_seconds, st.graph_seconds, st.map_seconds, r.read_seconds);
  EXPECT_EQ(r.ate->translation.count, 205u);
  // Measured: 1.44 cm with fr1's rolling shutter (20 ms, calibrated without
  // the ground truth: bench/run_rgbd_rolling_shutter.sh); 1.41-1.85 cm over
  // seeds 1-6. The issue's target is 2.0 cm. 3 frames lost to motion blur
  // (frames 113-115).
  EXPECT_LE(r.ate->translation.rmse, 0.020);
  EXPECT_LE(st.lost, 5u);
  EXPECT_GT(st.icp_edges, 2 * st.icp_refused);  // most keyframe pairs measured by depth too

  // As a global shutter (readout 0): worse, as measured (2.40 cm; 2.38-2.49
  // over seeds 1-6).
  RgbdSlamOptions global;
  global.rolling_shutter_readout = 0.0;
  RgbdSlam plain(seq.camera, for_sequence(global, seq));
  EXPECT_EQ(plain.options().rolling_shutter_readout, 0.0);
  const RgbdSlamRunResult p = run_rgbd_slam(plain, seq);
  ASSERT_TRUE(p.ate.has_value()) << p.ate_problem;
  EXPECT_GT(p.ate->translation.rmse, r.ate->translation.rmse + 0.005);
}

TEST(RgbdSlamDatasets, IclNuimLivingRoomAgainstItsTruePoses) {
  const RgbdSequence seq = read_rgbd_sequence(test_data::shared_dataset("rgbd/icl_livingroom"));
  ASSERT_EQ(seq.frames.size(), 5u);
  EXPECT_EQ(seq.camera_source, "icl-nuim");
  // Five frames far apart (turns of 49° and 91°), not a video: no motion
  // limit, every tracked frame a keyframe.
  RgbdSlamOptions o;
  o.max_norm = 0.0;
  o.min_inliers = 10;
  o.keyframe_threshold = 1e-3;
  RgbdSlam slam(seq.camera, o);
  const RgbdSlamRunResult r = run_rgbd_slam(slam, seq);
  ASSERT_TRUE(r.ate.has_value()) << r.ate_problem;
  for (std::size_t i = 0; i < slam.num_frames(); ++i) {
    const SE3d truth = seq.reference[0].pose.inverse() * seq.reference[i].pose;
    const SE3d err = truth.inverse() * slam.frame_pose(i);
    std::printf("icl frame %zu %s: %.4f m %.4f rad\n", i, std::string(to_string(slam.frame_status(i))).c_str(),
                err.translation().norm(), err.rotation().log().norm());
    if (slam.frame_status(i) == RgbdFrameStatus::Keyframe) {
      EXPECT_LT(err.translation().norm(), 0.02) << "frame " << i;
      EXPECT_LT(err.rotation().log().norm(), 0.01) << "frame " << i;
    }
  }
  // Measured: frame 3 (index 2) is tracked against frame 1 within 1.1 cm and
  // 0.36°; frames 2, 4 and 5 are not (too few matches across the turns),
  // and the run says so.
  EXPECT_EQ(slam.frame_status(2), RgbdFrameStatus::Keyframe);
  EXPECT_EQ(slam.stats().lost, 3u);
  ASSERT_FALSE(r.issues.empty());
  EXPECT_EQ(r.issues[0].code, "lost-tracking");
}

// MRPT's tests_rgbd.rawlog: one CObservation3DRangeScan of an OpenNI2
// camera (depth camera f = 572.9, intensity camera f = 521.2, 1.5 mm apart).
TEST(RgbdSlamDatasets, MrptTestsRgbdRawlogGivesOnePoseAndTheScansCloud) {
  const std::string path = test_data::shared_dataset("mrpt/tests_rgbd.rawlog");
  const RgbdSequence seq = read_rgbd_sequence(path);
  EXPECT_EQ(seq.format, RgbdSequenceFormat::Rawlog);
  ASSERT_EQ(seq.frames.size(), 1u);
  EXPECT_EQ(seq.sensor_label, "OPENNI2");
  EXPECT_EQ(seq.camera.width, 640u);
  EXPECT_NEAR(seq.camera.fx, 521.179233, 1e-6);  // the intensity camera's
  RgbdSlam slam(seq.camera);
  const RgbdSlamRunResult r = run_rgbd_slam(slam, seq);
  EXPECT_EQ(r.frames, 1u);
  EXPECT_TRUE(r.issues.empty());
  ASSERT_EQ(slam.num_frames(), 1u);
  EXPECT_EQ(slam.frame_status(0), RgbdFrameStatus::Keyframe);
  EXPECT_TRUE(slam.frame_pose(0).is_approx(SE3d()));
  EXPECT_NEAR(slam.frame_time(0), seq.frames[0].time, 1e-9);

  // The map against the points MRPT stored with the scan (sensor frame),
  // brought into the intensity camera's optical frame.
  AnyRawlogReader reader(path);
  const auto entry = reader.next();
  ASSERT_TRUE(entry.has_value());
  const auto scans = range_images_of(*entry);
  ASSERT_EQ(scans.size(), 1u);
  ASSERT_TRUE(scans[0]->points.has_value());
  const SE3d T_intensity_sensor = to_se3(scans[0]->T_sensor_intensity).inverse();
  std::vector<Eigen::Vector3f> stored;
  for (const Eigen::Vector3f& p : scans[0]->points->p_sensor) {
    stored.push_back((T_intensity_sensor * p.cast<double>()).cast<float>());
  }
  const KdTree3f tree(std::move(stored));
  const PointCloud map = slam.map_cloud();
  ASSERT_GT(map.size(), 10000u);
  std::vector<float> d;
  for (const Eigen::Vector3f& q : map.points()) d.push_back(std::sqrt(tree.nearest(q)->sq_distance));
  std::sort(d.begin(), d.end());
  const float median = d[d.size() / 2], p99 = d[d.size() * 99 / 100];
  std::printf("tests_rgbd: %zu map points, %zu stored; distance to the stored points: median %.4f m, 99%% %.4f m, "
              "max %.4f m\n",
              map.size(), scans[0]->points->p_sensor.size(), median, p99, d.back());
  EXPECT_LT(median, 0.005f);
  EXPECT_LT(p99, 0.012f);
}

}  // namespace
}  // namespace rove
