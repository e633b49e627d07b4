#include "rove/maps/point_map.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"

namespace rove {
namespace {

// A scan of a room-like contour: range varies smoothly with the angle.
RangeScan2D make_scan(std::size_t n = 181) {
  RangeScan2D s;
  std::vector<float> r(n);
  for (std::size_t i = 0; i < n; ++i) r[i] = 3.0f + std::sin(static_cast<float>(i) * 0.05f);
  s.set_ranges(r);
  s.aperture = kPi;
  return s;
}

TEST(PointMap, InsertsA2DScanAtARobotPoseLikeItsOwnProjection) {
  RangeScan2D s = make_scan();
  s.T_robot_sensor = Pose3(0.2, 0.0, 0.3, 0.1, 0, 0);
  s.valid[10] = false;
  PointMap map;
  map.insertion_options.min_dist_between_points = 0;  // keep every ray
  const Pose3 T(1.0, -2.0, 0.0, 0.7, 0, 0);
  ASSERT_TRUE(map.insert(s, T));
  const auto expect = s.points_3d(ScanFrame::Robot);
  ASSERT_EQ(map.size(), expect.size());
  for (std::size_t i = 0; i < expect.size(); ++i) {
    const Eigen::Vector3d g = T.rotation() * expect[i] + T.translation();
    EXPECT_NEAR((map.cloud()[i].cast<double>() - g).norm(), 0.0, 1e-5) << i;
  }
}

TEST(PointMap, MinDistanceKeepsFirstAndLastAndSpacing) {
  RangeScan2D s;
  s.set_ranges(std::vector<float>(101, 1.0f));  // 1 m circle, ray spacing pi/100 m ~ 0.0314
  PointMap map;
  map.insertion_options.min_dist_between_points = 0.05f;
  map.insert(s, Pose3());
  // every second ray passes (spacing 0.0628 > 0.05), plus the forced last point
  EXPECT_EQ(map.size(), 51u);
  for (std::size_t i = 1; i < map.size(); ++i)
    EXPECT_GT((map.cloud()[i] - map.cloud()[i - 1]).norm(), 0.05f - 1e-6f);
  // an invalid ray breaks the chain: the next valid ray is skipped
  s.valid[2] = false;
  PointMap m2;
  m2.insertion_options.min_dist_between_points = 0.01f;
  m2.insert(s, Pose3());
  EXPECT_EQ(m2.size(), 99u);  // ray 2 invalid, ray 3 dropped after it
}

TEST(PointMap, InterpolationFillsGapsAlongStraightRuns) {
  RangeScan2D s;
  std::vector<float> r(41);
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double a = -kPi / 2 + kPi * static_cast<double>(i) / 40.0;
    r[i] = static_cast<float>(2.0 / std::max(0.2, std::cos(a)));  // a wall at x = 2 (clipped)
  }
  s.set_ranges(r);
  s.max_range = 100;
  PointMap plain, interp;
  plain.insertion_options.min_dist_between_points = 0.05f;
  interp.insertion_options = plain.insertion_options;
  interp.insertion_options.also_interpolate = true;
  plain.insert(s, Pose3());
  interp.insert(s, Pose3());
  EXPECT_GT(interp.size(), plain.size());
  for (const auto& p : interp.cloud().points())
    if (std::fabs(p.y()) < 1.0f) {
      EXPECT_NEAR(p.x(), 2.0f, 1e-3f);  // added points lie on the wall
    }
}

TEST(PointMap, PlanarMapRefusesTiltedScans) {
  RangeScan2D s = make_scan();
  s.T_robot_sensor = Pose3(0, 0, 0, 0, 0.1, 0);
  PointMap map;
  map.insertion_options.is_planar_map = true;
  EXPECT_FALSE(map.insert(s, Pose3()));
  EXPECT_TRUE(map.empty());
  s.T_robot_sensor = Pose3();
  EXPECT_TRUE(map.insert(s, Pose3()));
}

TEST(PointMap, FusionAveragesInsteadOfGrowingAndDeletionClearsFreeSpace) {
  RangeScan2D s = make_scan();
  PointMap map;
  map.insertion_options.fuse_with_existing = true;
  map.insert(s, Pose3());
  const std::size_t n = map.size();
  map.insert(s, Pose3());
  EXPECT_EQ(map.size(), n);
  // a stale point inside the scanned area is deleted when deletion is on
  map.insertion_options.disable_deletion = false;
  map.insert_point({1.0f, 0.0f, 0.0f});
  map.insert_point({-10.0f, 0.0f, 0.0f});  // outside the scan polygon: kept
  map.insert(s, Pose3());
  EXPECT_EQ(map.size(), n + 1);
  EXPECT_FALSE(map.kdtree3().nearest(Eigen::Vector3f(1, 0, 0), 0.01f).has_value());
}

TEST(PointMap, LoadScanReplacesUnlessAddingToExisting) {
  RangeScan2D s = make_scan();
  PointMap map;
  map.load_scan(s, Pose3());
  const std::size_t n = map.size();
  map.load_scan(s, Pose3(1, 0, 0, 0, 0, 0));
  EXPECT_EQ(map.size(), 2 * n);
  map.insertion_options.add_to_existing = false;
  map.load_scan(s, Pose3());
  EXPECT_EQ(map.size(), n);
}

TEST(PointMap, LikelihoodPeaksAtTheTruePoseAndMatchesBruteForce) {
  RangeScan2D s = make_scan();
  PointMap map;
  map.insertion_options.min_dist_between_points = 0;
  const Pose3 truth(0.5, 0.2, 0, 0.3, 0, 0);
  map.insert(s, truth);
  const double at_truth = map.log_likelihood(s, truth);
  EXPECT_NEAR(at_truth, 0.0, 1e-6);
  const Pose3 off(0.6, 0.2, 0, 0.3, 0, 0);
  const double at_off = map.log_likelihood(s, off);
  EXPECT_LT(at_off, at_truth);
  // brute force: default insertion options, decimation 10, XY distances
  const auto pts = detail::scan_points(s, Pose3(), PointMapInsertionOptions{}, nullptr);
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < pts.size(); i += 10, ++n) {
    const Eigen::Vector3d g = off.rotation() * pts[i].cast<double>() + off.translation();
    double best = 1e30;
    for (const auto& q : map.cloud().points())
      best = std::min(best, (g.head<2>() - q.head<2>().cast<double>()).squaredNorm());
    sum += std::min(best, 1.0);
  }
  EXPECT_NEAR(at_off, -(sum / n) / 0.0025, 1e-3 * std::fabs(at_off));
  PointMap empty;
  EXPECT_EQ(empty.log_likelihood(s, truth), -100.0);
}

