#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/graph/graph_io.h"
#include "rove/io/grid_image.h"
#include "rove/io/ply.h"
#include "rove/io/tum_trajectory.h"
#include "rove/test_data.h"
#include "rove/viz/scene_files.h"

namespace rove {
namespace {

namespace fs = std::filesystem;

class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rove_scene_files_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    write_text_file_atomically(dir_ / name, text);
    return (dir_ / name).string();
  }
  fs::path dir_;
};

std::size_t vertices_of(const Scene& s, LayerKind kind) {
  std::size_t n = 0;
  for (const auto& l : s.layers) n += l.kind == kind ? l.positions.size() : 0;
  return n;
}

TEST_F(SceneFiles, TextFilesAreToldApartByTheirFirstRow) {
  EXPECT_EQ(detect_scene_input(write("a.txt", "# t x y z qx qy qz qw\n1 0 0 0 0 0 0 1\n")),
            SceneInputKind::TumTrajectory);
  EXPECT_EQ(detect_scene_input(write("b.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n")), SceneInputKind::KittiTrajectory);
  EXPECT_EQ(detect_scene_input(write("c.txt", "VERTEX2 0 0 0 0\n")), SceneInputKind::PoseGraph);
  EXPECT_EQ(detect_scene_input(write("particles_00003_final.txt", "% x y yaw w\n")), SceneInputKind::Particles);
  EXPECT_THROW(detect_scene_input(write("d.txt", "hello world\n")), ParseError);
  EXPECT_THROW(detect_scene_input(write("e.dat", "1 2 3\n")), ParseError);
  EXPECT_THROW(detect_scene_input((dir_ / "missing.pcd").string()), IoError);
  EXPECT_THROW(detect_scene_input(dir_.string()), ParseError);  // a folder of nothing rove wrote
}

TEST_F(SceneFiles, KittiPosesBecomeATrajectory) {
  const std::string p = write("poses.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 2 0 1 0 1 0 0 1 0\n1 0 0 4 0 1 0 1 0 0 1 3\n");
  Scene s;
  SceneLoadReport r;
  add_scene_input(s, p, {}, r);
  ASSERT_EQ(r.loaded.size(), 1u);
  EXPECT_NE(r.loaded[0].find("KITTI trajectory, 3 poses"), std::string::npos) << r.loaded[0];
  EXPECT_EQ(s.layers[0].positions[2], Eigen::Vector3f(4, 1, 3));
  EXPECT_EQ(s.layers[0].times, (std::vector<float>{0, 1, 2}));
}

TEST_F(SceneFiles, LidarSlamFolderGivesMapGraphAndPaths) {
  OccupancyGrid g(0.0f, 4.0f, 0.0f, 2.0f, 0.1f);
  save_ros_map((dir_ / "map").string(), g);
  PoseGraph2D graph;
  for (int i = 0; i < 5; ++i) graph.add_vertex(static_cast<VertexId>(i), SE2d(i, 0, 0));
  for (int i = 0; i < 4; ++i) graph.add_edge(static_cast<VertexId>(i), static_cast<VertexId>(i + 1), SE2d(1, 0, 0));
  graph.add_edge(0, 4, SE2d(4, 0, 0));
  graph.add_edge(1, 3, SE2d(2, 0, 0));
  write_graph(graph, (dir_ / "graph.g2o").string());
  std::vector<TimedPose2> path;
  for (int i = 0; i < 5; ++i) path.push_back({Timestamp::from_seconds(10 + i), Pose2(i, 0, 0)});
  for (const char* name : {"path.tum", "nodes.tum", "odometry.tum"}) write_tum_trajectory((dir_ / name).string(), path);
  EXPECT_EQ(detect_scene_input(dir_.string()), SceneInputKind::LidarSlamFolder);
  Scene s;
  const std::vector<std::string> inputs = {dir_.string()};
  const SceneLoadReport r = build_scene(s, inputs);
  ASSERT_TRUE(r.skipped.empty()) << r.skipped.front();
  EXPECT_NE(r.loaded[0].find("rove lidar-slam output"), std::string::npos);
  EXPECT_NE(r.loaded[0].find("2 loop closures"), std::string::npos) << r.loaded[0];
  EXPECT_EQ(vertices_of(s, LayerKind::Grid), 4u);
  EXPECT_EQ(vertices_of(s, LayerKind::GraphVertices), 5u);
  EXPECT_EQ(vertices_of(s, LayerKind::LoopEdges), 4u);
  EXPECT_EQ(vertices_of(s, LayerKind::Trajectory), 5u);
  EXPECT_EQ(vertices_of(s, LayerKind::Path), 5u);
  EXPECT_EQ(vertices_of(s, LayerKind::Label), 1u);
  EXPECT_EQ(s.time_origin, 10.0);
}

