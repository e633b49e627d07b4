#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "rove/core/error.h"
#include "rove/viz/scene_builders.h"

namespace rove {
namespace {

PointCloud line_cloud(std::size_t n) {
  PointCloud c;
  c.set_channels(PointChannels::Intensity);
  for (std::size_t i = 0; i < n; ++i) {
    c.push_back({static_cast<float>(i), 0.0f, 0.5f});
    c.intensities_mut()[i] = static_cast<float>(2 * i);
  }
  return c;
}

TEST(SceneBuilders, CloudKeepsEveryPointOnceInSpreadOrder) {
  Scene s;
  const CloudLayerReport r = add_point_cloud(s, line_cloud(1000), "line");
  ASSERT_EQ(r.kept, 1000u);
  const Layer& l = s.layers[r.layer];
  EXPECT_EQ(l.source_count, 1000u);
  EXPECT_NE(l.permutation_step, 0u);
  std::set<int> seen;
  for (std::size_t i = 0; i < l.positions.size(); ++i) {
    // Vertex i came from source_index(i): x = index, intensity = 2·index.
    const std::uint64_t src = l.source_index(i);
    EXPECT_EQ(l.positions[i].x(), static_cast<float>(src));
    EXPECT_EQ(l.intensities[i], static_cast<float>(2 * src));
    seen.insert(static_cast<int>(l.positions[i].x()));
  }
  EXPECT_EQ(seen.size(), 1000u);
  EXPECT_TRUE(l.colors.empty());
}

TEST(SceneBuilders, DecimatedCloudPrefixIsAnEvenSample) {
  Scene s;
  CloudLayerOptions o;
  o.max_points = 100;
  const CloudLayerReport r = add_point_cloud(s, line_cloud(10000), "line", o);
  EXPECT_EQ(r.kept, 100u);
  EXPECT_EQ(r.finite, 10000u);
  const Layer& l = s.layers[0];
  // The 100 kept x values fall one in each tenth of [0, 10000) ten times over.
  std::vector<int> per_decile(10, 0);
  for (const auto& p : l.positions) ++per_decile[static_cast<int>(p.x()) / 1000];
  for (int c : per_decile) {
    EXPECT_GE(c, 8);
    EXPECT_LE(c, 12);
  }
}

TEST(SceneBuilders, NonFinitePointsAreLeftOutAndCounted) {
  PointCloud c;
  c.push_back({0, 0, 0});
  c.push_back({std::nanf(""), 0, 0});
  c.push_back({1, 2, 3});
  c.push_back({0, INFINITY, 0});
  Scene s;
  const CloudLayerReport r = add_point_cloud(s, c, "c");
  EXPECT_EQ(r.skipped, 2u);
  EXPECT_EQ(r.kept, 2u);
  PointCloud bad;
  bad.push_back({std::nanf(""), 0, 0});
  EXPECT_THROW(add_point_cloud(s, bad, "bad"), InvalidArgument);
  EXPECT_THROW(add_point_cloud(s, PointCloud(), "empty"), InvalidArgument);
}

TEST(SceneBuilders, GridIsATexturedRectangleOverItsArea) {
  OccupancyGrid g(-2.0f, 3.0f, 1.0f, 2.0f, 0.5f);
  Scene s;
  add_occupancy_grid(s, g, "g");
  const Layer& l = s.layers[0];
  ASSERT_EQ(l.positions.size(), 4u);
  EXPECT_EQ(l.positions[0], Eigen::Vector3f(-2.0f, 1.0f, 0.0f));
  EXPECT_EQ(l.positions[2], Eigen::Vector3f(3.0f, 2.0f, 0.0f));
  // Image row 0 is the top (largest y): uv (0, 0) at (x_min, y_max).
  EXPECT_EQ(l.uvs[3], Eigen::Vector2f(0.0f, 0.0f));
  EXPECT_EQ(l.positions[3], Eigen::Vector3f(-2.0f, 2.0f, 0.0f));
  ASSERT_TRUE(l.texture.has_value());
  EXPECT_EQ(l.texture->width, 10u);
  EXPECT_EQ(l.texture->height, 2u);
  EXPECT_EQ(l.indices.size(), 6u);
  ASSERT_TRUE(l.grid.has_value());
  EXPECT_EQ(l.grid->x_min, -2.0);
  EXPECT_EQ(l.grid->y_min, 1.0);
  EXPECT_EQ(l.grid->resolution, 0.5);
  EXPECT_EQ(l.grid->size_x, 10u);
  EXPECT_EQ(l.grid->size_y, 2u);
  EXPECT_EQ(l.grid->cells_per_texel, 1u);
  s.check();
  // Cells that do not make the texture are refused.
  Scene bad = s;
  bad.layers[0].grid->size_x = 11;
  EXPECT_THROW(bad.check(), InvalidArgument);
}

TEST(SceneBuilders, LargeGridTextureShrinksToTheLimit) {
  OccupancyGrid g(0.0f, 100.0f, 0.0f, 10.0f, 0.01f);  // 10000 x 1000 cells
  GridLayerOptions o;
  o.max_texture_side = 4096;
  Scene s;
  add_occupancy_grid(s, g, "g", o);
  EXPECT_EQ(s.layers[0].texture->width, 3334u);  // factor 3
  EXPECT_EQ(s.layers[0].texture->height, 334u);
  EXPECT_EQ(s.layers[0].grid->cells_per_texel, 3u);
  s.check();
}

TEST(SceneBuilders, OctreeLeavesBecomeBoxesOfTheirSize) {
  OccupancyOctree tree(0.5);
  const Eigen::Vector3d a(0.25, 0.25, 0.25), b(2.25, 0.25, 1.25), free_cell(1.25, 1.25, 0.25);
  for (int k = 0; k < 3; ++k) {
    tree.update_node(tree.key_checked(a), true);
    tree.update_node(tree.key_checked(b), true);
    tree.update_node(tree.key_checked(free_cell), false);
  }
  Scene s;
  add_octree(s, tree, "tree");
  const Layer& l = s.layers[0];
  EXPECT_EQ(l.kind, LayerKind::Voxels);
  EXPECT_EQ(l.primitive, Primitive::Triangles);
  ASSERT_EQ(l.positions.size(), 16u);  // two occupied leaves, 8 corners each
  EXPECT_EQ(l.indices.size(), 72u);    // 12 triangles each
  // Each box spans its cell: corners at the centre ± 0.25 m.
  Eigen::Vector3f lo = l.positions[0], hi = l.positions[0];
  for (const auto& p : l.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  EXPECT_TRUE(lo.isApprox(Eigen::Vector3f(0.0f, 0.0f, 0.0f)));
  EXPECT_TRUE(hi.isApprox(Eigen::Vector3f(2.5f, 0.5f, 1.5f)));
  s.check();
  // Drawn as centres when there are more leaves than boxes allowed.
  VoxelLayerOptions o;
  o.max_boxes = 1;
  add_octree(s, tree, "points", o);
  EXPECT_EQ(s.layers[1].primitive, Primitive::Points);
  EXPECT_EQ(s.layers[1].positions.size(), 2u);
  EXPECT_THROW(add_octree(s, OccupancyOctree(0.1), "empty"), InvalidArgument);
}

TEST(SceneBuilders, TrajectoryTimesAreRelativeToTheSceneOrigin) {
  std::vector<StampedPose3> p;
  for (int i = 0; i < 5; ++i) {
    p.push_back({1.7e9 + 0.5 * i, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(i, 2.0 * i, 0))});
  }
  Scene s;
  TrajectoryLayerOptions o;
  o.frames = 3;
  o.frame_size = 0.25;
  add_trajectory(s, p, "t", o);
  ASSERT_EQ(s.layers.size(), 2u);
  EXPECT_EQ(s.time_origin, 1.7e9);
  EXPECT_EQ(s.layers[0].times, (std::vector<float>{0.0f, 0.5f, 1.0f, 1.5f, 2.0f}));
  EXPECT_EQ(s.layers[0].primitive, Primitive::LineStrip);
  EXPECT_EQ(s.layers[0].positions[4], Eigen::Vector3f(4.0f, 8.0f, 0.0f));
  // Frames at poses 0, 2, 4: x axes of 0.25 m along +x.
  const Layer& f = s.layers[1];
  ASSERT_EQ(f.positions.size(), 18u);
  EXPECT_EQ(f.positions[6], Eigen::Vector3f(2.0f, 4.0f, 0.0f));
  EXPECT_EQ(f.positions[7], Eigen::Vector3f(2.25f, 4.0f, 0.0f));
  EXPECT_EQ(f.times[7], 1.0f);
  s.check();
}

TEST(SceneBuilders, PoseGraphSeparatesLoopClosures) {
  PoseGraph2D g;
  for (int i = 0; i < 4; ++i) g.add_vertex(static_cast<VertexId>(i), SE2d(i, 0, 0));
  for (int i = 0; i < 3; ++i) g.add_edge(static_cast<VertexId>(i), static_cast<VertexId>(i + 1), SE2d(1, 0, 0));
  g.add_edge(0, 3, SE2d(3, 0, 0));
  Scene s;
  add_pose_graph(s, g, "g");
  ASSERT_EQ(s.layers.size(), 3u);
  EXPECT_EQ(s.layers[0].kind, LayerKind::GraphVertices);
  EXPECT_EQ(s.layers[0].positions.size(), 4u);
  EXPECT_EQ(s.layers[1].kind, LayerKind::GraphEdges);
  EXPECT_EQ(s.layers[1].positions.size(), 6u);
  EXPECT_EQ(s.layers[2].kind, LayerKind::LoopEdges);
  ASSERT_EQ(s.layers[2].positions.size(), 2u);
  EXPECT_EQ(s.layers[2].positions[1], Eigen::Vector3f(3.0f, 0.0f, 0.0f));
}

TEST(SceneBuilders, EdgesBetweenTheSameVerticesAreDrawnOnce) {
  // rove rgbd-slam measures each relative pose both ways: two edges per pair.
  PoseGraph3D g;
  for (int i = 0; i < 4; ++i) g.add_vertex(static_cast<VertexId>(i), SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(i, 0, 0)));
  for (VertexId i = 0; i < 3; ++i) {
    g.add_edge(i, i + 1, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0)));
    g.add_edge(i, i + 1, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0)));
  }
  g.add_edge(0, 3, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(3, 0, 0)));
  g.add_edge(3, 0, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-3, 0, 0)));
  Scene s;
  add_pose_graph(s, g, "g");
  ASSERT_EQ(s.layers.size(), 3u);
  EXPECT_EQ(s.layers[1].positions.size(), 6u);  // 3 pairs
  ASSERT_EQ(s.layers[2].kind, LayerKind::LoopEdges);
  ASSERT_EQ(s.layers[2].positions.size(), 2u);  // one loop
  EXPECT_EQ(s.layers[2].positions[1], Eigen::Vector3f(3, 0, 0));
}

