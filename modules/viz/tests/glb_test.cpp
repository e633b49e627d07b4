#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "rove/core/error.h"
#include "rove/viz/glb.h"
#include "rove/viz/scene_builders.h"

namespace rove {
namespace {

// The floats of accessor `a` (float component type), read through its buffer view.
std::vector<float> read_floats(const GlbContents& g, std::size_t a) {
  const JsonValue& acc = g.json["accessors"][a];
  EXPECT_EQ(acc["componentType"].as_number(), 5126);
  const JsonValue& view = g.json["bufferViews"][acc["bufferView"].as_index()];
  const std::size_t offset = view["byteOffset"].as_index(), length = view["byteLength"].as_index();
  EXPECT_EQ(offset % 4, 0u);
  EXPECT_LE(offset + length, g.bin.size());
  std::vector<float> out(length / 4);
  std::memcpy(out.data(), g.bin.data() + offset, length);
  return out;
}

Scene two_layer_scene() {
  Scene s;
  s.title = "test";
  PointCloud cloud;
  cloud.set_channels(PointChannels::Color);
  cloud.push_back({1.0f, 2.0f, 3.0f}, Rgb8{255, 0, 0});
  cloud.push_back({-1.0f, 0.5f, 0.25f}, Rgb8{0, 255, 0});
  cloud.push_back({0.0f, -4.0f, 1.0f}, Rgb8{0, 0, 255});
  add_point_cloud(s, cloud, "cloud");
  std::vector<StampedPose3> traj = {{10.0, SE3d()}, {11.0, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0))},
                                    {12.5, SE3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 1, 0))}};
  TrajectoryLayerOptions o;
  o.frames = 2;
  add_trajectory(s, traj, "path", o);
  return s;
}

TEST(Glb, HeaderChunksAndAccessorsRoundTrip) {
  const Scene s = two_layer_scene();
  ASSERT_EQ(s.layers.size(), 3u);  // cloud, path, path frames
  const std::vector<std::uint8_t> bytes = write_glb_to_memory(s);
  ASSERT_GE(bytes.size(), 28u);
  EXPECT_EQ(std::memcmp(bytes.data(), "glTF", 4), 0);
  const GlbContents g = parse_glb(bytes, "mem");
  EXPECT_EQ(g.version, 2u);
  EXPECT_EQ(g.json["asset"]["version"].as_string(), "2.0");
  EXPECT_EQ(g.bin.size() % 4, 0u);
  EXPECT_EQ(g.json["buffers"][0]["byteLength"].as_index(), g.bin.size());
  // Root node (z up → y up) then one node per layer.
  const auto& nodes = g.json["nodes"].as_array();
  ASSERT_EQ(nodes.size(), 4u);
  EXPECT_NEAR(nodes[0]["rotation"][0].as_number(), -std::sqrt(0.5), 1e-15);
  EXPECT_EQ(nodes[0]["children"].as_array().size(), 3u);
  EXPECT_EQ(nodes[1]["extras"]["rove"]["kind"].as_string(), "point_cloud");
  EXPECT_EQ(nodes[2]["extras"]["rove"]["kind"].as_string(), "trajectory");
  EXPECT_EQ(nodes[2]["extras"]["rove"]["time_mode"].as_string(), "cumulative");
  EXPECT_EQ(nodes[3]["extras"]["rove"]["kind"].as_string(), "frames");
  const JsonValue& extras = g.json["scenes"][0]["extras"]["rove"];
  EXPECT_EQ(extras["time_origin"].as_number(), 10.0);
  EXPECT_EQ(extras["vertices"].as_index(), 3u + 3u + 12u);

  // The cloud: POSITION with exact bounds, COLOR_0 as normalized bytes.
  const JsonValue& prim = g.json["meshes"][0]["primitives"][0];
  EXPECT_EQ(prim["mode"].as_number(), 0);
  const std::size_t pa = prim["attributes"]["POSITION"].as_index();
  const JsonValue& pacc = g.json["accessors"][pa];
  EXPECT_EQ(pacc["count"].as_index(), 3u);
  EXPECT_EQ(pacc["type"].as_string(), "VEC3");
  EXPECT_EQ(pacc["min"][0].as_number(), -1.0);
  EXPECT_EQ(pacc["min"][1].as_number(), -4.0);
  EXPECT_EQ(pacc["min"][2].as_number(), 0.25);
  EXPECT_EQ(pacc["max"][0].as_number(), 1.0);
  EXPECT_EQ(pacc["max"][1].as_number(), 2.0);
  EXPECT_EQ(pacc["max"][2].as_number(), 3.0);
  const std::vector<float> pos = read_floats(g, pa);
  ASSERT_EQ(pos.size(), 9u);
  // Every input point is there once (in spread order).
  float sum_x = 0, sum_y = 0, sum_z = 0;
  for (int i = 0; i < 3; ++i) {
    sum_x += pos[3 * i];
    sum_y += pos[3 * i + 1];
    sum_z += pos[3 * i + 2];
  }
  EXPECT_EQ(sum_x, 0.0f);
  EXPECT_EQ(sum_y, -1.5f);
  EXPECT_EQ(sum_z, 4.25f);
  const JsonValue& cacc = g.json["accessors"][prim["attributes"]["COLOR_0"].as_index()];
  EXPECT_EQ(cacc["componentType"].as_number(), 5121);
  EXPECT_TRUE(cacc["normalized"].as_bool());
  EXPECT_EQ(cacc["type"].as_string(), "VEC4");

  // The trajectory: a line strip with its times after the origin.
  const JsonValue& tprim = g.json["meshes"][1]["primitives"][0];
  EXPECT_EQ(tprim["mode"].as_number(), 3);
  const std::vector<float> times = read_floats(g, tprim["attributes"]["_TIME"].as_index());
  EXPECT_EQ(times, (std::vector<float>{0.0f, 1.0f, 2.5f}));
  // Every material is unlit.
  for (const auto& m : g.json["materials"].as_array()) EXPECT_TRUE(m["extensions"].contains("KHR_materials_unlit"));
}