// An output folder of rove rgbd-slam, as it writes one: 6 frames, 4
// keyframes with edges measured both ways, loops 2–0 (measured twice) and
// 3–0, 3 loop checks, a coloured map of 3 points. Positions are in the
// first keyframe's optical frame (y down, z forward).
class RgbdSlamFolder : public SceneFiles {
 protected:
  void SetUp() override {
    SceneFiles::SetUp();
    std::vector<TimedPose3> traj, kfs;
    for (int i = 0; i < 6; ++i) {
      const SE3d T(Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitY())),
                   Eigen::Vector3d(0.1 * i, -0.02 * i, 0.05 * i));
      traj.push_back({Timestamp::from_seconds(1000.0 + 0.1 * i), T});
      if (i != 1 && i != 4) kfs.push_back(traj.back());
    }
    write_tum_trajectory((dir_ / "trajectory.tum").string(), traj);
    write_tum_trajectory((dir_ / "keyframes.tum").string(), kfs);
    PoseGraph3D g;
    for (std::size_t k = 0; k < kfs.size(); ++k) g.add_vertex(k, kfs[k].pose, k == 0);
    const auto both_ways = [&](VertexId a, VertexId b) {
      const SE3d T_a_b = kfs[a].pose.inverse() * kfs[b].pose;
      g.add_edge(a, b, T_a_b);
      g.add_edge(a, b, T_a_b);
    };
    for (VertexId k = 0; k + 1 < kfs.size(); ++k) both_ways(k, k + 1);
    both_ways(0, 2);
    g.add_edge(0, 3, kfs[0].pose.inverse() * kfs[3].pose);
    write_graph(g, (dir_ / "graph.g2o").string());
    write("loops.csv",
          "keyframe,candidate,keyframe_time,candidate_time,kind,matches,inliers,motion_norm,accepted\n"
          "2,0,1000.300000,1000.000000,nearby,120,80,0.2000,1\n"
          "3,1,1000.500000,1000.200000,nearby,30,10,0.1000,0\n"
          "3,0,1000.500000,1000.000000,random,100,60,0.3000,1\n");
    PointCloud map;
    map.set_channels(PointChannels::Color);
    map.push_back({0.0f, 0.5f, 2.0f}, Rgb8{200, 10, 10});
    map.push_back({1.0f, 0.5f, 2.5f}, Rgb8{10, 200, 10});
    map.push_back({-1.0f, -0.5f, 3.0f}, Rgb8{10, 10, 200});
    write_ply((dir_ / "map.ply").string(), map);
    keyframes_ = kfs;
    trajectory_ = traj;
  }
  std::vector<TimedPose3> keyframes_, trajectory_;
};

const Layer* layer_of(const Scene& s, LayerKind kind) {
  for (const auto& l : s.layers) {
    if (l.kind == kind) return &l;
  }
  return nullptr;
}

