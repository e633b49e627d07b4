#include "rove/registration/voxel_size.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "synthetic_3d.h"

namespace rove {
namespace {

// Oracle: the count against a brute-force set of cell indices.
TEST(VoxelSize, CountMatchesDistinctCells) {
  const auto pts = test::room_3d(0.1);
  for (double leaf : {0.05, 0.1, 0.25, 1.0}) {
    std::vector<std::array<long, 3>> cells;
    for (const auto& p : pts) {
      cells.push_back({static_cast<long>(std::floor(p.x() / leaf)),
                       static_cast<long>(std::floor(p.y() / leaf)),
                       static_cast<long>(std::floor(p.z() / leaf))});
    }
    std::sort(cells.begin(), cells.end());
    const auto distinct = static_cast<std::size_t>(std::unique(cells.begin(), cells.end()) - cells.begin());
    EXPECT_EQ(count_occupied_voxels(pts, leaf), distinct) << leaf;
  }
}

TEST(VoxelSize, SuggestionIsTheFinestRoundLeafWithinTheBudget) {
  const auto pts = test::room_3d(0.05);
  for (std::size_t budget : {500u, 2000u, 8000u}) {
    const double v = suggest_voxel_size(pts, budget);
    ASSERT_GT(v, 0.0);
    EXPECT_LE(count_occupied_voxels(pts, v), budget) << v;
    // The next finer rung of the ladder exceeds the budget.
    const double finer[] = {0.01, 0.02, 0.025, 0.05, 0.1, 0.2, 0.25, 0.5, 1.0, 2.0, 2.5, 5.0};
    for (std::size_t i = 1; i < std::size(finer); ++i)
      if (finer[i] == v) {
        EXPECT_GT(count_occupied_voxels(pts, finer[i - 1]), budget) << v;
      }
  }
  // A cloud within the budget is not down-sampled; NaN points are ignored.
  std::vector<Eigen::Vector3f> few(100, Eigen::Vector3f::Zero());
  few.emplace_back(NAN, 0.0f, 0.0f);
  EXPECT_EQ(suggest_voxel_size(few, 100), 0.0);
  EXPECT_THROW(suggest_voxel_size(few, 0), InvalidArgument);
  EXPECT_THROW(count_occupied_voxels(few, 0.0), InvalidArgument);
}

}  // namespace
}  // namespace rove