TEST(Glb, UpAxisAndGridCellsAreInTheMetadata) {
  Scene s;
  add_occupancy_grid(s, OccupancyGrid(-1.0f, 2.0f, 0.5f, 1.5f, 0.25f), "floor");
  GlbContents g = parse_glb(write_glb_to_memory(s), "mem");
  EXPECT_EQ(g.json["scenes"][0]["extras"]["rove"]["up"].as_string(), "z");
  const JsonValue& cells = g.json["nodes"][1]["extras"]["rove"]["grid"];
  EXPECT_EQ(cells["x_min"].as_number(), -1.0);
  EXPECT_EQ(cells["y_min"].as_number(), 0.5);
  EXPECT_EQ(cells["resolution"].as_number(), 0.25);
  EXPECT_EQ(cells["size_x"].as_index(), 12u);
  EXPECT_EQ(cells["size_y"].as_index(), 4u);
  EXPECT_EQ(cells["cells_per_texel"].as_index(), 1u);
  // A camera's optical frame: −y up becomes glTF's y up by 180° about x
  // (quaternion x y z w = 1 0 0 0), which maps (0, −1, 0) to (0, 1, 0).
  s.up = SceneUp::MinusY;
  g = parse_glb(write_glb_to_memory(s), "mem");
  EXPECT_EQ(g.json["scenes"][0]["extras"]["rove"]["up"].as_string(), "-y");
  const JsonValue& q = g.json["nodes"][0]["rotation"];
  EXPECT_EQ(q[0].as_number(), 1.0);
  EXPECT_EQ(q[3].as_number(), 0.0);
}

TEST(Glb, EveryAccessorFitsItsViewAndTheBuffer) {
  Scene s = two_layer_scene();
  OccupancyGrid grid(-1.0f, 1.0f, -2.0f, 2.0f, 0.1f);
  add_occupancy_grid(s, grid, "grid");
  const GlbContents g = parse_glb(write_glb_to_memory(s), "mem");
  static const std::map<std::string, std::size_t> kComponents = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}};
  for (const auto& acc : g.json["accessors"].as_array()) {
    const JsonValue& view = g.json["bufferViews"][acc["bufferView"].as_index()];
    const std::size_t size = acc["componentType"].as_number() == 5121 ? 1 : 4;
    EXPECT_EQ(view["byteLength"].as_index(), acc["count"].as_index() * kComponents.at(acc["type"].as_string()) * size);
    EXPECT_LE(view["byteOffset"].as_index() + view["byteLength"].as_index(), g.bin.size());
  }
  // The grid's texture is a PNG in the buffer, sampled nearest.
  const JsonValue& image = g.json["images"][0];
  EXPECT_EQ(image["mimeType"].as_string(), "image/png");
  const JsonValue& view = g.json["bufferViews"][image["bufferView"].as_index()];
  EXPECT_EQ(std::memcmp(g.bin.data() + view["byteOffset"].as_index(), "\x89PNG", 4), 0);
  EXPECT_EQ(g.json["samplers"][0]["magFilter"].as_number(), 9728);
  // Indices of the grid's two triangles.
  const JsonValue& prim = g.json["meshes"][3]["primitives"][0];
  EXPECT_EQ(prim["mode"].as_number(), 4);
  EXPECT_EQ(g.json["accessors"][prim["indices"].as_index()]["count"].as_index(), 6u);
}

TEST(Glb, CorruptFilesAreParseErrors) {
  std::vector<std::uint8_t> bytes = write_glb_to_memory(two_layer_scene());
  auto truncated = bytes;
  truncated.resize(bytes.size() - 4);
  EXPECT_THROW(parse_glb(truncated, "t"), ParseError);
  auto bad_magic = bytes;
  bad_magic[0] = 'x';
  EXPECT_THROW(parse_glb(bad_magic, "m"), ParseError);
  auto bad_json = bytes;
  bad_json[20] = '!';  // first byte of the JSON chunk
  EXPECT_THROW(parse_glb(bad_json, "j"), ParseError);
  EXPECT_THROW(parse_glb(std::vector<std::uint8_t>(8, 0), "short"), ParseError);
}

TEST(Glb, InvalidScenesAreRefused) {
  Scene s;
  Layer& l = s.layers.emplace_back();
  l.name = "bad";
  l.positions = {{0, 0, 0}, {1, 1, 1}};
  l.colors.resize(1);
  l.source_count = 2;
  EXPECT_THROW(write_glb_to_memory(s), InvalidArgument);
  l.colors.clear();
  l.positions[1].x() = std::nanf("");
  EXPECT_THROW(write_glb_to_memory(s), InvalidArgument);
}

TEST(Glb, ALayerThatStartsHiddenSaysSoAndOnlyIt) {
  Scene s = two_layer_scene();
  s.layers[0].shown = false;
  const GlbContents g = parse_glb(write_glb_to_memory(s), "mem");
  const auto& nodes = g.json["nodes"].as_array();
  ASSERT_EQ(nodes.size(), 4u);
  ASSERT_TRUE(nodes[1]["extras"]["rove"].contains("shown"));
  EXPECT_FALSE(nodes[1]["extras"]["rove"]["shown"].as_bool());
  EXPECT_FALSE(nodes[2]["extras"]["rove"].contains("shown"));  // shown: the key is left out
  EXPECT_FALSE(nodes[3]["extras"]["rove"].contains("shown"));
}

}  // namespace
}  // namespace rove