TEST_F(RgbdSlamFolder, GivesTheMapTrajectoryKeyframesAndGraphWithLoopsOnce) {
  EXPECT_EQ(detect_scene_input(dir_.string()), SceneInputKind::RgbdSlamFolder);
  Scene s;
  SceneLoadReport r;
  add_scene_input(s, dir_.string(), {}, r);
  ASSERT_EQ(r.loaded.size(), 1u);
  const std::string& line = r.loaded[0];
  EXPECT_NE(line.find("rove rgbd-slam output, map 3 points; graph 3D, 4 vertices, 9 edges (2 loop closures by 3 edges); 6 poses "
                      "(trajectory.tum); 4 keyframes; loops.csv: 2 of 3 loop checks accepted (nearby 1, random 1)"),
            std::string::npos)
      << line;
  EXPECT_EQ(s.up, SceneUp::MinusY);
  // The map in its file's colours.
  const Layer* map = layer_of(s, LayerKind::PointCloud);
  ASSERT_NE(map, nullptr);
  ASSERT_EQ(map->positions.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const std::uint64_t k = map->source_index(i);
    const Eigen::Vector3f want = k == 0 ? Eigen::Vector3f(0, 0.5f, 2) : k == 1 ? Eigen::Vector3f(1, 0.5f, 2.5f)
                                                                             : Eigen::Vector3f(-1, -0.5f, 3);
    EXPECT_EQ(map->positions[i], want) << k;
    EXPECT_EQ(map->colors[i].r, k == 0 ? 200 : 10) << k;
  }
  // The graph: each pair of keyframes once, the loops 0–2 and 0–3 highlighted.
  EXPECT_EQ(vertices_of(s, LayerKind::GraphVertices), 4u);
  EXPECT_EQ(vertices_of(s, LayerKind::GraphEdges), 6u);
  const Layer* loops = layer_of(s, LayerKind::LoopEdges);
  ASSERT_NE(loops, nullptr);
  ASSERT_EQ(loops->positions.size(), 4u);
  const auto at = [](const TimedPose3& p) { return p.pose.translation().cast<float>().eval(); };
  EXPECT_TRUE(loops->positions[0].isApprox(at(keyframes_[0]), 1e-6f));
  EXPECT_TRUE(loops->positions[1].isApprox(at(keyframes_[2]), 1e-6f));
  EXPECT_TRUE(loops->positions[3].isApprox(at(keyframes_[3]), 1e-6f));
  // Every frame on the trajectory, the keyframes as a path with a frame each.
  const Layer* traj = layer_of(s, LayerKind::Trajectory);
  ASSERT_NE(traj, nullptr);
  ASSERT_EQ(traj->positions.size(), 6u);
  EXPECT_TRUE(traj->positions[5].isApprox(at(trajectory_[5]), 1e-6f));
  EXPECT_NEAR(traj->times[5] + s.time_origin, 1000.5, 1e-4);
  const Layer* kf = layer_of(s, LayerKind::Path);
  ASSERT_NE(kf, nullptr);
  ASSERT_EQ(kf->positions.size(), 4u);
  EXPECT_TRUE(kf->positions[2].isApprox(at(keyframes_[2]), 1e-6f));
  const Layer* frames = layer_of(s, LayerKind::Frames);
  ASSERT_NE(frames, nullptr);
  ASSERT_EQ(frames->positions.size(), 4u * 6u);  // 3 axes of 2 vertices per keyframe
  // Keyframe 3's z axis (blue, the camera's forward) along its rotation's third column.
  const Eigen::Vector3f z_axis = frames->positions[3 * 6 + 5] - frames->positions[3 * 6 + 4];
  const Eigen::Vector3f want = keyframes_[3].pose.rotation_matrix().col(2).cast<float>();
  EXPECT_NEAR(z_axis.normalized().dot(want), 1.0f, 1e-5f);
  EXPECT_EQ(vertices_of(s, LayerKind::Label), 1u);
  EXPECT_EQ(s.layers.back().text, "start");
  EXPECT_TRUE(s.layers.back().positions[0].isApprox(at(trajectory_[0]), 1e-6f));
}

TEST_F(RgbdSlamFolder, AfterAMapTheSceneKeepsZUp) {
  OccupancyGrid g(0.0f, 1.0f, 0.0f, 1.0f, 0.1f);
  const RosMapFiles f = save_ros_map((dir_ / "floor").string(), g);
  const std::vector<std::string> inputs = {f.yaml, dir_.string()};
  Scene s;
  const SceneLoadReport r = build_scene(s, inputs);
  ASSERT_TRUE(r.skipped.empty()) << r.skipped.front();
  EXPECT_EQ(s.up, SceneUp::PlusZ);
}

