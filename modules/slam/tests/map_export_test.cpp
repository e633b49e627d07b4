#include "rove/slam/map_export.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <algorithm>
#include <map>
#include <utility>
#include <vector>

#include "rove/core/error.h"
#include "rove/io/gray_image.h"

namespace rove {
namespace {

// The points picture is a palette PNG; read back through rove's reader
// (palette expanded, R, G, B averaged) each colour has its own gray level:
// white 255, points (40, 40, 40) 40, path (220, 30, 30) 93, start
// (0, 170, 0) 57, end (0, 0, 220) 73 (±1 for the reader's rounding).
TEST(RenderPointsPng, DrawsPointsPathAndMarkersInTheirColours) {
  // Pixel centres (5 cm pixels, 1 m margin): points well away from the path
  // and from each other, the path along y = 0.
  PointCloud cloud({{0.0125f, 1.0125f, 0.0f}, {2.0125f, 1.0125f, 0.0f}, {1.0125f, -0.9875f, 0.5f}});
  const std::vector<Pose2> path = {Pose2(0.0125, 0.0125, 0.0), Pose2(1.0125, 0.0125, 0.0),
                                   Pose2(2.0125, 0.0125, 0.0)};
  const auto file = (std::filesystem::temp_directory_path() / "rove_points_picture.png").string();
  render_points_png(file, cloud, path);
  const GrayImage img = read_gray_image(file);
  std::filesystem::remove(file);
  // Content spans 4 m each way with the margin: 80 px (81 when the
  // division rounds up).
  EXPECT_NEAR(img.width, 80, 1);
  EXPECT_NEAR(img.height, 80, 1);
  std::map<int, int> count;                  // gray level (to ±1) -> pixels
  std::map<int, std::pair<double, double>> sum;  // level -> sum of (u, v)
  std::vector<std::pair<int, int>> dark;
  for (std::uint32_t v = 0; v < img.height; ++v) {
    for (std::uint32_t u = 0; u < img.width; ++u) {
      int level = img.at(u, v);
      for (int c : {255, 40, 93, 57, 73})
        if (std::abs(level - c) <= 1) level = c;
      ++count[level];
      sum[level].first += u;
      sum[level].second += v;
      if (level == 40) dark.emplace_back(static_cast<int>(u), static_cast<int>(v));
    }
  }
  EXPECT_EQ(count[40], 3);           // one pixel per point
  EXPECT_EQ(count[57], 7 * 7);       // start marker, radius 3
  EXPECT_EQ(count[73], 7 * 7);       // end marker
  EXPECT_EQ(count[93], 41 - 2 * 4);  // the path's 41 pixels less those under the markers
  EXPECT_EQ(count[255] + count[40] + count[57] + count[73] + count[93],
            static_cast<int>(img.width * img.height));
  // +x right, +y up: the end marker 40 px right of the start, the points
  // 20 px above the start and the end, and 20 px below the middle.
  const double su = sum[57].first / 49, sv = sum[57].second / 49;
  const double eu = sum[73].first / 49, ev = sum[73].second / 49;
  EXPECT_NEAR(eu - su, 40, 1);
  EXPECT_NEAR(ev, sv, 0.5);
  ASSERT_EQ(dark.size(), 3u);
  std::sort(dark.begin(), dark.end(), [](auto a, auto b) { return a.first < b.first; });
  EXPECT_NEAR(dark[0].first, su, 1);
  EXPECT_NEAR(dark[0].second, sv - 20, 1);
  EXPECT_NEAR(dark[1].first, su + 20, 1);
  EXPECT_NEAR(dark[1].second, sv + 20, 1);
  EXPECT_NEAR(dark[2].first, eu, 1);
  EXPECT_NEAR(dark[2].second, ev - 20, 1);
}

TEST(RenderPointsPng, UnwritablePathIsAnIoError) {
  PointCloud cloud({{0.0f, 0.0f, 0.0f}});
  EXPECT_THROW(render_points_png("/nonexistent-dir/points.png", cloud, {}), IoError);
}

}  // namespace
}  // namespace rove
