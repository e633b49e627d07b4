// The grid planners on MRPT's own planning example: the Malaga campus map,
// a robot of radius 0.30 m, from (20, −110) to (90, 40).
#include <gtest/gtest.h>

#include "rove/io/mrpt_gridmap.h"
#include "rove/nav/grid_planner.h"
#include "rove/test_data.h"

namespace rove {
namespace {

// MRPT 2.5.8's PlannerSimple2D (robotRadius 0.30, other options at their
// defaults) on the same map and query: the length of its path from the
// origin through every point it returns, as printed by (bench preset,
// ROVE_BUILD_PEER_TOOLS=ON)
//   rove_mrpt_nav_reference 2006-MalagaCampus.gridmap.gz 0.30 20 -110 90 40
// ("points 416 length 194.949180 m").
constexpr double kMrptLength = 194.949180;

const NavigationGrid& malaga() {
  static const NavigationGrid g = NavigationGrid::from_occupancy(
      load_mrpt_gridmap(test_data::shared_dataset("mrpt/2006-MalagaCampus.gridmap.gz")).grid);
  return g;
}

// Every cell each segment of the path passes through is farther than the
// radius from every obstacle.
void expect_clear(const NavigationGrid& g, const GridPath& p, double radius) {
  for (std::size_t i = 1; i < p.poses.size(); ++i) {
    EXPECT_GT(g.segment_clearance(p.poses[i - 1].translation(), p.poses[i].translation()), radius)
        << "segment " << i;
  }
  EXPECT_GT(p.min_clearance, radius);
}

TEST(GridPlannerDatasets, MalagaValueIterationMatchesMrpt) {
  GridPlannerOptions o;
  o.robot_radius = 0.30;
  const GridPlanResult r = plan_path(malaga(), SE2d(20, -110, 0), SE2d(90, 40, 0), o);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_NEAR(r.path.length, kMrptLength, 0.01 * kMrptLength);
  expect_clear(malaga(), r.path, o.robot_radius);
  EXPECT_TRUE(r.path.poses.front().is_approx(SE2d(20, -110, 0)));
  EXPECT_TRUE(r.path.poses.back().is_approx(SE2d(90, 40, 0)));
}

TEST(GridPlannerDatasets, MalagaAStarIsNoLongerThanValueIteration) {
  GridPlannerOptions o;
  o.robot_radius = 0.30;
  const GridPlanResult vi = plan_path(malaga(), SE2d(20, -110, 0), SE2d(90, 40, 0), o);
  ASSERT_TRUE(vi.ok()) << vi.message;
  o.method = GridPlannerMethod::AStar;
  for (const bool simplify : {false, true}) {
    for (const double w : {0.0, 1.0}) {
      o.simplify = simplify;
      o.clearance_weight = w;
      const GridPlanResult r = plan_path(malaga(), SE2d(20, -110, 0), SE2d(90, 40, 0), o);
      ASSERT_TRUE(r.ok()) << r.message;
      EXPECT_LE(r.path.length, vi.path.length) << "simplify " << simplify << " weight " << w;
      expect_clear(malaga(), r.path, o.robot_radius);
    }
  }
}

TEST(GridPlannerDatasets, MalagaRobotWiderThanEveryCorridorHasNoPath) {
  // Both ends lie in open places (4.2 m and 3.2 m from the nearest
  // obstacle) but every way between them is narrower than 3.6 m.
  GridPlannerOptions o;
  o.robot_radius = 1.8;
  for (const auto method : {GridPlannerMethod::ValueIteration, GridPlannerMethod::AStar}) {
    o.method = method;
    const GridPlanResult r = plan_path(malaga(), SE2d(19.5, -103, 0), SE2d(90, 40, 0), o);
    EXPECT_EQ(r.termination, PlanTermination::NoPath) << r.message;
    EXPECT_NE(r.message.find("no path"), std::string::npos);
  }
  o.robot_radius = 1.2;
  EXPECT_TRUE(plan_path(malaga(), SE2d(19.5, -103, 0), SE2d(90, 40, 0), o).ok());
}

}  // namespace
}  // namespace rove