TEST_F(RgbdSlamFolder, ABadLoopsFileNamesTheLineAndLeavesTheSceneAsItWas) {
  write("loops.csv",
        "keyframe,candidate,keyframe_time,candidate_time,kind,matches,inliers,motion_norm,accepted\n"
        "2,0,1000.3,1000.0,nearby,120,80,0.2,1\n"
        "9,0,1000.3,1000.0,nearby,120,80,0.2,1\n");
  Scene s;
  SceneLoadReport r;
  try {
    add_scene_input(s, dir_.string(), {}, r);
    FAIL() << "a loop of keyframe 9 of 4 was read";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().line, 3u);
    EXPECT_EQ(e.location().field, "keyframe");
    EXPECT_NE(e.message().find("keyframes.tum has 4"), std::string::npos) << e.message();
  }
  EXPECT_TRUE(s.layers.empty());
  EXPECT_EQ(s.up, SceneUp::PlusZ);
  EXPECT_TRUE(std::isnan(s.time_origin));
  write("loops.csv", "keyframe,candidate,kind,accepted\n1,0,nearby,yes\n");
  EXPECT_THROW(add_scene_input(s, dir_.string(), {}, r), ParseError);
  write("loops.csv", "keyframe,kind,accepted\n1,nearby,1\n");
  EXPECT_THROW(add_scene_input(s, dir_.string(), {}, r), ParseError);
  EXPECT_TRUE(s.layers.empty());
}

TEST_F(SceneFiles, PfLocalizationFolderTimesParticlesByTheirStep) {
  std::vector<TimedPose2> path = {{Timestamp::from_seconds(100), Pose2(0, 0, 0)},
                                  {Timestamp::from_seconds(101), Pose2(1, 0, 0)}};
  write_tum_trajectory((dir_ / "path.tum").string(), path);
  write("steps.txt",
        "# step time x y phi particles ess converged mass scan_fit range_residual injected cov_xx cov_xy cov_xphi "
        "cov_yy cov_yphi cov_phiphi seconds\n"
        "0 100.0 0 0 0 10 5 0 0.5 -1 -1 0 0.25 0 0 0.04 0 0.01 0.001\n"
        "1 101.0 1 0 0 10 5 1 0.9 -1 -1 0 0.01 0 0 0.01 0 0.01 0.001\n");
  write("particles_initial.txt", "% x  y  yaw[rad] log_weight\n0 0 0 0\n1 1 0 -1\n");
  write("particles_00001_final.txt", "% x  y  yaw[rad] log_weight\n1 0 0 0\n1.1 0 0 0\n1.2 0 0 0\n");
  Scene s;
  SceneLoadReport r;
  add_scene_input(s, dir_.string(), {}, r);
  EXPECT_NE(r.loaded[0].find("2 particle sets, 5 particles"), std::string::npos) << r.loaded[0];
  const Layer* particles = nullptr;
  const Layer* ellipses = nullptr;
  for (const auto& l : s.layers) {
    if (l.kind == LayerKind::Particles) particles = &l;
    if (l.kind == LayerKind::Covariance) ellipses = &l;
  }
  ASSERT_NE(particles, nullptr);
  ASSERT_NE(ellipses, nullptr);
  // Initial set just before step 0 (t = 100 s), the final set at step 1.
  EXPECT_NEAR(particles->times.front() + s.time_origin, 100.0 - 1e-3, 1e-6);
  EXPECT_EQ(particles->times.back() + s.time_origin, 101.0);
  EXPECT_EQ(particles->positions.size(), 5u);
  // Step 0's ellipse: sigma 0.5 m by 0.2 m, 3-sigma half axes 1.5 and 0.6.
  float max_x = 0;
  for (std::size_t i = 0; i < ellipses->positions.size() / 2; ++i) max_x = std::max(max_x, ellipses->positions[i].x());
  EXPECT_NEAR(max_x, 1.5f, 1e-4);
}

