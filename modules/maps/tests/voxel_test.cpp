#include "rove/maps/voxel_grid.h"

#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "rove/core/error.h"
#include "rove/maps/pass_through.h"
#include "rove/maps/point_cloud_sampling.h"
#include "rove/maps_oracles.h"

namespace rove {
namespace {

TEST(VoxelGrid, MatchesTheOracleOnRandomClouds) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-7, 7);
  PointCloud c;
  for (int i = 0; i < 5000; ++i) c.push_back({u(rng), u(rng), u(rng) * 0.1f});
  c.push_back({std::nanf(""), 0, 0});
  test_oracles::expect_voxel_filter_matches_oracle(c, Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  test_oracles::expect_voxel_filter_matches_oracle(c, Eigen::Vector3f(0.3f, 1.1f, 0.05f));
  test_oracles::expect_voxel_filter_matches_oracle(c, Eigen::Vector3f(1e-6f, 1e-6f, 1e-6f));  // PCL would give up (2^31 cells)
}

TEST(VoxelGrid, HugeGridsBeyond64BitIndicesStillWork) {
  PointCloud c;
  c.push_back({-1e10f, -1e10f, -1e10f});
  c.push_back({1e10f, 1e10f, 1e10f});
  c.push_back({1e10f, 1e10f, 1e10f});
  test_oracles::expect_voxel_filter_matches_oracle(c, Eigen::Vector3f(1e-3f, 1e-3f, 1e-3f));
  EXPECT_THROW(voxel_downsample(c, 1e-12f), InvalidArgument);  // index beyond int64
  EXPECT_THROW(voxel_downsample(c, 0.0f), InvalidArgument);
  EXPECT_THROW(voxel_downsample(c, -1.0f), InvalidArgument);
  EXPECT_THROW(voxel_downsample(c, std::nanf("")), InvalidArgument);
}

TEST(VoxelGrid, AveragesChannelsAndHonorsMinPoints) {
  PointCloud c;
  c.set_channels(PointChannels::Color | PointChannels::Intensity | PointChannels::Normal);
  c.push_back({0.1f, 0.1f, 0.1f}, Rgb8{0, 100, 255});
  c.push_back({0.2f, 0.2f, 0.2f}, Rgb8{255, 101, 0});
  c.push_back({5.1f, 0.1f, 0.1f}, Rgb8{1, 2, 3});
  c.intensities_mut()[0] = 1;
  c.intensities_mut()[1] = 3;
  c.normals_mut()[0] = {1, 0, 0};
  c.normals_mut()[1] = {0, 1, 0};
  VoxelGridOptions o;
  o.leaf_size = Eigen::Vector3f::Constant(1.0f);
  auto r = voxel_grid_filter(c, o);
  ASSERT_EQ(r.cloud.size(), 2u);
  EXPECT_EQ(r.cloud.colors()[0], (Rgb8{128, 101, 128}));
  EXPECT_EQ(r.cloud.intensities()[0], 2.0f);
  EXPECT_NEAR(r.cloud.normals()[0].norm(), 1.0f, 1e-6f);
  o.min_points_per_voxel = 2;
  r = voxel_grid_filter(c, o);
  EXPECT_EQ(r.cloud.size(), 1u);
  EXPECT_EQ(r.dropped_voxels, 1u);
  o.average_channels = false;
  EXPECT_EQ(voxel_grid_filter(c, o).cloud.channels(), PointChannels::None);
  EXPECT_TRUE(voxel_downsample(PointCloud{}, 0.1f).empty());
}

TEST(PassThrough, KeepsInclusiveLimitsAndNegative) {
  PointCloud c;
  c.set_channels(PointChannels::Intensity);
  for (int i = 0; i < 10; ++i) c.push_back({0, 0, static_cast<float>(i)});
  c.push_back({std::nanf(""), 0, 5});
  for (int i = 0; i < 11; ++i) c.intensities_mut()[static_cast<std::size_t>(i)] = static_cast<float>(-i);
  PassThroughOptions o;
  o.min = 2;
  o.max = 4;
  auto r = pass_through_filter(c, o);
  EXPECT_EQ(r.kept_indices, (std::vector<std::size_t>{2, 3, 4}));
  o.negative = true;
  r = pass_through_filter(c, o);
  EXPECT_EQ(r.cloud.size(), 7u);  // NaN point removed either way
  o.field = parse_point_field("intensity");
  o.negative = false;
  o.min = -3;
  o.max = -1;
  EXPECT_EQ(pass_through_filter(c, o).kept_indices, (std::vector<std::size_t>{1, 2, 3}));
  EXPECT_THROW(parse_point_field("w"), InvalidArgument);
  o.min = 5;
  EXPECT_THROW(pass_through_filter(c, o), InvalidArgument);
  o.field = PointField::NormalX;
  o.min = 0;
  EXPECT_THROW(pass_through_filter(c, o), InvalidArgument);
}

TEST(Sampling, RandomAndUniform) {
  PointCloud c;
  for (int i = 0; i < 100; ++i) c.push_back({static_cast<float>(i), 0, 0});
  const PointCloud r = random_downsample(c, 30, 7);
  ASSERT_EQ(r.size(), 30u);
  for (std::size_t i = 1; i < r.size(); ++i) EXPECT_LT(r[i - 1].x(), r[i].x());  // distinct, input order
  EXPECT_EQ(random_downsample(c, 30, 7), r);
  EXPECT_EQ(random_downsample(c, 500, 7).size(), 100u);
  const PointCloud u = uniform_downsample(c, 7);
  EXPECT_EQ(u.size(), 15u);
  EXPECT_EQ(u[2].x(), 14.0f);
  EXPECT_THROW(uniform_downsample(c, 0), InvalidArgument);
}

}  // namespace
}  // namespace rove
