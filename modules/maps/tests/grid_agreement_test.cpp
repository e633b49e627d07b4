// grid_agreement on hand-made grids: a map equal to its reference, a wall
// moved by one cell (within tolerance), a doubled wall, and walls the
// reference never saw.

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/maps/grid_agreement.h"
#include "rove/maps/occupancy_grid.h"

namespace rove {
namespace {

// A 20 × 20-cell room of 0.1 m cells: free inside, a wall along column `wall_x`.
OccupancyGrid room(int wall_x, float outside = 0.5f) {
  OccupancyGrid g(0, 2, 0, 2, 0.1f, outside);
  for (int y = 0; y < 20; ++y) {
    for (int x = 2; x < 18; ++x) g.set_free_probability(x, y, x == wall_x ? 0.05f : 0.95f);
  }
  return g;
}

TEST(GridAgreement, CountsAgreeingCellsAndMatchedWalls) {
  const OccupancyGrid ref = room(10);
  const GridAgreement same = grid_agreement(ref, ref);
  EXPECT_EQ(same.compared, 16u * 20u);
  EXPECT_EQ(same.agreeing, same.compared);
  EXPECT_EQ(same.occupied, 20u);
  EXPECT_DOUBLE_EQ(same.wall_agreement(), 1.0);
  EXPECT_DOUBLE_EQ(same.known_wall_agreement(), 1.0);

  // A wall one cell off: 2 × 20 cells disagree, every wall cell is matched.
  const GridAgreement shifted = grid_agreement(room(11), ref);
  EXPECT_EQ(shifted.compared - shifted.agreeing, 40u);
  EXPECT_DOUBLE_EQ(shifted.wall_agreement(), 1.0);

  // A doubled wall (a second one 5 cells away): half the walls unmatched.
  OccupancyGrid doubled = room(10);
  for (int y = 0; y < 20; ++y) doubled.set_free_probability(15, y, 0.05f);
  const GridAgreement d = grid_agreement(doubled, ref);
  EXPECT_EQ(d.occupied, 40u);
  EXPECT_EQ(d.occupied_matched, 20u);
  EXPECT_DOUBLE_EQ(d.known_wall_agreement(), 0.5);

  // Walls where the reference saw nothing lower wall_agreement only.
  OccupancyGrid beyond = room(10, 0.05f);  // columns 0-1 and 18-19 "occupied"
  const GridAgreement b = grid_agreement(beyond, ref);
  EXPECT_EQ(b.occupied, 100u);
  EXPECT_EQ(b.occupied_known, 20u);
  EXPECT_DOUBLE_EQ(b.known_wall_agreement(), 1.0);
  EXPECT_LT(b.wall_agreement(), 0.5);
}

TEST(GridAgreement, RejectsOptionsOutOfRange) {
  const OccupancyGrid g = room(10);
  GridAgreementOptions o;
  o.known_margin = 0.5;
  EXPECT_THROW(grid_agreement(g, g, o), InvalidArgument);
  o.known_margin = 0.1;
  o.wall_tolerance_cells = -1;
  EXPECT_THROW(grid_agreement(g, g, o), InvalidArgument);
}

}  // namespace
}  // namespace rove