TEST_F(SceneFiles, KfSlamFolderGivesPathLandmarksAndTheirEllipses) {
  std::vector<TimedPose2> path = {{Timestamp::from_seconds(5), Pose2(0, 0, 0)},
                                  {Timestamp::from_seconds(6), Pose2(1, 0, 0)}};
  write_tum_trajectory((dir_ / "path.tum").string(), path);
  // A pf-localization folder also has steps.txt and path.tum: landmarks.csv tells them apart.
  write("steps.txt", "# step time x y z qx qy qz qw\n");
  write("landmarks.csv",
        "index,id,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,observations,first_step,truth_id,error\n"
        "0,7,2.0,1.0,0.0,0.25,0,0,0.04,0,0,3,0,7,0.01\n"
        "1,9,-1.0,3.0,0.0,0.01,0,0,0.01,0,0,1,1,,\n");
  EXPECT_EQ(detect_scene_input(dir_.string()), SceneInputKind::KfSlamFolder);
  Scene s;
  SceneLoadReport r;
  add_scene_input(s, dir_.string(), {}, r);
  EXPECT_NE(r.loaded[0].find("rove kf-slam output"), std::string::npos) << r.loaded[0];
  EXPECT_NE(r.loaded[0].find("2 2D landmarks with their 3-sigma ellipses"), std::string::npos) << r.loaded[0];
  EXPECT_EQ(vertices_of(s, LayerKind::Trajectory), 2u);
  EXPECT_EQ(vertices_of(s, LayerKind::PointCloud), 2u);
  EXPECT_EQ(vertices_of(s, LayerKind::Label), 3u);  // start, 7, 9
  const Layer* ellipses = nullptr;
  for (const auto& l : s.layers) {
    if (l.kind == LayerKind::Covariance) ellipses = &l;
  }
  ASSERT_NE(ellipses, nullptr);
  // Landmark 7: sigma 0.5 m by 0.2 m around (2, 1): 3-sigma reach x 0.5..3.5, y 0.4..1.6.
  float max_x = -1e9f, max_y = -1e9f;
  for (std::size_t i = 0; i < ellipses->positions.size() / 2; ++i) {
    max_x = std::max(max_x, ellipses->positions[i].x());
    max_y = std::max(max_y, ellipses->positions[i].y());
  }
  EXPECT_NEAR(max_x, 3.5f, 1e-4);
  EXPECT_NEAR(max_y, 1.6f, 2e-3);  // the polygon's vertex nearest the axis
}

TEST_F(SceneFiles, ThreeDimensionalLandmarksGetEllipsoids) {
  const std::string p = write("landmarks.csv",
                              "index,id,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,observations\n"
                              "0,1,0,0,1.5,0.01,0,0,0.01,0,0.04,2\n");
  EXPECT_EQ(detect_scene_input(p), SceneInputKind::Landmarks);
  Scene s;
  SceneLoadReport r;
  add_scene_input(s, p, {}, r);
  EXPECT_NE(r.loaded[0].find("1 3D landmarks with their 3-sigma ellipsoids"), std::string::npos) << r.loaded[0];
  float max_z = -1e9f;
  for (const auto& l : s.layers) {
    if (l.kind != LayerKind::Covariance) continue;
    for (const auto& v : l.positions) max_z = std::max(max_z, v.z());
  }
  EXPECT_NEAR(max_z, 1.5f + 0.6f, 1e-4);  // 3 sigma of 0.2 m above the mean
}

