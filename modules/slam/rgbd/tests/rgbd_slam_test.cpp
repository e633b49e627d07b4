// The RGB-D SLAM pipeline on rendered frames of a textured room with known
// camera poses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_set>

#include "rove/core/error.h"
#include "rove/core/ini.h"
#include "rove/io/octree_files.h"
#include "rove/slam/rgbd_slam.h"
#include "rove/slam/rgbd_slam_run.h"
#include "rgbd_test_room.h"

namespace rove {
namespace {

using namespace rgbd_test;

double angle_of(const SE3d& T) { return T.rotation().log().norm(); }

TEST(RgbdSlam, FollowsARenderedRoomAndClosesTheLoop) {
  const PinholeCamera cam = test_camera();
  RgbdSlam slam(cam);
  constexpr std::size_t kFrames = 30;
  for (std::size_t i = 0; i < kFrames; ++i) {
    const RgbdFrameUpdate u = slam.process(render(cam, true_pose(i, kFrames)), 0.1 * static_cast<double>(i));
    EXPECT_NE(u.status, RgbdFrameStatus::Lost) << "frame " << i;
    EXPECT_NE(u.status, RgbdFrameStatus::NoFeatures) << "frame " << i;
  }
  slam.finish();
  ASSERT_EQ(slam.num_frames(), kFrames);
  const SE3d T0 = true_pose(0, kFrames);
  for (std::size_t i = 0; i < kFrames; ++i) {
    const SE3d truth = T0.inverse() * true_pose(i, kFrames);
    const SE3d err = truth.inverse() * slam.frame_pose(i);
    // Measured: at most 15 mm and 4.1 mrad (frame 10), 7 mm typical; the
    // rendering is not anti-aliased, so corners sit on whole pixels.
    EXPECT_LT(err.translation().norm(), 0.02) << "frame " << i;
    EXPECT_LT(angle_of(err), 0.006) << "frame " << i;
  }
  const RgbdSlamStats& st = slam.stats();
  EXPECT_EQ(st.frames, kFrames);
  EXPECT_EQ(st.lost, 0u);
  EXPECT_GE(st.keyframes, 3u);
  EXPECT_GE(st.loops_accepted, 1u);
  EXPECT_EQ(slam.graph().num_vertices(), st.keyframes);
  // The map lies on the room's planes (each point within 2 cm of one).
  const PointCloud map = slam.map_cloud();
  ASSERT_GT(map.size(), 1000u);
  ASSERT_TRUE(map.has_colors());
  std::size_t off = 0;
  for (const Eigen::Vector3f& q : map.points()) {
    const Eigen::Vector3d p = T0 * q.cast<double>();
    double d = std::numeric_limits<double>::infinity();
    for (const Plane& pl : kPlanes) d = std::min(d, std::abs(p[pl.axis] - pl.value));
    if (d > 0.02) ++off;
  }
  EXPECT_EQ(off, 0u);
}

TEST(RgbdSlam, BundleAdjustmentOfTheRenderedRoomKeepsEveryFrameOnItsTruePose) {
  const PinholeCamera cam = test_camera();
  RgbdSlamOptions o;
  o.bundle_adjustment = true;
  RgbdSlam slam(cam, o);
  constexpr std::size_t kFrames = 30;
  for (std::size_t i = 0; i < kFrames; ++i) slam.process(render(cam, true_pose(i, kFrames)), 0.1 * static_cast<double>(i));
  slam.finish();
  const auto& ba = slam.bundle_adjustment();
  ASSERT_TRUE(ba.has_value());
  EXPECT_TRUE(ba->ok()) << ba->message;
  const RgbdSlamStats& st = slam.stats();
  EXPECT_GT(st.ba_points, 200u);
  EXPECT_GE(st.ba_observations, 2 * st.ba_points);
  EXPECT_LT(st.ba_outliers, st.ba_observations / 10);
  EXPECT_LT(ba->rmse_px, 1.0);  // corners on whole pixels: about half a pixel
  const SE3d T0 = true_pose(0, kFrames);
  for (std::size_t i = 0; i < kFrames; ++i) {
    const SE3d err = (T0.inverse() * true_pose(i, kFrames)).inverse() * slam.frame_pose(i);
    EXPECT_LT(err.translation().norm(), 0.02) << "frame " << i;
    EXPECT_LT(angle_of(err), 0.006) << "frame " << i;
  }
  // Off by default: no adjustment, no tracks kept.
  RgbdSlam plain(cam);
  plain.process(render(cam, true_pose(0, kFrames)), 0.0);
  plain.process(render(cam, true_pose(1, kFrames)), 0.1);
  plain.finish();
  EXPECT_FALSE(plain.bundle_adjustment().has_value());
}

// A rolling shutter reading the rows over 25 ms, frames 1/30 s apart on the
// room's path (turns of up to 1.6 rad/s: the rows' poses differ by up to
// 40 mrad, 20 px). Measured: with the readout known, mean 2.0 cm and 8.8
// mrad (max 3.8 cm); without, 3.1 cm and 23.7 mrad (max 8.0 cm). The rest
// is the angular velocity's lag: it is the last two frames', 1.5 frames
// before the frame's own, on a path that turns back every 15 frames.
TEST(RgbdSlam, RollingShutterFramesAreFollowedWhenTheReadoutIsKnown) {
  const PinholeCamera cam = test_camera();
  constexpr std::size_t kFrames = 30;
  constexpr double kDt = 1.0 / 30.0, kReadout = 0.025;
  auto frame = [&](std::size_t i) {
    return render_rows(cam, [&](std::uint32_t v) {
      const double row_time = ((v + 0.5) / cam.height - 0.5) * kReadout;  // from the middle row's
      return true_pose(static_cast<double>(i) + row_time / kDt, kFrames);
    });
  };
  std::vector<RgbdFrame> frames;
  for (std::size_t i = 0; i < kFrames; ++i) frames.push_back(frame(i));
  struct Errors {
    double mean_translation = 0.0, mean_rotation = 0.0, max_translation = 0.0;
  };
  auto run = [&](double readout) {
    RgbdSlamOptions o;
    o.rolling_shutter_readout = readout;
    RgbdSlam slam(cam, o);
    for (std::size_t i = 0; i < kFrames; ++i) slam.process(frames[i], kDt * static_cast<double>(i));
    slam.finish();
    Errors e;
    const SE3d T0 = true_pose(0.0, kFrames);  // the middle row's pose of frame 0
    for (std::size_t i = 0; i < kFrames; ++i) {
      const SE3d err = (T0.inverse() * true_pose(static_cast<double>(i), kFrames)).inverse() * slam.frame_pose(i);
      e.mean_translation += err.translation().norm() / kFrames;
      e.mean_rotation += angle_of(err) / kFrames;
      e.max_translation = std::max(e.max_translation, err.translation().norm());
    }
    return e;
  };
  const Errors corrected = run(kReadout), plain = run(0.0);
  std::printf("rolling shutter 25 ms: mean %.4f m %.5f rad (max %.4f m) corrected; %.4f m %.5f rad (max %.4f m) not\n",
              corrected.mean_translation, corrected.mean_rotation, corrected.max_translation,
              plain.mean_translation, plain.mean_rotation, plain.max_translation);
  EXPECT_LT(corrected.max_translation, 0.05);
  EXPECT_LT(corrected.mean_rotation, 0.012);
  EXPECT_LT(corrected.mean_translation, 0.8 * plain.mean_translation);
  EXPECT_LT(corrected.mean_rotation, 0.5 * plain.mean_rotation);
}

// Loop candidates by appearance alone (no nearby, proximity or random
// ones): the room's path comes back near its start, and the keyframes that
// look alike are found and closed.
TEST(RgbdSlam, AppearanceAloneFindsTheLoopBackToTheStart) {
  const PinholeCamera cam = test_camera();
  RgbdSlamOptions o;
  o.nearby_loops = o.proximity_loops = o.random_loops = 0;
  o.appearance_loops = 2;
  RgbdSlam slam(cam, o);
  constexpr std::size_t kFrames = 30;
  for (std::size_t i = 0; i < kFrames; ++i) slam.process(render(cam, true_pose(i, kFrames)), 0.1 * static_cast<double>(i));
  slam.finish();
  std::size_t checked = 0, accepted = 0, far_apart = 0;
  for (const RgbdLoopCheck& c : slam.loop_checks()) {
    EXPECT_EQ(c.kind, RgbdLoopKind::Appearance);
    ++checked;
    accepted += c.accepted;
    // Not the previous keyframe (joined already) and, for some, a keyframe
    // from the start seen again at the end.
    if (c.accepted && c.keyframe >= c.candidate + 3) ++far_apart;
  }
  EXPECT_GT(checked, 0u);
  EXPECT_GE(accepted, checked / 2) << "appearance candidates should mostly be real loops";
  EXPECT_GE(far_apart, 1u);
  const SE3d T0 = true_pose(0, kFrames);
  for (std::size_t i = 0; i < kFrames; ++i) {
    const SE3d err = (T0.inverse() * true_pose(i, kFrames)).inverse() * slam.frame_pose(i);
    EXPECT_LT(err.translation().norm(), 0.02) << "frame " << i;
  }
  EXPECT_EQ(to_string(RgbdLoopKind::Appearance), "appearance");
}

// Distance from p (world) to the nearest of the room's planes.
double distance_to_room(const Eigen::Vector3d& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const Plane& pl : kPlanes) d = std::min(d, std::abs(p[pl.axis] - pl.value));
  return d;
}

TEST(RgbdSlam, TheOctreeMapHoldsTheRoomsWallsAndTheFreeSpaceBeforeThem) {
  const PinholeCamera cam = test_camera();
  RgbdSlam slam(cam);  // octree_resolution 0.05
  constexpr std::size_t kFrames = 30;
  for (std::size_t i = 0; i < 10; ++i) {
    slam.process(render(cam, true_pose(i, kFrames)), 0.1 * static_cast<double>(i));
  }
  slam.finish();
  ASSERT_GE(slam.stats().keyframes, 2u);
  const OccupancyOctree tree = slam.map_octree();
  EXPECT_EQ(tree.resolution(), 0.05);
  EXPECT_GT(slam.stats().octree_seconds, 0.0);
  // World = the first camera's frame, which is the room's (true_pose(0) is
  // the identity).
  ASSERT_TRUE(true_pose(0, kFrames).is_approx(SE3d()));

  // Every occupied cell lies on a wall (its centre within half its diagonal
  // and 2 cm of a plane), and holds points of the cloud map.
  const PointCloud map = slam.map_cloud();
  std::unordered_set<OctreeKey, OctreeKeyHash> map_cells;
  for (const Eigen::Vector3f& q : map.points()) map_cells.insert(tree.key_checked(q.cast<double>()));
  std::size_t occupied = 0, free = 0, off_wall = 0, without_points = 0;
  tree.for_each_leaf([&](const OctreeLeaf& l) {
    if (!tree.is_occupied(l.log_odds)) {
      ++free;
      return;
    }
    ++occupied;
    const double half_diagonal = tree.node_size(l.depth) * std::sqrt(3.0) / 2.0;
    if (distance_to_room(tree.center_of(l.key, l.depth)) > half_diagonal + 0.02) ++off_wall;
    if (l.depth == kOctreeDepth && !map_cells.contains(l.key)) ++without_points;
  });
  EXPECT_GT(occupied, 1000u);
  EXPECT_GT(free, 100u);
  EXPECT_EQ(off_wall, 0u);
  // Measured: 0. The octree's points are the keyframes' clouds before the
  // final voxel filter, whose cells the map's 1 cm voxels fall in.
  EXPECT_LE(without_points, occupied / 100);

  // The space inside the first camera's view (x/z within ±0.45, y/z within
  // ±0.35 of the image's ±0.61 and ±0.46) and before the far wall (z = 3)
  // is known and free; behind the wall nothing is known.
  for (double z = 0.3; z <= 2.8; z += 0.1) {
    for (double a = -0.45; a <= 0.46; a += 0.15) {
      for (double b = -0.35; b <= 0.36; b += 0.175) {
        const double x = a * z, y = b * z;
        const auto n = tree.search(Eigen::Vector3d(x, y, z));
        ASSERT_TRUE(n.has_value()) << x << " " << y << " " << z;
        EXPECT_FALSE(tree.is_occupied(n->log_odds)) << x << " " << y << " " << z;
      }
    }
  }
  EXPECT_FALSE(tree.search(Eigen::Vector3d(0.0, 0.0, 3.3)).has_value());
  // The wall (z = 3, a cell boundary) is in the cell before or after it.
  const auto before = tree.search(Eigen::Vector3d(0.02, 0.02, 2.99));
  const auto after = tree.search(Eigen::Vector3d(0.02, 0.02, 3.01));
  EXPECT_TRUE((before && tree.is_occupied(before->log_odds)) || (after && tree.is_occupied(after->log_odds)));

  // OctoMap's .bt: read back, every cell has the occupancy it had.
  const OccupancyOctree back = parse_octree(octree_binary_bytes(tree, OctreeBinaryContent::MaxLikelihood), "map.bt");
  EXPECT_EQ(back.resolution(), tree.resolution());
  std::size_t differ = 0;
  tree.for_each_leaf([&](const OctreeLeaf& l) {
    const auto n = back.search(l.key, l.depth);
    if (!n || back.is_occupied(n->log_odds) != tree.is_occupied(l.log_odds)) ++differ;
  });
  EXPECT_EQ(differ, 0u);
}

TEST(RgbdSlam, NoOctreeResolutionMeansNoOctree) {
  RgbdSlamOptions o;
  o.octree_resolution = 0.0;
  RgbdSlam slam(test_camera(), o);
  EXPECT_THROW(slam.map_octree(), InvalidArgument);
  o.octree_resolution = -0.1;
  EXPECT_THROW(RgbdSlam(test_camera(), o), InvalidArgument);
  o.octree_resolution = 0.05;
  o.octree_threads = 300;
  EXPECT_THROW(RgbdSlam(test_camera(), o), InvalidArgument);
}

TEST(RgbdSlam, ATexturelessFrameIsSkippedAndCounted) {
  const PinholeCamera cam = test_camera();
  RgbdSlam slam(cam);
  constexpr std::size_t kFrames = 30;
  for (std::size_t i = 0; i < 8; ++i) {
    const RgbdFrameUpdate u = slam.process(render(cam, true_pose(i, kFrames), i == 4), 0.1 * static_cast<double>(i));
    if (i == 4) {
      EXPECT_EQ(u.status, RgbdFrameStatus::NoFeatures);
      EXPECT_EQ(u.features, 0u);
    } else {
      EXPECT_NE(u.status, RgbdFrameStatus::Lost) << "frame " << i;
      EXPECT_NE(u.status, RgbdFrameStatus::NoFeatures) << "frame " << i;
    }
  }
  EXPECT_EQ(slam.stats().no_features, 1u);
  EXPECT_EQ(slam.stats().lost, 0u);
  const SE3d truth = true_pose(0, kFrames).inverse() * true_pose(7, kFrames);
  EXPECT_LT((truth.inverse() * slam.frame_pose(7)).translation().norm(), 0.02);
}

TEST(RgbdSlam, AllTexturelessFramesGiveIdentityPosesAndNoKeyframe) {
  const PinholeCamera cam = test_camera();
  RgbdSlam slam(cam);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(slam.process(render(cam, SE3d(), true), static_cast<double>(i)).status,
              RgbdFrameStatus::NoFeatures);
  }
  EXPECT_FALSE(slam.finish().has_value());
  EXPECT_TRUE(slam.keyframes().empty());
  EXPECT_TRUE(slam.frame_pose(2).is_approx(SE3d()));
  EXPECT_EQ(slam.map_cloud().size(), 0u);
}

