// The viewer in a real browser (headless Chromium, Debian's chromium): the
// pages load the scene through three.js's glTF loader and publish what
// they drew; screenshots are compared with a reference by pixel
// statistics. Suites ending in "Browser" carry the ctest label `browser`.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/gray_image.h"
#include "rove/io/grid_image.h"
#include "rove/io/tum_trajectory.h"
#include "rove/test_data.h"
#include "rove/viz/glb.h"
#include "rove/viz/headless_browser.h"
#include "rove/viz/scene_builders.h"
#include "rove/viz/scene_files.h"
#include "rove/viz/viewer_page.h"
#include "rove/viz/viewer_server.h"

namespace rove {
namespace {

namespace fs = std::filesystem;

fs::path temp_folder(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("rove_viz_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

// A 10 m x 8 m room with walls, a map.yaml in `dir`; a square trajectory
// inside it; returns the paths (map.yaml, path.tum).
std::vector<std::string> write_room(const fs::path& dir) {
  OccupancyGrid g(0.0f, 10.0f, 0.0f, 8.0f, 0.05f);
  for (int cy = 0; cy < static_cast<int>(g.size_y()); ++cy) {
    for (int cx = 0; cx < static_cast<int>(g.size_x()); ++cx) {
      const bool wall = cx < 4 || cy < 4 || cx >= static_cast<int>(g.size_x()) - 4 ||
                        cy >= static_cast<int>(g.size_y()) - 4 || (cx == 100 && cy < 100);
      g.set_free_probability(cx, cy, wall ? 0.0f : 1.0f);
    }
  }
  const RosMapFiles f = save_ros_map((dir / "map").string(), g);
  std::vector<TimedPose2> path;
  for (int i = 0; i <= 40; ++i) {
    const double s = i / 10.0;  // around a 6 m x 4 m rectangle
    const double x = s < 1 ? 2 + 6 * s : s < 2 ? 8 : s < 3 ? 8 - 6 * (s - 2) : 2;
    const double y = s < 1 ? 2 : s < 2 ? 2 + 4 * (s - 1) : s < 3 ? 6 : 6 - 4 * (s - 3);
    path.push_back({Timestamp::from_seconds(100.0 + i), Pose2(x, y, 0.0)});
  }
  write_tum_trajectory((dir / "path.tum").string(), path);
  return {f.yaml, (dir / "path.tum").string()};
}

JsonValue stats_of(const std::string& dom) {
  const std::string stats = page_stats_json(dom);
  EXPECT_FALSE(stats.empty()) << "the page published no stats:\n" << dom.substr(0, 2000);
  return parse_json(stats.empty() ? "{}" : stats, "rove-stats");
}

// Vertices per layer kind of a scene, as the page reports them.
std::map<std::string, std::size_t> kinds_of(const Scene& s) {
  std::map<std::string, std::size_t> k;
  for (const auto& l : s.layers) k[to_string(l.kind)] += l.positions.size();
  return k;
}

void expect_page_shows(const JsonValue& stats, const Scene& scene) {
  ASSERT_TRUE(stats.is_object());
  ASSERT_EQ(stats["status"].as_string(), "ready") << (stats.contains("error") ? stats["error"].as_string() : "");
  EXPECT_EQ(stats["layers"].as_index(), scene.layers.size());
  EXPECT_EQ(stats["objects"].as_index(), scene.layers.size());
  EXPECT_EQ(stats["vertices"].as_index(), scene.vertex_count());
  for (const auto& [kind, vertices] : kinds_of(scene)) {
    EXPECT_EQ(stats["kinds"][kind]["vertices"].as_index(), vertices) << kind;
    // The slider starts at the end: everything is drawn.
    EXPECT_EQ(stats["drawn"][kind].as_index(), vertices) << kind;
  }
}

Scene grid_trajectory_graph_scene(const fs::path& dir) {
  std::vector<std::string> inputs = write_room(dir);
  inputs.push_back(test_data::bundled_file("posegraph/w100.graph"));
  Scene scene;
  const SceneLoadReport r = build_scene(scene, inputs);
  EXPECT_TRUE(r.skipped.empty()) << r.skipped.front();
  return scene;
}

TEST(ViewerBrowser, StandalonePageShowsACloud) {
  const fs::path dir = temp_folder("cloud");
  Scene scene;
  const std::vector<std::string> inputs = {test_data::bundled_file("pointcloud/room_scan1.pcd")};
  build_scene(scene, inputs);
  ASSERT_EQ(scene.layers.size(), 1u);
  const std::vector<std::uint8_t> glb = write_glb_to_memory(scene);
  const fs::path html = dir / "cloud.html";
  write_text_file_atomically(html, standalone_page(glb));
  const JsonValue stats = stats_of(headless_dump_dom(file_url(html.string())));
  expect_page_shows(stats, scene);
  EXPECT_EQ(stats["kinds"]["point_cloud"]["vertices"].as_index(), 112586u);
  EXPECT_EQ(stats["glb_bytes"].as_index(), glb.size());
  fs::remove_all(dir);
}

TEST(ViewerBrowser, ServedPageShowsAGridATrajectoryAndAPoseGraph) {
  const fs::path dir = temp_folder("served");
  const Scene scene = grid_trajectory_graph_scene(dir);
  const std::map<std::string, std::size_t> kinds = kinds_of(scene);
  EXPECT_EQ(kinds.at("grid"), 4u);
  EXPECT_EQ(kinds.at("trajectory"), 41u);
  EXPECT_EQ(kinds.at("graph_vertices"), 60u);
  ViewerServerOptions o;
  o.port = 0;
  ViewerServer server(write_glb_to_memory(scene), o);
  EXPECT_GT(server.port(), 0);
  const JsonValue stats = stats_of(headless_dump_dom(server.url()));
  expect_page_shows(stats, scene);
  // The page, three.js, its loader and controls, the viewer and the scene.
  EXPECT_GE(server.requests(), 6u);
  server.stop();
  fs::remove_all(dir);
}

TEST(ViewerBrowser, AClickAtTheCentrePicksThePointThereWithItsFileIndex) {
  // Three points on a line: the camera looks at the middle one, which the
  // spread order stores as vertex 2 (step 2 of 3): the page must report
  // the file's index 1.
  PointCloud c;
  c.push_back({-1.0f, 0.0f, 0.0f});
  c.push_back({0.0f, 0.0f, 0.0f});
  c.push_back({1.0f, 0.0f, 0.0f});
  Scene scene;
  add_point_cloud(scene, c, "three");
  ASSERT_EQ(scene.layers[0].positions[2], Eigen::Vector3f(0, 0, 0));
  const fs::path dir = temp_folder("pick");
  ViewerPageOptions po;
  po.pick_at = std::array<double, 2>{0.0, 0.0};
  const fs::path html = dir / "pick.html";
  write_text_file_atomically(html, standalone_page(write_glb_to_memory(scene), po));
  const JsonValue stats = stats_of(headless_dump_dom(file_url(html.string())));
  ASSERT_TRUE(stats.contains("pick")) << "no pick in the stats";
  const JsonValue& pick = stats["pick"];
  ASSERT_TRUE(pick.is_object()) << "nothing picked at the centre";
  EXPECT_EQ(pick["layer"].as_string(), "three");
  EXPECT_EQ(pick["index"].as_index(), 1u);
  EXPECT_EQ(pick["x"].as_number(), 0.0);
  fs::remove_all(dir);
}

TEST(ViewerBrowser, AClickOnAGridShowsTheCellItsCentreAndOccupancy) {
  // 11 x 7 cells of 10 cm: the camera looks at the middle of cell (5, 3),
  // the one cell that is not free.
  OccupancyGrid g(0.0f, 1.1f, 0.0f, 0.7f, 0.1f);
  ASSERT_EQ(g.size_x(), 11u);
  ASSERT_EQ(g.size_y(), 7u);
  for (std::uint32_t cy = 0; cy < g.size_y(); ++cy) {
    for (std::uint32_t cx = 0; cx < g.size_x(); ++cx) g.set_free_probability(cx, cy, cx == 5 && cy == 3 ? 0.2f : 1.0f);
  }
  Scene scene;
  add_occupancy_grid(scene, g, "floor");
  const fs::path dir = temp_folder("pick_grid");
  ViewerPageOptions po;
  po.pick_at = std::array<double, 2>{0.0, 0.0};
  const fs::path html = dir / "pick.html";
  write_text_file_atomically(html, standalone_page(write_glb_to_memory(scene), po));
  const JsonValue stats = stats_of(headless_dump_dom(file_url(html.string())));
  ASSERT_TRUE(stats.contains("pick")) << "no pick in the stats";
  const JsonValue& pick = stats["pick"];
  ASSERT_TRUE(pick.is_object()) << "nothing picked at the centre";
  EXPECT_EQ(pick["kind"].as_string(), "grid");
  EXPECT_EQ(pick["layer"].as_string(), "floor");
  ASSERT_TRUE(pick.contains("cell"));
  EXPECT_EQ(pick["cell"][0].as_index(), 5u);
  EXPECT_EQ(pick["cell"][1].as_index(), 3u);
  EXPECT_EQ(pick["index"].as_index(), 3u * 11u + 5u);
  EXPECT_NEAR(pick["x"].as_number(), 0.55, 1e-6);
  EXPECT_NEAR(pick["y"].as_number(), 0.35, 1e-6);
  // The texture holds 255·p(free) rounded.
  ASSERT_TRUE(pick["occupancy"].is_number()) << "the page could not read the texture";
  const double want = 1.0 - std::round(255.0 * g.free_probability(5, 3)) / 255.0;
  EXPECT_NEAR(pick["occupancy"].as_number(), want, 1e-6);
  EXPECT_NEAR(pick["occupancy"].as_number(), 0.8, 0.01);
  fs::remove_all(dir);
}

// Pixel statistics of a gray image: mean, standard deviation, and the share
// of pixels away from the page's background (#1b1e23, gray ≈ 30).
struct PixelStats {
  double mean = 0, stddev = 0, drawn = 0;
};

PixelStats pixel_stats(const GrayImage& img) {
  PixelStats s;
  double sum = 0, sum2 = 0;
  std::size_t drawn = 0;
  for (std::uint8_t v : img.pixels) {
    sum += v;
    sum2 += static_cast<double>(v) * v;
    drawn += std::abs(static_cast<int>(v) - 30) > 12;
  }
  const double n = static_cast<double>(img.pixels.size());
  s.mean = sum / n;
  s.stddev = std::sqrt(std::max(0.0, sum2 / n - s.mean * s.mean));
  s.drawn = static_cast<double>(drawn) / n;
  return s;
}

TEST(ViewerBrowser, ScreenshotMatchesTheReferenceByPixelStatistics) {
  const fs::path dir = temp_folder("shot");
  const Scene scene = grid_trajectory_graph_scene(dir);
  const fs::path html = dir / "scene.html";
  ViewerPageOptions po;
  po.panel = false;
  write_text_file_atomically(html, standalone_page(write_glb_to_memory(scene), po));
  HeadlessOptions h;
  h.width = 480;
  h.height = 320;
  const fs::path png = dir / "scene.png";
  headless_screenshot(file_url(html.string()), png.string(), h);
  const GrayImage shot = read_gray_image(png.string());
  ASSERT_EQ(shot.width, 480u);
  ASSERT_EQ(shot.height, 320u);
  const PixelStats got = pixel_stats(shot);
  const std::string ref_path = test_data::bundled_file("viz/reference_grid_scene.png");
  if (std::getenv("ROVE_UPDATE_REFERENCE") != nullptr) fs::copy_file(png, ref_path, fs::copy_options::overwrite_existing);
  const PixelStats ref = pixel_stats(read_gray_image(ref_path));
  // Not blank: the white floor of the grid and the graph cover a part of it.
  EXPECT_GT(got.drawn, 0.05);
  EXPECT_GT(got.stddev, 15.0);
  // And like the reference within what renderers differ by.
  EXPECT_NEAR(got.mean, ref.mean, 8.0);
  EXPECT_NEAR(got.stddev, ref.stddev, 8.0);
  EXPECT_NEAR(got.drawn, ref.drawn, 0.05);
  fs::remove_all(dir);
}

TEST(ViewerServer, APortInUseIsAClearError) {
  ViewerServerOptions o;
  o.port = 0;
  ViewerServer first(std::vector<std::uint8_t>{}, o);
  o.port = first.port();
  try {
    ViewerServer second(std::vector<std::uint8_t>{}, o);
    FAIL() << "a second server bound port " << o.port;
  } catch (const ResourceError& e) {
    EXPECT_NE(e.message().find(fmt::format("127.0.0.1:{}", o.port)), std::string::npos) << e.message();
    EXPECT_NE(e.message().find("in use"), std::string::npos) << e.message();
  }
}

TEST(ViewerServer, MissingThreeJsNamesTheDebianPackage) {
  ViewerServerOptions o;
  o.port = 0;
  o.page.three_dir = "/nonexistent/three";
  try {
    ViewerServer server(std::vector<std::uint8_t>{}, o);
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(e.message().find("libjs-three"), std::string::npos) << e.message();
  }
}

}  // namespace
}  // namespace rove
