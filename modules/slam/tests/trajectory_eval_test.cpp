#include "rove/slam/trajectory_eval.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "rove/core/error.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

AteOptions aligned_by(TrajectoryAlignment alignment) {
  AteOptions o;
  o.alignment = alignment;
  return o;
}

RpeOptions rpe_over(double delta, RpeUnit unit = RpeUnit::Frames, double scale = 1.0) {
  RpeOptions o;
  o.delta = delta;
  o.unit = unit;
  o.scale = scale;
  return o;
}

SE3d pose_xy_yaw(double x, double y, double yaw) {
  return SE3d(Eigen::Matrix3d(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
              Eigen::Vector3d(x, y, 0));
}

/// A wavy 3D path, one pose per 0.1 s from t0.
std::vector<StampedPose3> wavy_path(std::size_t n, double t0 = 100.0) {
  std::vector<StampedPose3> p;
  for (std::size_t k = 0; k < n; ++k) {
    const double s = 0.1 * static_cast<double>(k);
    const Eigen::Matrix3d R =
        Eigen::Matrix3d(Eigen::AngleAxisd(0.3 * s, Eigen::Vector3d::UnitZ()) *
                        Eigen::AngleAxisd(0.1 * std::sin(s), Eigen::Vector3d::UnitX()));
    p.push_back({t0 + s, SE3d(R, Eigen::Vector3d(2 * std::cos(s), 3 * std::sin(0.5 * s), 0.2 * s))});
  }
  return p;
}

TEST(TrajectoryEval, ErrorStatisticsByHand) {
  const ErrorStatistics s = error_statistics({4, 1, 3, 2});
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.sse, 30.0);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.stddev, std::sqrt(1.25));
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 4.0);
  EXPECT_DOUBLE_EQ(error_statistics({3, 1, 2}).median, 2.0);
  EXPECT_EQ(error_statistics({}).count, 0u);
  EXPECT_THROW(error_statistics({1, std::nan("")}), InvalidArgument);
}

TEST(TrajectoryEval, AssociationTakesClosestPairsOneToOne) {
  const std::vector<StampedPose3> ref = {{1.000, {}}, {1.100, {}}, {1.200, {}}, {5.0, {}}};
  // 1.104 and 1.097 both want 1.100: the closer (1.097, diff 0.003) wins
  // it; 1.104 then has nothing within 0.01. 3.0 is far from everything.
  const std::vector<StampedPose3> est = {{1.104, {}}, {1.097, {}}, {1.205, {}}, {3.0, {}}, {0.995, {}}};
  const TrajectoryAssociation a = associate_by_time(ref, est, AssociationOptions{0.01, 0.0});
  ASSERT_EQ(a.pairs.size(), 3u);
  // In the estimate's time order: 0.995→1.000, 1.097→1.100, 1.205→1.200.
  EXPECT_EQ(a.pairs[0], std::make_pair(std::size_t{0}, std::size_t{4}));
  EXPECT_EQ(a.pairs[1], std::make_pair(std::size_t{1}, std::size_t{1}));
  EXPECT_EQ(a.pairs[2], std::make_pair(std::size_t{2}, std::size_t{2}));
  ASSERT_EQ(a.unmatched_estimate_times.size(), 2u);
  EXPECT_EQ(a.unmatched_estimate_times[0], 1.104);
  EXPECT_EQ(a.unmatched_estimate_times[1], 3.0);
  // An offset moves the estimate onto the reference.
  const auto shifted = associate_by_time(ref, {{4.0, {}}}, AssociationOptions{0.01, 1.0});
  ASSERT_EQ(shifted.pairs.size(), 1u);
  EXPECT_EQ(shifted.pairs[0].first, 3u);
  EXPECT_THROW(associate_by_time(ref, est, AssociationOptions{-1.0, 0.0}), InvalidArgument);
}