TEST(PointMap, KdTreeFollowsChangesTransformAndClip) {
  PointMap map;
  map.insert_point({1, 2, 3});
  EXPECT_EQ(map.kdtree3().size(), 1u);
  map.insert_point({5, 5, 5});
  EXPECT_EQ(map.kdtree3().nearest(Eigen::Vector3f(5, 5, 4.9f))->index, 1u);
  EXPECT_EQ(map.kdtree2().size(), 2u);
  const Pose3 T(1, 2, 3, 0.4, 0.2, -0.1);
  PointMap moved = map;
  moved.transform(T);
  moved.change_frame(T);  // back to the original frame
  for (std::size_t i = 0; i < map.size(); ++i)
    EXPECT_NEAR((moved.cloud()[i] - map.cloud()[i]).norm(), 0.0f, 1e-5f);
  BoundingBox3 box;
  box.min = Eigen::Vector3f(0, 0, 0);
  box.max = Eigen::Vector3f(2, 2, 3);
  map.clip(box);
  EXPECT_EQ(map.size(), 1u);
  EXPECT_EQ(map.kdtree3().size(), 1u);
  EXPECT_EQ(map.bounding_box().min, Eigen::Vector3f(1, 2, 3));
}

TEST(PointMap, IntensityChannelFromScanIntensities) {
  RangeScan2D s = make_scan(11);
  s.intensity.assign(11, 0);
  for (int i = 0; i < 11; ++i) s.intensity[static_cast<std::size_t>(i)] = i * 10;
  PointMap map(PointChannels::Intensity);
  map.insertion_options.min_dist_between_points = 0;
  map.insert(s, Pose3());
  ASSERT_EQ(map.size(), 11u);
  EXPECT_EQ(map.cloud().intensities()[7], 70.0f);
}

}  // namespace
}  // namespace rove
