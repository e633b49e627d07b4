#include "rove/viz/scene.h"

#include <fmt/format.h>

#include <cmath>

#include "rove/core/error.h"

namespace rove {

const char* to_string(LayerKind kind) noexcept {
  switch (kind) {
    case LayerKind::PointCloud: return "point_cloud";
    case LayerKind::Scans: return "scans";
    case LayerKind::Grid: return "grid";
    case LayerKind::Voxels: return "voxels";
    case LayerKind::Trajectory: return "trajectory";
    case LayerKind::Path: return "path";
    case LayerKind::Frames: return "frames";
    case LayerKind::GraphVertices: return "graph_vertices";
    case LayerKind::GraphEdges: return "graph_edges";
    case LayerKind::LoopEdges: return "loop_edges";
    case LayerKind::Covariance: return "covariance";
    case LayerKind::Particles: return "particles";
    case LayerKind::Label: return "label";
  }
  return "unknown";
}

const char* to_string(SceneUp up) noexcept {
  switch (up) {
    case SceneUp::PlusZ: return "z";
    case SceneUp::MinusY: return "-y";
  }
  return "unknown";
}

std::uint64_t Layer::source_index(std::uint64_t i) const noexcept {
  if (permutation_step == 0 || source_count == 0) return i;
  // (i · step) mod n by doubling: every sum stays below 2n < 2^64 since
  // n < 2^63 (a count of elements in memory).
  std::uint64_t a = i % source_count, b = permutation_step % source_count, r = 0;
  while (b != 0) {
    if (b & 1) r = (r + a) % source_count;
    a = (a + a) % source_count;
    b >>= 1;
  }
  return r;
}

std::size_t Scene::vertex_count() const noexcept {
  std::size_t n = 0;
  for (const auto& l : layers) n += l.positions.size();
  return n;
}

SceneBounds Scene::bounds() const noexcept {
  SceneBounds b;
  for (const auto& l : layers) {
    for (const auto& p : l.positions) {
      b.min = b.min.cwiseMin(p);
      b.max = b.max.cwiseMax(p);
    }
  }
  return b;
}

namespace {

std::size_t vertices_per_primitive(Primitive p) {
  switch (p) {
    case Primitive::Points: return 1;
    case Primitive::Lines: return 2;
    case Primitive::LineStrip: return 1;
    case Primitive::Triangles: return 3;
  }
  return 1;
}

void check_layer(const Layer& l, std::size_t index) {
  const auto fail = [&](const std::string& what) {
    throw InvalidArgument(fmt::format("scene layer {} '{}' ({}): {}", index, l.name, to_string(l.kind), what));
  };
  const std::size_t n = l.positions.size();
  if (n == 0) fail("no vertices");
  const auto same_size = [&](std::size_t size, const char* what) {
    if (size != 0 && size != n) fail(fmt::format("{} {} for {} vertices", size, what, n));
  };
  same_size(l.colors.size(), "colours");
  same_size(l.intensities.size(), "intensities");
  same_size(l.times.size(), "times");
  same_size(l.uvs.size(), "texture coordinates");
  for (std::size_t i = 0; i < n; ++i) {
    if (!l.positions[i].allFinite()) fail(fmt::format("vertex {} is not finite", i));
  }
  for (std::size_t i = 0; i < l.times.size(); ++i) {
    if (!std::isfinite(l.times[i])) fail(fmt::format("time {} is not finite", i));
  }
  if (l.time_mode != TimeMode::None && l.times.empty()) fail("a time mode without times");
  const std::size_t elements = l.indices.empty() ? n : l.indices.size();
  if (elements % vertices_per_primitive(l.primitive) != 0) {
    fail(fmt::format("{} vertices do not make whole primitives", elements));
  }
  if (l.primitive == Primitive::LineStrip && elements < 2) fail("a line strip of one vertex");
  for (std::uint32_t k : l.indices) {
    if (k >= n) fail(fmt::format("index {} out of range ({} vertices)", k, n));
  }
  if (l.texture.has_value() != !l.uvs.empty()) fail("texture coordinates without a texture, or the reverse");
  if (l.texture && (l.texture->png.empty() || l.texture->width == 0 || l.texture->height == 0)) {
    fail("an empty texture");
  }
  if (l.kind == LayerKind::Label && l.text.empty()) fail("a label without text");
  if (!(l.point_size > 0.0f) || !std::isfinite(l.point_size)) fail("point size must be positive");
  if (l.source_count < n) fail(fmt::format("source count {} below {} vertices", l.source_count, n));
  if (l.grid) {
    const GridCells& g = *l.grid;
    if (l.kind != LayerKind::Grid || !l.texture) fail("grid cells on a layer that is not a textured grid");
    if (!(g.resolution > 0.0) || !std::isfinite(g.resolution) || !std::isfinite(g.x_min) || !std::isfinite(g.y_min)) {
      fail(fmt::format("grid cells of resolution {} at ({}, {})", g.resolution, g.x_min, g.y_min));
    }
    const auto texels = [&](std::uint32_t cells) { return (cells + g.cells_per_texel - 1) / g.cells_per_texel; };
    if (g.size_x == 0 || g.size_y == 0 || g.cells_per_texel == 0 || texels(g.size_x) != l.texture->width ||
        texels(g.size_y) != l.texture->height) {
      fail(fmt::format("{} x {} grid cells ({} per texel) do not make its {} x {} texture", g.size_x, g.size_y,
                       g.cells_per_texel, l.texture->width, l.texture->height));
    }
  }
}

}  // namespace

void Scene::check() const {
  for (std::size_t i = 0; i < layers.size(); ++i) check_layer(layers[i], i);
}

}  // namespace rove