TEST(TrajectoryEval, AteByHandWithoutAndWithAlignment) {
  // The estimate is the reference shifted 0.1 m in y: unaligned every
  // error is 0.1 m, aligned (SE3 or SE2) it is 0.
  std::vector<StampedPose3> ref, est;
  for (int k = 0; k < 5; ++k) {
    ref.push_back({double(k), pose_xy_yaw(k, 0.5 * k * k, 0.1 * k)});
    est.push_back({double(k), pose_xy_yaw(k, 0.5 * k * k + 0.1, 0.1 * k)});
  }
  const AteResult none = absolute_trajectory_error(ref, est, aligned_by(TrajectoryAlignment::None));
  EXPECT_EQ(none.translation.count, 5u);
  EXPECT_NEAR(none.translation.rmse, 0.1, 1e-12);
  EXPECT_NEAR(none.translation.max, 0.1, 1e-12);
  EXPECT_NEAR(none.rotation.max, 0.0, 1e-12);
  for (const auto alignment : {TrajectoryAlignment::SE3, TrajectoryAlignment::SE2}) {
    const AteResult a = absolute_trajectory_error(ref, est, aligned_by(alignment));
    EXPECT_NEAR(a.translation.max, 0.0, 1e-9) << to_string(alignment);
    EXPECT_NEAR(a.transform.T_reference_estimate.translation().y(), -0.1, 1e-9);
  }
  // A rotation error by hand: one pose turned by 3 degrees.
  est[2].pose = pose_xy_yaw(2, 2.1, 0.2 + 3 * kDeg);
  const AteResult r = absolute_trajectory_error(ref, est, aligned_by(TrajectoryAlignment::None));
  EXPECT_NEAR(r.rotation.max, 3 * kDeg, 1e-12);
  EXPECT_NEAR(r.rotation.mean, 3 * kDeg / 5, 1e-12);
}

TEST(TrajectoryEval, AteReportsHowFarThePositionsSpread) {
  // Positions at ±1 m on x and ±2 m on y: RMS distance from the centroid
  // sqrt((1 + 4 + 1 + 4) / 4) = sqrt(2.5).
  std::vector<StampedPose3> ref, est;
  const double xy[4][2] = {{1, 0}, {-1, 0}, {0, 2}, {0, -2}};
  for (int k = 0; k < 4; ++k) {
    ref.push_back({double(k), pose_xy_yaw(5 + xy[k][0], 7 + xy[k][1], 0.3 * k)});
    est.push_back({double(k), pose_xy_yaw(xy[k][0], xy[k][1], 0.3 * k)});
  }
  const AteResult a = absolute_trajectory_error(ref, est, aligned_by(TrajectoryAlignment::SE3));
  EXPECT_NEAR(a.position_spread, std::sqrt(2.5), 1e-12);
  // A camera turning in place (positions within a millimetre, the estimate's
  // orientations 5 degrees off): the alignment cannot see the rotation from
  // the positions, and the spread says so.
  ref.clear();
  est.clear();
  for (int k = 0; k < 10; ++k) {
    ref.push_back({double(k), pose_xy_yaw(1e-4 * (k % 3), 1e-4 * (k % 2), 0.2 * k)});
    est.push_back({double(k), pose_xy_yaw(1e-4 * (k % 3), 1e-4 * (k % 2), 0.2 * k + 5 * kDeg)});
  }
  const AteResult b = absolute_trajectory_error(ref, est, aligned_by(TrajectoryAlignment::SE3));
  EXPECT_LT(b.position_spread, 1e-3);
  EXPECT_NEAR(b.rotation.mean, 5 * kDeg, 1e-6);
}

TEST(TrajectoryEval, AlignedAteIsInvariantToTheEstimatesFrame) {
  const auto ref = wavy_path(80);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.03);
  std::vector<StampedPose3> est = ref;
  for (auto& p : est) p.pose = SE3d(p.pose.rotation(), p.pose.translation() + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  const AteResult a = absolute_trajectory_error(ref, est);
  // The same estimate expressed in another frame (and, for Sim3, scale).
  const SE3d G(Eigen::Matrix3d(Eigen::AngleAxisd(1.2, Eigen::Vector3d(0.3, -1, 0.4).normalized())),
               Eigen::Vector3d(10, -4, 7));
  std::vector<StampedPose3> moved = est;
  for (auto& p : moved) p.pose = G * p.pose;
  const AteResult b = absolute_trajectory_error(ref, moved);
  EXPECT_NEAR(a.translation.rmse, b.translation.rmse, 1e-9);
  EXPECT_NEAR(a.rotation.rmse, b.rotation.rmse, 1e-9);
  EXPECT_GT(a.translation.rmse, 0.02);
  EXPECT_LT(a.translation.rmse, 0.08);
  // Unaligned it is the frame change that dominates.
  EXPECT_GT(absolute_trajectory_error(ref, moved, aligned_by(TrajectoryAlignment::None)).translation.rmse, 5.0);

  std::vector<StampedPose3> scaled = est;
  for (auto& p : scaled) p.pose = SE3d(p.pose.rotation(), 0.25 * (G * p.pose).translation());
  const AteResult s = absolute_trajectory_error(ref, scaled, aligned_by(TrajectoryAlignment::Sim3));
  EXPECT_NEAR(s.transform.scale, 4.0, 0.05);
  EXPECT_LT(s.translation.rmse, 0.08);
}