TEST_F(SceneFiles, BadLandmarkFilesNameTheLineAndColumn) {
  const std::string header = "index,id,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz\n";
  const auto load_error = [&](const std::string& name, const std::string& text) -> std::optional<ParseError> {
    Scene s;
    SceneLoadReport r;
    try {
      add_scene_input(s, write(name, text), {}, r);
    } catch (const ParseError& e) {
      EXPECT_TRUE(s.layers.empty());
      return e;
    }
    return std::nullopt;
  };
  auto e = load_error("nan.csv", header + "0,1,1,2,0,0.1,0,0,0.1,0,0\n1,2,nan,2,0,0.1,0,0,0.1,0,0\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->location().line, 3u);
  EXPECT_EQ(e->location().field, "x");
  e = load_error("short.csv", header + "0,1,1,2\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->location().line, 2u);
  e = load_error("other.csv", "id,x,y,z\n1,2,3,4\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->location().field, "header");
  e = load_error("empty.csv", header);
  ASSERT_TRUE(e);
  e = load_error("notpsd.csv", header + "0,1,1,2,0,0.1,0.5,0,0.1,0,0\n");  // |cov_xy| > sqrt(xx·yy)
  ASSERT_TRUE(e);
  EXPECT_EQ(e->location().field, "covariance");
}

TEST_F(SceneFiles, RangeOnlyRbpfSlamFolderGivesBeacons) {
  std::vector<TimedPose2> path = {{Timestamp::from_seconds(1), Pose2(0, 0, 0)},
                                  {Timestamp::from_seconds(2), Pose2(1, 0, 0)}};
  write_tum_trajectory((dir_ / "path.tum").string(), path);
  write("ess.csv", "step,time,ess\n0,1,1\n");
  write("beacons.csv",
        "id,kind,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,components\n"
        "3,gaussian,4.0,-2.0,0.0,0.04,0,0,0.01,0,0,1\n");
  EXPECT_EQ(detect_scene_input(dir_.string()), SceneInputKind::RbpfSlamFolder);
  Scene s;
  SceneLoadReport r;
  add_scene_input(s, dir_.string(), {}, r);
  EXPECT_NE(r.loaded[0].find("; 1 2D beacons with their 3-sigma ellipses"), std::string::npos) << r.loaded[0];
  EXPECT_EQ(vertices_of(s, LayerKind::PointCloud), 1u);
  bool labelled = false;
  for (const auto& l : s.layers) labelled = labelled || (l.kind == LayerKind::Label && l.text == "3");
  EXPECT_TRUE(labelled);
}

TEST_F(SceneFiles, RbpfSlamFolderGivesMapAndPaths) {
  OccupancyGrid g(0.0f, 4.0f, 0.0f, 2.0f, 0.1f);
  save_ros_map((dir_ / "map").string(), g);
  std::vector<TimedPose2> path = {{Timestamp::from_seconds(1), Pose2(0, 0, 0)},
                                  {Timestamp::from_seconds(2), Pose2(1, 0, 0)},
                                  {Timestamp::from_seconds(3), Pose2(2, 0, 0)}};
  for (const char* name : {"path.tum", "odometry.tum"}) write_tum_trajectory((dir_ / name).string(), path);
  write("ess.csv", "update,ess\n0,1\n");
  EXPECT_EQ(detect_scene_input(dir_.string()), SceneInputKind::RbpfSlamFolder);
  Scene s;
  SceneLoadReport r;
  add_scene_input(s, dir_.string(), {}, r);
  EXPECT_NE(r.loaded[0].find("rove rbpf-slam output"), std::string::npos) << r.loaded[0];
  EXPECT_EQ(vertices_of(s, LayerKind::Grid), 4u);
  EXPECT_EQ(vertices_of(s, LayerKind::Trajectory), 3u);
  EXPECT_EQ(vertices_of(s, LayerKind::Path), 3u);
}

TEST_F(SceneFiles, BadParticleFileNamesTheLine) {
  const std::string p = write("particles_00002_x.txt", "% x y yaw w\n1 2 3 4\n1 two 3 4\n");
  Scene s;
  SceneLoadReport r;
  try {
    add_scene_input(s, p, {}, r);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().line, 3u);
  }
  EXPECT_TRUE(s.layers.empty());  // the scene is left as it was
}

TEST_F(SceneFiles, RawlogScansFollowTheOdometry) {
  Scene s;
  SceneLoadReport r;
  add_scene_input(s, test_data::bundled_file("mrpt/2006-01ENE-21-SENA_Telecom_Faculty_one_loop_only.rawlog"), {}, r);
  ASSERT_EQ(r.loaded.size(), 1u);
  // The Telecom loop: 225 scans (as rove icp-slam reads it).
  EXPECT_NE(r.loaded[0].find("225 scans along the odometry"), std::string::npos) << r.loaded[0];
  EXPECT_GT(vertices_of(s, LayerKind::Scans), 225u * 100u);
  EXPECT_EQ(vertices_of(s, LayerKind::Trajectory), 225u);
  // The scans' times never go back (the slider shows them cumulatively).
  const Layer& scans = s.layers[0];
  EXPECT_TRUE(std::is_sorted(scans.times.begin(), scans.times.end()));
}

TEST_F(SceneFiles, BuildSceneSkipsWhatFailsAndNamesIt) {
  const std::string bad = write("bad.pcd", "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\n");
  const std::vector<std::string> inputs = {bad, test_data::bundled_file("pointcloud/bunny.pcd")};
  Scene s;
  const SceneLoadReport r = build_scene(s, inputs);
  ASSERT_EQ(r.skipped.size(), 1u);
  EXPECT_NE(r.skipped[0].find("bad.pcd"), std::string::npos) << r.skipped[0];
  EXPECT_EQ(s.layers.size(), 1u);
  EXPECT_EQ(s.title, "bunny.pcd");
  EXPECT_EQ(s.sources.size(), 1u);
}

}  // namespace
}  // namespace rove
