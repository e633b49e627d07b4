// The scans of a map against each other (rove/slam/scan_consistency.h): the
// simulated building's loop at its true poses, and along an odometry that
// drifts, whose return overlays the first pass at an angle.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "rove/core/error.h"
#include "rove/slam/scan_consistency.h"
#include "sim_building.h"

namespace rove {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct Loop {
  std::vector<Pose2> truth;
  std::vector<RangeScan2D> scans;
};

// Every fifth pose of the loop around the block (a scan each 1 m or turn).
Loop loop() {
  const auto walls = test::building(Eigen::Vector2d::Zero());
  const std::vector<Pose2> path = test::loop_path(Eigen::Vector2d::Zero());
  std::mt19937_64 rng(3);
  std::normal_distribution<double> unit(0.0, 1.0);
  Loop l;
  for (std::size_t k = 0; k < path.size(); k += 5) {
    l.truth.push_back(path[k]);
    l.scans.push_back(test::simulate_scan(walls, path[k], 0.01, unit, rng));
  }
  // Past the start again, so that the return overlaps the first scans.
  for (std::size_t k = 0; k < 30; k += 5) {
    l.truth.push_back(path[k]);
    l.scans.push_back(test::simulate_scan(walls, path[k], 0.01, unit, rng));
  }
  return l;
}

std::vector<PosedScan> posed(const std::vector<Pose2>& poses, const std::vector<RangeScan2D>& scans) {
  std::vector<PosedScan> out;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    out.push_back({SE2d(poses[k].x(), poses[k].y(), poses[k].phi()), &scans[k]});
  }
  return out;
}

TEST(ScanConsistency, TruePosesAgreeADriftingPathDoesNot) {
  const Loop l = loop();
  const ScanConsistency truth = scan_consistency(posed(l.truth, l.scans));
  ASSERT_EQ(truth.through_walls.size(), l.scans.size());
  EXPECT_EQ(truth.through_walls[0], 0.0);
  EXPECT_EQ(truth.checked, l.scans.size() - 1);
  EXPECT_EQ(truth.contradicted, 0u);
  EXPECT_FALSE(truth.flagged());
  // The same scans along a path that turns 2° too far per meter: 56 m
  // later the return lies meters and degrees off the first pass.
  std::vector<Pose2> drift{l.truth[0]};
  for (std::size_t k = 1; k < l.truth.size(); ++k) {
    const Pose2 step = l.truth[k] - l.truth[k - 1];
    drift.push_back(drift.back() + Pose2(step.x(), step.y(), step.phi() + 2.0 * kDeg * step.norm()));
  }
  const ScanConsistency drifted = scan_consistency(posed(drift, l.scans));
  std::printf("true poses: %zu of %zu contradicted; drifting: %zu of %zu\n", truth.contradicted,
              truth.checked, drifted.contradicted, drifted.checked);
  EXPECT_TRUE(drifted.flagged());
  EXPECT_GE(drifted.contradicted, kMinContradicted);
  // The first leg is still consistent (drift is small there).
  for (std::size_t k = 1; k < 10; ++k) EXPECT_LE(drifted.through_walls[k], kContradictedRays) << k;
}

// Scans kilometers apart: the grid coarsens to fit kMaxReplayTiles, and
// beyond kMaxCoarsening the scans are left unchecked (resolution 0).
TEST(ScanConsistency, FarApartScansCoarsenTheGridOrAreNotChecked) {
  const Loop l = loop();
  const ScanConsistency near = scan_consistency(posed(l.truth, l.scans));
  EXPECT_FLOAT_EQ(static_cast<float>(near.resolution), 0.05f);
  // The loop, then the same loop 2 km north-east: a bounding box of about
  // 1,300 × 1,300 tiles at 5 cm, 160 × 160 at 0.4 m.
  std::vector<Pose2> poses = l.truth;
  std::vector<RangeScan2D> scans = l.scans;
  for (std::size_t k = 0; k < l.truth.size(); ++k) {
    poses.emplace_back(l.truth[k].x() + 2000.0, l.truth[k].y() + 2000.0, l.truth[k].phi());
    scans.push_back(l.scans[k]);
  }
  const ScanConsistency far = scan_consistency(posed(poses, scans));
  EXPECT_FLOAT_EQ(static_cast<float>(far.resolution), 0.4f);
  EXPECT_EQ(far.checked, scans.size() - 1);
  EXPECT_FALSE(far.flagged());
  // 100 km apart: not checked.
  poses.back() = Pose2(1e5, 1e5, 0.0);
  const ScanConsistency too_far = scan_consistency(posed(poses, scans));
  EXPECT_EQ(too_far.resolution, 0.0);
  EXPECT_EQ(too_far.checked, 0u);
  EXPECT_EQ(too_far.through_walls.size(), scans.size());
  EXPECT_FALSE(too_far.flagged());
}

TEST(ScanConsistency, RunDecision) {
  EXPECT_FALSE(contradicted_run(0, 0));
  EXPECT_FALSE(contradicted_run(2, 5));   // under kMinContradicted
  EXPECT_TRUE(contradicted_run(3, 5));
  EXPECT_FALSE(contradicted_run(10, 100));  // at the share: not above it
  EXPECT_TRUE(contradicted_run(11, 100));
}

TEST(ScanConsistency, RefusesBadInput) {
  const Loop l = loop();
  std::vector<PosedScan> one = posed({l.truth[0]}, l.scans);
  const ScanConsistency single = scan_consistency(one);
  EXPECT_EQ(single.checked, 0u);
  EXPECT_FALSE(single.flagged());
  EXPECT_EQ(scan_consistency({}).through_walls.size(), 0u);
  EXPECT_THROW(scan_consistency(one, 0.0f), InvalidArgument);
  EXPECT_THROW(scan_consistency(one, std::nanf("")), InvalidArgument);
  std::vector<PosedScan> null_scan{{SE2d(), nullptr}};
  EXPECT_THROW(scan_consistency(null_scan), InvalidArgument);
}

}  // namespace
}  // namespace rove