TEST(TrajectoryEval, AteSe2KeepsZAndRollPitch) {
  // A planar estimate rotated 30 degrees about z and shifted: SE2 recovers
  // the rigid change exactly.
  std::vector<StampedPose3> ref, est;
  const SE3d G = pose_xy_yaw(3, -2, 30 * kDeg);
  for (int k = 0; k < 10; ++k) {
    ref.push_back({double(k), pose_xy_yaw(std::cos(k), std::sin(2.0 * k), 0.3 * k)});
    est.push_back({double(k), G * ref.back().pose});
  }
  const AteResult a = absolute_trajectory_error(ref, est, aligned_by(TrajectoryAlignment::SE2));
  EXPECT_NEAR(a.translation.max, 0.0, 1e-9);
  EXPECT_NEAR(a.rotation.max, 0.0, 1e-9);
  EXPECT_NEAR(a.transform.T_reference_estimate.translation().z(), 0.0, 0.0);
}

TEST(TrajectoryEval, AteNamesWhatDidNotAssociate) {
  const auto ref = wavy_path(10, 100.0);
  const auto est = wavy_path(10, 200.0);
  try {
    absolute_trajectory_error(ref, est);
    FAIL();
  } catch (const InvalidArgument& e) {
    const std::string m = e.message();
    EXPECT_NE(m.find("t 100.000000 .. 100.900000"), std::string::npos) << m;
    EXPECT_NE(m.find("t 200.000000 .. 200.900000"), std::string::npos) << m;
  }
}

TEST(TrajectoryEval, RpeByHand) {
  // The estimate drifts in scale: each 1 m step of the reference is 1.1 m.
  // A second estimate drifts in heading, 1 degree a step.
  std::vector<StampedPose3> ref, est, turning;
  for (int k = 0; k < 6; ++k) {
    ref.push_back({double(k), pose_xy_yaw(k, 0, 0)});
    est.push_back({double(k), pose_xy_yaw(1.1 * k, 0, 0)});
    turning.push_back({double(k), pose_xy_yaw(k, 0, k * kDeg)});
  }
  const RpeResult f = relative_pose_error(ref, est);
  EXPECT_EQ(f.intervals.size(), 5u);
  EXPECT_NEAR(f.translation.mean, 0.1, 1e-12);
  EXPECT_NEAR(f.translation.stddev, 0.0, 1e-12);
  EXPECT_NEAR(f.rotation.max, 0.0, 1e-12);
  EXPECT_NEAR(relative_pose_error(ref, turning).rotation.min, 1 * kDeg, 1e-12);
  EXPECT_NEAR(relative_pose_error(ref, turning).rotation.max, 1 * kDeg, 1e-12);
  // Two meters (or two seconds) apart: j − i = 2, error 0.2 m, 2 degrees.
  for (const RpeUnit unit : {RpeUnit::Meters, RpeUnit::Seconds}) {
    const RpeResult r = relative_pose_error(ref, est, rpe_over(2, unit));
    EXPECT_EQ(r.intervals.size(), 4u) << to_string(unit);
    EXPECT_EQ(r.intervals[0], std::make_pair(std::size_t{0}, std::size_t{2}));
    EXPECT_NEAR(r.translation.mean, 0.2, 1e-12);
    EXPECT_NEAR(relative_pose_error(ref, turning, rpe_over(2, unit)).rotation.mean, 2 * kDeg,
                1e-12);
  }
  // The scale option undoes the drift of the translations.
  EXPECT_NEAR(relative_pose_error(ref, est, rpe_over(1, RpeUnit::Frames, 1 / 1.1)).translation.max, 0.0, 1e-12);
  // RPE does not depend on the estimate's frame.
  std::vector<StampedPose3> moved = est;
  for (auto& p : moved) p.pose = pose_xy_yaw(5, 6, 1.0) * p.pose;
  EXPECT_NEAR(relative_pose_error(ref, moved).translation.rmse, f.translation.rmse, 1e-12);
  EXPECT_THROW(relative_pose_error(ref, est, rpe_over(10)), InvalidArgument);
  EXPECT_THROW(relative_pose_error(ref, est, rpe_over(1.5)), InvalidArgument);
  EXPECT_THROW(relative_pose_error(ref, est, rpe_over(0)), InvalidArgument);
}