TEST(SceneBuilders, EllipseIsTheKSigmaContour) {
  PositionCovariance2 c;
  c.mean = {1.0, -1.0};
  c.covariance << 4.0, 0.0, 0.0, 0.25;  // sigma 2 m along x, 0.5 m along y
  Scene s;
  CovarianceLayerOptions o;
  o.sigmas = 3.0;
  add_covariance_ellipses(s, std::span(&c, 1), "cov", o);
  const Layer& l = s.layers[0];
  ASSERT_EQ(l.positions.size(), 2 * o.segments);
  for (const auto& p : l.positions) {
    const double dx = (p.x() - 1.0) / 6.0, dy = (p.y() + 1.0) / 1.5;
    EXPECT_NEAR(dx * dx + dy * dy, 1.0, 1e-5);
  }
  c.covariance(0, 1) = 5.0;  // not symmetric
  EXPECT_THROW(add_covariance_ellipses(s, std::span(&c, 1), "bad"), InvalidArgument);
  c.covariance << 1.0, 0.0, 0.0, -1.0;  // not positive semi-definite
  EXPECT_THROW(add_covariance_ellipses(s, std::span(&c, 1), "bad"), InvalidArgument);
}

TEST(SceneBuilders, EllipsoidAxesFollowTheEigenvectors) {
  PositionCovariance3 c;
  c.covariance = Eigen::Vector3d(1.0, 4.0, 9.0).asDiagonal();
  Scene s;
  CovarianceLayerOptions o;
  o.sigmas = 1.0;
  add_covariance_ellipsoids(s, std::span(&c, 1), "cov", o);
  // Every vertex lies on the 1-sigma ellipsoid x² + y²/4 + z²/9 = 1.
  for (const auto& p : s.layers[0].positions) {
    EXPECT_NEAR(p.x() * p.x() + p.y() * p.y() / 4.0 + p.z() * p.z() / 9.0, 1.0, 1e-5);
  }
  EXPECT_EQ(s.layers[0].positions.size(), 3 * 2 * o.segments);
}

