// load_mrpt_simplemap on MRPT's datasets (bundled in data/mrpt), compared with
// libmrpt's reading (tests/data/mrpt_*_simplemap_reference.txt).



#include "rove/io/mrpt_simplemap.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "rove/core/error.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/test_data.h"

namespace rove {
namespace {

const std::string kDatasets = test_data::bundled_file("mrpt/");
const std::string kTestData = ROVE_SOURCE_DIR "/modules/io/tests/data/";

void check_against_reference(const std::string& map_file, const std::string& reference) {
  ASSERT_TRUE(std::filesystem::exists(kDatasets + map_file))
      << "dataset missing: " << kDatasets + map_file;
  const SimpleMap map = load_mrpt_simplemap(kDatasets + map_file);
  std::ifstream in(kTestData + reference);
  ASSERT_TRUE(in.good()) << "cannot read " << reference;
  std::size_t checked = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    std::string kind;
    ls >> kind;
    if (kind == "N") {
      std::size_t n = 0;
      ls >> n;
      EXPECT_EQ(map.keyframes.size(), n);
      continue;
    }
    ASSERT_EQ(kind, "K");
    std::size_t k = 0;
    ls >> k;
    ASSERT_LT(k, map.keyframes.size());
    SCOPED_TRACE("keyframe " + std::to_string(k));
    const SimpleMapKeyframe& kf = map.keyframes[k];
    const Pose3& p = kf.pose.mean();
    double v[6];
    for (double& x : v) ls >> x;
    EXPECT_NEAR(p.x(), v[0], 1e-12);
    EXPECT_NEAR(p.y(), v[1], 1e-12);
    EXPECT_NEAR(p.z(), v[2], 1e-12);
    EXPECT_NEAR(p.yaw(), v[3], 1e-9);
    EXPECT_NEAR(p.pitch(), v[4], 1e-9);
    EXPECT_NEAR(p.roll(), v[5], 1e-9);
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) {
        double x = 0;
        ls >> x;
        EXPECT_NEAR(kf.pose.covariance()(r, c), x, 1e-12 + 1e-9 * std::abs(x));
      }
    }
    std::size_t frame_size = 0, rays = 0;
    std::uint64_t ticks = 0;
    float first = 0, last = 0;
    ls >> frame_size >> rays >> ticks >> first >> last;
    ASSERT_FALSE(ls.fail());
    ASSERT_EQ(kf.frame->size(), frame_size);
    const auto scan = kf.frame->find<RangeScan2D>();
    ASSERT_NE(scan, nullptr);
    ASSERT_EQ(scan->size(), rays);
    EXPECT_EQ(scan->timestamp.to_mrpt(), ticks);
    EXPECT_EQ(scan->ranges.front(), first);
    EXPECT_EQ(scan->ranges.back(), last);
    ++checked;
  }
  EXPECT_EQ(checked, 4u);
}

TEST(MrptSimpleMap, MalagaCsFacBuildingEqualsLibmrpt) {
  check_against_reference("malaga-cs-fac-building.simplemap.gz",
                          "mrpt_malaga_cs_fac_building_simplemap_reference.txt");
}

TEST(MrptSimpleMap, LocalizationDemoOldFormatEqualsLibmrpt) {
  // Written by MRPT < 0.5.5: old framing, CSensFrameProbSequence with 2D
  // poses, CSensorialFrame, CMatrix.
  check_against_reference("localization_demo.simplemap.gz",
                          "mrpt_localization_demo_simplemap_reference.txt");
}

TEST(MrptSimpleMap, NotASimpleMapIsAParseError) {
  const std::string rawlog =
      ROVE_SOURCE_DIR "/data/mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog";
  EXPECT_THROW(load_mrpt_simplemap(rawlog), ParseError);
}

}  // namespace
}  // namespace rove