TEST(TrajectoryEval, RelationErrorByHand) {
  std::vector<StampedPose3> est;
  for (int k = 0; k < 4; ++k) est.push_back({10.0 + k, pose_xy_yaw(k, 0, 0)});
  // Relations: exact (0 error), 5 cm and 2 degrees off, and one whose
  // second time is not in the estimate.
  const std::vector<PoseRelation> rel = {
      {10.0, 11.0, pose_xy_yaw(1, 0, 0)},
      {11.0, 13.0, pose_xy_yaw(2, 0.05, 2 * kDeg)},
      {12.0, 17.5, pose_xy_yaw(1, 0, 0)},
  };
  const RelationResult r = relation_error(est, rel);
  EXPECT_EQ(r.relations, 3u);
  EXPECT_EQ(r.used, 2u);
  ASSERT_EQ(r.missing_times.size(), 1u);
  EXPECT_EQ(r.missing_times[0], 17.5);
  EXPECT_NEAR(r.rotation.max, 2 * kDeg, 1e-12);
  EXPECT_NEAR(r.rotation.mean, 1 * kDeg, 1e-12);
  // δ*⁻¹·δ with δ* = (2, 0.05, 2°), δ = (2, 0, 0): the error's translation
  // is R(−2°)·(0, −0.05), of length 0.05.
  EXPECT_NEAR(r.translation.max, 0.05, 1e-12);
  EXPECT_NEAR(r.translation.mean, 0.025, 1e-12);
  EXPECT_NEAR(r.translation_squared.mean, 0.05 * 0.05 / 2, 1e-14);
  // Nothing usable: an error naming the times.
  try {
    relation_error(est, {{50.0, 51.0, SE3d()}});
    FAIL();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(e.message().find("50.000000, 51.000000"), std::string::npos) << e.message();
  }
}

TEST(TrajectoryEval, RelationTimesMoveToTheEstimatesClock) {
  const std::vector<PoseRelation> rel = {{100.0004, 101.0, SE3d()}, {101.0, 250.0, SE3d()}};
  const std::vector<ClockPair> clock = {{101.0, 11.0}, {100.0, 10.0}, {102.0, 12.0}};
  const auto m = map_relation_times(rel, clock, 1e-3);
  EXPECT_EQ(m[0].t1, 10.0);
  EXPECT_EQ(m[0].t2, 11.0);
  EXPECT_EQ(m[1].t1, 11.0);
  EXPECT_EQ(m[1].t2, 250.0);  // not on the clock: kept, later reported missing
  EXPECT_THROW(map_relation_times(rel, clock, -1.0), InvalidArgument);
}

TEST(TrajectoryEval, AlignmentAndUnitNames) {
  for (const auto a : {TrajectoryAlignment::None, TrajectoryAlignment::SE3, TrajectoryAlignment::SE2,
                       TrajectoryAlignment::Sim3})
    EXPECT_EQ(parse_trajectory_alignment(to_string(a)), a);
  for (const auto u : {RpeUnit::Frames, RpeUnit::Meters, RpeUnit::Seconds})
    EXPECT_EQ(parse_rpe_unit(to_string(u)), u);
  EXPECT_THROW(parse_trajectory_alignment("sim2"), InvalidArgument);
  EXPECT_THROW(parse_rpe_unit("km"), InvalidArgument);
}

}  // namespace
}  // namespace rove