TEST(SceneBuilders, ParticlesCarryRelativeWeightsAndSnapshotTimes) {
  std::vector<ParticleSnapshot> snaps(2);
  snaps[0].time = 5.0;
  snaps[0].states = {SE2d(0, 0, 0), SE2d(1, 1, 0)};
  snaps[0].log_weights = {0.0, std::log(0.5)};
  snaps[1].time = 6.0;
  snaps[1].states = {SE2d(2, 2, 0)};
  Scene s;
  add_particles(s, snaps, "p");
  const Layer& l = s.layers[0];
  EXPECT_EQ(l.time_mode, TimeMode::Snapshot);
  EXPECT_EQ(l.times, (std::vector<float>{0.0f, 0.0f, 1.0f}));
  EXPECT_FLOAT_EQ(l.intensities[1], 0.5f);
  EXPECT_FLOAT_EQ(l.intensities[2], 1.0f);
  snaps[1].log_weights = {0.0, 0.0};
  EXPECT_THROW(add_particles(s, snaps, "bad"), InvalidArgument);
}

TEST(SceneBuilders, LabelsAndFrames) {
  Scene s;
  add_label(s, {1, 2, 3}, "here");
  add_frame(s, SE3d(), 2.0, "origin");
  EXPECT_EQ(s.layers[0].text, "here");
  EXPECT_EQ(s.layers[1].positions[5], Eigen::Vector3f(0, 0, 2));
  EXPECT_THROW(add_label(s, {0, 0, 0}, ""), InvalidArgument);
  s.check();
  EXPECT_EQ(s.vertex_count(), 7u);
  EXPECT_EQ(s.bounds().max, Eigen::Vector3f(2, 2, 3));
}

TEST(SceneBuilders, ScansThinToTheBudgetAcrossThePath) {
  std::vector<TimedPoints> scans(10);
  for (int k = 0; k < 10; ++k) {
    scans[k].time = k;
    for (int i = 0; i < 100; ++i) scans[k].points.emplace_back(k, i, 0);
  }
  Scene s;
  add_scans(s, scans, "scans", 250);
  const Layer& l = s.layers[0];
  EXPECT_EQ(l.positions.size(), 250u);  // every 4th point of every scan
  EXPECT_EQ(l.times.back(), 9.0f);
  EXPECT_EQ(l.source_count, 1000u);
}

TEST(SceneBuilders, RampGoesFromBlueToRed) {
  const Rgba8 lo = ramp_color(0.0f), hi = ramp_color(1.0f);
  EXPECT_GT(lo.b, lo.r);
  EXPECT_GT(hi.r, hi.b);
  EXPECT_EQ(ramp_color(-1.0f), lo);
  EXPECT_EQ(ramp_color(std::nanf("")), lo);
  EXPECT_EQ(ramp_color(7.0f), hi);
}

}  // namespace
}  // namespace rove