TEST(RgbdSlam, RejectsBadInput) {
  const PinholeCamera cam = test_camera();
  RgbdSlam slam(cam);
  const RgbdFrame f = render(cam, SE3d());
  slam.process(f, 1.0);
  EXPECT_THROW(slam.process(f, 1.0), InvalidArgument);  // time does not increase
  PinholeCamera other = cam;
  other.width = 320;
  RgbdSlam small(other);
  EXPECT_THROW(small.process(f, 0.0), InvalidArgument);  // size differs from the camera's
  RgbdSlamOptions o;
  o.min_inliers = 3;
  EXPECT_THROW(RgbdSlam(cam, o), InvalidArgument);
}

TEST(RgbdSlamOptions, ReadsTheTutorialNamesAndPresets) {
  const IniFile ini = IniFile::parse(
      "detector=ORB\ndescriptor=ORB\ngood_match_threshold=4\ncamera.fx=518.0;\nmin_inliers=7\n"
      "max_norm=0.3\nkeyframe_threshold=0.2\nnearby_loops=4\nrandom_loops=6\nvoxel_grid=0.02\n"
      "visualize_pointcloud=yes\n",
      "params.txt");
  const ConfigSection s(ini, "");
  const RgbdSlamOptions o = RgbdSlamOptions::from_config(s);
  s.check_all_read();
  EXPECT_EQ(o.match.relative_factor, 4.0);
  EXPECT_EQ(o.min_inliers, 7u);
  EXPECT_EQ(o.max_norm, 0.3);
  EXPECT_EQ(o.keyframe_threshold, 0.2);
  EXPECT_EQ(o.nearby_loops, 4u);
  EXPECT_EQ(o.random_loops, 6u);
  EXPECT_EQ(o.voxel_grid, 0.02);
  EXPECT_EQ(o.octree_resolution, 0.05);  // rove's default kept
  EXPECT_EQ(o.proximity_loops, RgbdSlamOptions().proximity_loops);  // rove's default kept

  const IniFile t = IniFile::parse("[rgbd]\npreset = tutorial\n", "t.ini");
  const RgbdSlamOptions tut = RgbdSlamOptions::from_config(ConfigSection(t, "rgbd"));
  EXPECT_EQ(tut.min_inliers, 5u);
  EXPECT_EQ(tut.nearby_loops, 5u);
  EXPECT_EQ(tut.random_loops, 5u);
  EXPECT_EQ(tut.proximity_loops, 0u);
  EXPECT_EQ(tut.match.relative_factor, 10.0);
  EXPECT_EQ(tut.guided_radius_px, 0.0);

  const IniFile nol = IniFile::parse("check_loop_closure=no\n", "n.ini");
  const RgbdSlamOptions n = RgbdSlamOptions::from_config(ConfigSection(nol, ""));
  EXPECT_EQ(n.nearby_loops + n.random_loops + n.proximity_loops, 0u);

  const IniFile oct = IniFile::parse("[rgbd-slam]\noctree_resolution = 0.1\noctree_threads = 0\n", "o.ini");
  const RgbdSlamOptions ot = RgbdSlamOptions::from_config(ConfigSection(oct, "rgbd-slam"));
  EXPECT_EQ(ot.octree_resolution, 0.1);
  EXPECT_EQ(ot.octree_threads, 0);

  // The geometric edges: on by default, off in the tutorial's preset, keys read.
  EXPECT_EQ(RgbdSlamOptions().icp_voxel, 0.03);
  EXPECT_EQ(tut.icp_voxel, 0.0);
  const IniFile icp = IniFile::parse(
      "icp_voxel = 0.04\nicp_max_distance = 0.2\nicp_min_pairing = 0.7\nicp_max_correction = 0.05\n", "i.ini");
  const ConfigSection is(icp, "");
  const RgbdSlamOptions io = RgbdSlamOptions::from_config(is);
  is.check_all_read();
  EXPECT_EQ(io.icp_voxel, 0.04);
  EXPECT_EQ(io.icp_max_distance, 0.2);
  EXPECT_EQ(io.icp_min_pairing, 0.7);
  EXPECT_EQ(io.icp_max_correction, 0.05);
}

TEST(RgbdSlamOptions, BadValuesNameTheKey) {
  for (const char* text : {"detector=SIFT\n", "min_inliers=2\n", "preset=fast\n", "voxel_grid=-1\n",
                           "nearby_loops=1.5\n", "octree_resolution=-0.05\n", "octree_threads=1000\n",
                           "icp_voxel=-0.02\n", "icp_max_distance=0\n", "icp_min_pairing=1.5\n",
                           "icp_max_correction=nan\n", "rolling_shutter_readout=-0.01\n",
                           "rolling_shutter_readout=2\n", "ba_inverse_depth_sigma=0\n", "ba_iterations=0\n",
                           "bundle_adjustment=maybe\n"}) {
    const IniFile ini = IniFile::parse(text, "bad.ini");
    try {
      RgbdSlamOptions::from_config(ConfigSection(ini, ""));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const ConfigError& e) {
      const std::string key(text, std::string_view(text).find('='));
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

// Unset, the readout is the sequence's camera's; set, it is the file's; the
// tutorial's preset is a global shutter.
TEST(RgbdSlamOptions, RollingShutterReadoutComesFromTheCameraUnlessSet) {
  RgbdSequence seq;
  seq.rolling_shutter_readout = 0.02;
  const RgbdSlamOptions unset = RgbdSlamOptions::from_config(ConfigSection(IniFile::parse("", "a.ini"), ""));
  EXPECT_FALSE(unset.rolling_shutter_readout.has_value());
  EXPECT_EQ(for_sequence(unset, seq).rolling_shutter_readout, 0.02);
  const RgbdSlamOptions set =
      RgbdSlamOptions::from_config(ConfigSection(IniFile::parse("rolling_shutter_readout = 0.03\n", "b.ini"), ""));
  EXPECT_EQ(for_sequence(set, seq).rolling_shutter_readout, 0.03);
  const RgbdSlamOptions tutorial =
      RgbdSlamOptions::from_config(ConfigSection(IniFile::parse("preset = tutorial\n", "c.ini"), ""));
  EXPECT_EQ(for_sequence(tutorial, seq).rolling_shutter_readout, 0.0);
  EXPECT_EQ(named_camera("tum-fr1")->rolling_shutter_readout, 0.02);
  EXPECT_EQ(named_camera("icl-nuim")->rolling_shutter_readout, 0.0);
}

TEST(RgbdSlamOptions, MotionNormIsTheTutorials) {
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.3, 0.0, 0.4, 0.0, 0.2, 0.0;
  const SE3d T = SE3d(SE3d::exp(xi).rotation(), Eigen::Vector3d(0.3, 0.0, 0.4));
  EXPECT_NEAR(motion_norm(T), 0.2 + 0.5, 1e-12);
  xi << 0.0, 0.0, 0.0, 0.0, 0.0, 3.0;
  EXPECT_NEAR(motion_norm(SE3d::exp(xi)), 3.0, 1e-12);
}

}  // namespace
}  // namespace rove
