#include "rove/viz/scene_builders.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/io/grid_image.h"

namespace rove {

namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// Seconds after the scene's time origin (set by the first timed layer).
float relative_time(Scene& scene, double t) {
  ROVE_CHECK_MSG(std::isfinite(t), "a time that is not finite: {}", t);
  if (std::isnan(scene.time_origin)) scene.time_origin = t;
  return static_cast<float>(t - scene.time_origin);
}

// Sets the origin to the earliest of `times` when it is not yet set, so that
// the slider starts at 0.
void seed_time_origin(Scene& scene, double earliest) {
  if (std::isnan(scene.time_origin) && std::isfinite(earliest)) scene.time_origin = earliest;
}

// A step coprime with n near n / φ: i ↦ (i · step) mod n visits every index
// once, and its prefixes are spread evenly over [0, n) (the golden-ratio
// sequence, Weyl's equidistribution).
std::uint64_t spread_step(std::uint64_t n) {
  if (n < 3) return 0;
  std::uint64_t s = static_cast<std::uint64_t>(std::llround(static_cast<double>(n) * 0.6180339887498949));
  s = std::clamp<std::uint64_t>(s, 1, n - 1);
  while (std::gcd(s, n) != 1) ++s;
  return s;
}

Layer& new_layer(Scene& scene, std::string name, LayerKind kind, Primitive primitive, Rgba8 color) {
  Layer& l = scene.layers.emplace_back();
  l.name = std::move(name);
  l.kind = kind;
  l.primitive = primitive;
  l.color = color;
  return l;
}

void finish_layer(Layer& l) { l.source_count = std::max<std::uint64_t>(l.source_count, l.positions.size()); }

Eigen::Vector3f to_f(const Eigen::Vector3d& p) { return p.cast<float>(); }

}  // namespace

Rgba8 ramp_color(float t) noexcept {
  if (!(t >= 0.0f)) t = 0.0f;  // also NaN
  t = std::min(t, 1.0f);
  // Piecewise linear through blue, cyan, green, yellow, red.
  static constexpr float kStops[5][3] = {{0.15f, 0.25f, 0.95f}, {0.0f, 0.85f, 0.95f}, {0.1f, 0.85f, 0.2f},
                                         {0.98f, 0.9f, 0.1f},   {0.9f, 0.15f, 0.1f}};
  const float x = t * 4.0f;
  const int i = std::min(3, static_cast<int>(x));
  const float f = x - static_cast<float>(i);
  const auto mix = [&](int c) {
    return static_cast<std::uint8_t>(std::lround(255.0f * (kStops[i][c] * (1.0f - f) + kStops[i + 1][c] * f)));
  };
  return {mix(0), mix(1), mix(2), 255};
}

CloudLayerReport add_point_cloud(Scene& scene, const PointCloud& cloud, std::string name,
                                 const CloudLayerOptions& options) {
  ROVE_CHECK_GT(options.max_points, std::size_t{0});
  std::vector<std::size_t> finite;
  finite.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cloud[i].allFinite()) finite.push_back(i);
  }
  if (finite.empty()) {
    throw InvalidArgument(fmt::format("cloud '{}' has no finite point ({} points)", name, cloud.size()));
  }
  CloudLayerReport report;
  report.layer = scene.layers.size();
  report.finite = finite.size();
  report.skipped = cloud.size() - finite.size();
  Layer& l = new_layer(scene, std::move(name), options.kind, Primitive::Points, {230, 230, 230, 255});
  l.point_size = options.point_size;
  const std::uint64_t n = finite.size();
  l.source_count = n;
  l.permutation_step = spread_step(n);
  const std::size_t kept = std::min<std::size_t>(n, options.max_points);
  l.positions.resize(kept);
  if (cloud.has_colors()) l.colors.resize(kept);
  if (cloud.has_intensity()) l.intensities.resize(kept);
  std::uint64_t spread = 0;  // l.source_index(i), stepped along
  for (std::size_t i = 0; i < kept; ++i) {
    const std::size_t src = finite[spread];
    if (l.permutation_step != 0) spread = (spread + l.permutation_step) % n;
    else ++spread;
    l.positions[i] = cloud[src];
    if (cloud.has_colors()) {
      const Rgb8 c = cloud.colors()[src];
      l.colors[i] = {c.r, c.g, c.b, 255};
    }
    if (cloud.has_intensity()) l.intensities[i] = cloud.intensities()[src];
  }
  report.kept = kept;
  return report;
}

namespace {

// Shrinks a gray image by an integer factor, each pixel the darkest (most
// occupied) of its block.
GrayImage shrink_darkest(const GrayImage& in, std::uint32_t factor) {
  GrayImage out;
  out.width = (in.width + factor - 1) / factor;
  out.height = (in.height + factor - 1) / factor;
  out.pixels.assign(static_cast<std::size_t>(out.width) * out.height, 255);
  for (std::uint32_t v = 0; v < in.height; ++v) {
    for (std::uint32_t u = 0; u < in.width; ++u) {
      std::uint8_t& o = out.pixels[static_cast<std::size_t>(v / factor) * out.width + u / factor];
      o = std::min(o, in.at(u, v));
    }
  }
  return out;
}

}  // namespace

std::size_t add_occupancy_grid(Scene& scene, const OccupancyGrid& grid, std::string name,
                               const GridLayerOptions& options) {
  if (grid.size_x() == 0 || grid.size_y() == 0) {
    throw InvalidArgument(fmt::format("grid '{}' has no cells", name));
  }
  ROVE_CHECK_GE(options.max_texture_side, 16u);
  GridImageOptions gio;
  gio.mode = RosMapMode::Scale;
  GrayImage image = grid_to_image(grid, gio);
  const std::uint32_t side = std::max(image.width, image.height);
  std::uint32_t cells_per_texel = 1;
  if (side > options.max_texture_side) {
    cells_per_texel = (side + options.max_texture_side - 1) / options.max_texture_side;
    image = shrink_darkest(image, cells_per_texel);
  }
  const std::size_t index = scene.layers.size();
  Layer& l = new_layer(scene, std::move(name), LayerKind::Grid, Primitive::Triangles, {255, 255, 255, 255});
  const float x0 = grid.x_min(), y0 = grid.y_min();
  const float x1 = x0 + static_cast<float>(grid.size_x()) * grid.resolution();
  const float y1 = y0 + static_cast<float>(grid.size_y()) * grid.resolution();
  const float z = options.z;
  // Image row 0 is the largest y; texture v = 0 is the image's top row.
  l.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
  l.uvs = {{0.0f, 1.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, 0.0f}};
  l.indices = {0, 1, 2, 0, 2, 3};
  Texture tex;
  tex.width = image.width;
  tex.height = image.height;
  tex.png = encode_png(image);
  l.texture = std::move(tex);
  l.source_count = static_cast<std::uint64_t>(grid.size_x()) * grid.size_y();
  l.grid = GridCells{grid.x_min(), grid.y_min(), grid.resolution(), static_cast<std::uint32_t>(grid.size_x()),
                     static_cast<std::uint32_t>(grid.size_y()), cells_per_texel};
  return index;
}

namespace {

// The 8 corners and 12 triangles (outward) of an axis-aligned box.
void append_box(Layer& l, const Eigen::Vector3f& c, float half, Rgba8 color) {
  static constexpr int kFaces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                        {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  const auto base = static_cast<std::uint32_t>(l.positions.size());
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3f s((k & 1) ? half : -half, (k & 2) ? half : -half, (k & 4) ? half : -half);
    l.positions.push_back(c + s);
    // Darker bottom corners give the boxes some relief without lighting.
    const float shade = (k & 4) ? 1.0f : 0.7f;
    l.colors.push_back({static_cast<std::uint8_t>(color.r * shade), static_cast<std::uint8_t>(color.g * shade),
                        static_cast<std::uint8_t>(color.b * shade), 255});
  }
  for (const auto& f : kFaces) {
    for (int k : f) l.indices.push_back(base + static_cast<std::uint32_t>(k));
  }
}

}  // namespace

std::size_t add_octree(Scene& scene, const OccupancyOctree& tree, std::string name,
                       const VoxelLayerOptions& options) {
  std::vector<OctreeLeaf> occupied;
  for (const auto& leaf : tree.leaves()) {
    if (tree.is_occupied(leaf.log_odds)) occupied.push_back(leaf);
  }
  if (occupied.empty()) throw InvalidArgument(fmt::format("octree '{}' has no occupied cell", name));
  float zmin = std::numeric_limits<float>::max(), zmax = std::numeric_limits<float>::lowest();
  std::vector<Eigen::Vector3f> centers;
  centers.reserve(occupied.size());
  for (const auto& leaf : occupied) {
    centers.push_back(to_f(tree.center_of(leaf.key, leaf.depth)));
    zmin = std::min(zmin, centers.back().z());
    zmax = std::max(zmax, centers.back().z());
  }
  const bool boxes = occupied.size() <= options.max_boxes;
  const std::size_t index = scene.layers.size();
  Layer& l = new_layer(scene, std::move(name), LayerKind::Voxels,
                       boxes ? Primitive::Triangles : Primitive::Points, {200, 200, 200, 255});
  const float span = std::max(zmax - zmin, 1e-6f);
  const bool colored = has_channels(tree.channels(), OctreeChannels::Color);
  for (std::size_t i = 0; i < occupied.size(); ++i) {
    Rgba8 color = ramp_color((centers[i].z() - zmin) / span);
    if (colored) {
      if (const std::optional<Rgb8> c = tree.color_at(occupied[i].key)) color = {c->r, c->g, c->b, 255};
    }
    if (boxes) {
      const double size = tree.resolution() * std::ldexp(1.0, kOctreeDepth - occupied[i].depth);
      append_box(l, centers[i], static_cast<float>(0.5 * size), color);
    } else {
      l.positions.push_back(centers[i]);
      l.colors.push_back(color);
    }
  }
  l.source_count = std::max<std::uint64_t>(occupied.size(), l.positions.size());
  return index;
}

namespace {

// Frames (three axis segments each) at `count` poses spread over `poses`.
void add_frames_along(Scene& scene, std::span<const StampedPose3> poses, const std::string& name,
                      std::size_t count, double size, bool timed) {
  if (count == 0 || poses.empty()) return;
  Layer& l = new_layer(scene, name + " frames", LayerKind::Frames, Primitive::Lines, {255, 255, 255, 255});
  const std::size_t n = poses.size();
  count = std::min(count, n);
  static const Rgba8 kAxis[3] = {{230, 50, 40, 255}, {60, 200, 60, 255}, {60, 110, 240, 255}};
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = count == 1 ? 0 : k * (n - 1) / (count - 1);
    const SE3d& T = poses[i].pose;
    const Eigen::Matrix3d R = T.rotation_matrix();
    for (int a = 0; a < 3; ++a) {
      l.positions.push_back(to_f(T.translation()));
      l.positions.push_back(to_f(T.translation() + size * R.col(a)));
      l.colors.push_back(kAxis[a]);
      l.colors.push_back(kAxis[a]);
      if (timed) {
        const float t = relative_time(scene, poses[i].time);
        l.times.push_back(t);
        l.times.push_back(t);
      }
    }
  }
  l.time_mode = timed ? TimeMode::Cumulative : TimeMode::None;
  finish_layer(l);
}

}  // namespace

std::size_t add_trajectory(Scene& scene, std::span<const StampedPose3> poses, std::string name,
                           const TrajectoryLayerOptions& options) {
  if (poses.empty()) throw InvalidArgument(fmt::format("trajectory '{}' has no pose", name));
  double earliest = poses.front().time;
  Eigen::Vector3d lo = poses.front().pose.translation(), hi = lo;
  for (const auto& p : poses) {
    if (!std::isfinite(p.time)) throw InvalidArgument(fmt::format("trajectory '{}': a time is not finite", name));
    earliest = std::min(earliest, p.time);
    lo = lo.cwiseMin(p.pose.translation());
    hi = hi.cwiseMax(p.pose.translation());
  }
  if (options.timed) seed_time_origin(scene, earliest);
  const std::size_t index = scene.layers.size();
  {
    Layer& l = new_layer(scene, name, options.kind, poses.size() >= 2 ? Primitive::LineStrip : Primitive::Points,
                         options.color);
    l.point_size = 6.0f;
    for (const auto& p : poses) {
      l.positions.push_back(to_f(p.pose.translation()));
      if (options.timed) l.times.push_back(relative_time(scene, p.time));
    }
    l.time_mode = options.timed ? TimeMode::Cumulative : TimeMode::None;
    finish_layer(l);
  }
  const double size = options.frame_size > 0.0 ? options.frame_size : std::max(0.05, 0.04 * (hi - lo).norm());
  add_frames_along(scene, poses, name, options.frames, size, options.timed);
  return index;
}

namespace {

template <class Graph, class PositionOf>
std::size_t add_graph(Scene& scene, const Graph& graph, const std::string& name, PositionOf position_of) {
  if (graph.num_vertices() == 0) throw InvalidArgument(fmt::format("pose graph '{}' has no vertex", name));
  const std::size_t index = scene.layers.size();
  Layer& v = new_layer(scene, name + " vertices", LayerKind::GraphVertices, Primitive::Points, {120, 200, 255, 255});
  v.point_size = 5.0f;
  for (const auto& [id, vertex] : graph.vertices()) v.positions.push_back(position_of(vertex.pose));
  finish_layer(v);
  Layer odo;
  odo.name = name + " edges";
  odo.kind = LayerKind::GraphEdges;
  odo.primitive = Primitive::Lines;
  odo.color = {150, 160, 180, 255};
  Layer loops = odo;
  loops.name = name + " loop closures";
  loops.kind = LayerKind::LoopEdges;
  loops.color = {255, 60, 60, 255};
  // Each pair of vertices joined once: a relative pose measured both ways
  // (rove rgbd-slam's symmetric edges) is one segment and one loop closure.
  std::set<std::pair<VertexId, VertexId>> joined;
  for (const auto& e : graph.edges()) {
    if (!joined.insert(std::minmax(e.from, e.to)).second) continue;
    Layer& target = (e.to == e.from + 1 || e.from == e.to + 1) ? odo : loops;
    target.positions.push_back(position_of(graph.pose(e.from)));
    target.positions.push_back(position_of(graph.pose(e.to)));
  }
  for (Layer* l : {&odo, &loops}) {
    if (l->positions.empty()) continue;
    finish_layer(*l);
    scene.layers.push_back(std::move(*l));
  }
  return index;
}

}  // namespace

std::size_t add_pose_graph(Scene& scene, const PoseGraph2D& graph, std::string name) {
  return add_graph(scene, graph, name, [](const SE2d& T) {
    return Eigen::Vector3f(static_cast<float>(T.translation().x()), static_cast<float>(T.translation().y()), 0.0f);
  });
}

std::size_t add_pose_graph(Scene& scene, const PoseGraph3D& graph, std::string name) {
  return add_graph(scene, graph, name, [](const SE3d& T) { return to_f(T.translation()); });
}

namespace {

template <int N>
Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> checked_eigen(const Eigen::Matrix<double, N, N>& C,
                                                                          const std::string& name, std::size_t i) {
  const double scale = std::max(1.0, C.cwiseAbs().maxCoeff());
  if (!C.allFinite() || (C - C.transpose()).cwiseAbs().maxCoeff() > 1e-9 * scale) {
    throw InvalidArgument(fmt::format("covariance {} of '{}' is not finite and symmetric", i, name));
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(C);
  if (es.eigenvalues().minCoeff() < -1e-9 * scale) {
    throw InvalidArgument(fmt::format("covariance {} of '{}' is not positive semi-definite (eigenvalue {})", i,
                                      name, es.eigenvalues().minCoeff()));
  }
  return es;
}

// Appends the ellipse c + k·(√λa·cos s·a + √λb·sin s·b) as segments.
void append_ellipse(Layer& l, const Eigen::Vector3d& c, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    std::size_t segments, float time, bool timed) {
  for (std::size_t s = 0; s < segments; ++s) {
    for (std::size_t e : {s, s + 1}) {
      const double ang = kTwoPi * static_cast<double>(e % segments) / static_cast<double>(segments);
      l.positions.push_back(to_f(c + std::cos(ang) * a + std::sin(ang) * b));
      if (timed) l.times.push_back(time);
    }
  }
}

void check_covariance_options(const CovarianceLayerOptions& o) {
  ROVE_CHECK_MSG(o.sigmas > 0.0 && std::isfinite(o.sigmas), "sigmas must be positive: {}", o.sigmas);
  ROVE_CHECK_GE(o.segments, std::size_t{8});
}

template <class Item>
void seed_from_items(Scene& scene, std::span<const Item> items, bool timed) {
  if (!timed || items.empty()) return;
  double earliest = items.front().time;
  for (const auto& it : items) earliest = std::min(earliest, it.time);
  seed_time_origin(scene, earliest);
}

}  // namespace

std::size_t add_covariance_ellipses(Scene& scene, std::span<const PositionCovariance2> items, std::string name,
                                    const CovarianceLayerOptions& options) {
  check_covariance_options(options);
  if (items.empty()) throw InvalidArgument(fmt::format("covariances '{}': none given", name));
  seed_from_items(scene, items, options.timed);
  const std::size_t index = scene.layers.size();
  Layer& l = new_layer(scene, std::move(name), LayerKind::Covariance, Primitive::Lines, {255, 120, 220, 255});
  for (std::size_t i = 0; i < items.size(); ++i) {
    const auto es = checked_eigen<2>(items[i].covariance, l.name, i);
    const Eigen::Vector2d sd = es.eigenvalues().cwiseMax(0.0).cwiseSqrt() * options.sigmas;
    const Eigen::Vector3d a(sd(0) * es.eigenvectors()(0, 0), sd(0) * es.eigenvectors()(1, 0), 0.0);
    const Eigen::Vector3d b(sd(1) * es.eigenvectors()(0, 1), sd(1) * es.eigenvectors()(1, 1), 0.0);
    const Eigen::Vector3d c(items[i].mean.x(), items[i].mean.y(), options.z);
    const float t = options.timed ? relative_time(scene, items[i].time) : 0.0f;
    append_ellipse(l, c, a, b, options.segments, t, options.timed);
  }
  l.time_mode = options.timed ? TimeMode::Snapshot : TimeMode::None;
  finish_layer(l);
  return index;
}

std::size_t add_covariance_ellipsoids(Scene& scene, std::span<const PositionCovariance3> items, std::string name,
                                      const CovarianceLayerOptions& options) {
  check_covariance_options(options);
  if (items.empty()) throw InvalidArgument(fmt::format("covariances '{}': none given", name));
  seed_from_items(scene, items, options.timed);
  const std::size_t index = scene.layers.size();
  Layer& l = new_layer(scene, std::move(name), LayerKind::Covariance, Primitive::Lines, {255, 120, 220, 255});
  for (std::size_t i = 0; i < items.size(); ++i) {
    const auto es = checked_eigen<3>(items[i].covariance, l.name, i);
    Eigen::Matrix3d axes = es.eigenvectors();
    for (int k = 0; k < 3; ++k) axes.col(k) *= std::sqrt(std::max(0.0, es.eigenvalues()(k))) * options.sigmas;
    const float t = options.timed ? relative_time(scene, items[i].time) : 0.0f;
    for (const auto& [p, q] : {std::pair{0, 1}, std::pair{1, 2}, std::pair{0, 2}}) {
      append_ellipse(l, items[i].mean, axes.col(p), axes.col(q), options.segments, t, options.timed);
    }
  }
  l.time_mode = options.timed ? TimeMode::Snapshot : TimeMode::None;
  finish_layer(l);
  return index;
}

std::size_t add_particles(Scene& scene, std::span<const ParticleSnapshot> snapshots, std::string name) {
  if (snapshots.empty()) throw InvalidArgument(fmt::format("particles '{}': no set given", name));
  seed_from_items(scene, snapshots, true);
  const std::size_t index = scene.layers.size();
  Layer& l = new_layer(scene, std::move(name), LayerKind::Particles, Primitive::Points, {255, 90, 60, 255});
  l.point_size = 3.0f;
  for (std::size_t s = 0; s < snapshots.size(); ++s) {
    const ParticleSnapshot& snap = snapshots[s];
    if (snap.states.empty()) throw InvalidArgument(fmt::format("particles '{}': set {} is empty", l.name, s));
    if (!snap.log_weights.empty() && snap.log_weights.size() != snap.states.size()) {
      throw InvalidArgument(fmt::format("particles '{}': set {} has {} weights for {} particles", l.name, s,
                                        snap.log_weights.size(), snap.states.size()));
    }
    const double top = snap.log_weights.empty()
                           ? 0.0
                           : *std::max_element(snap.log_weights.begin(), snap.log_weights.end());
    const float t = relative_time(scene, snap.time);
    for (std::size_t i = 0; i < snap.states.size(); ++i) {
      const Eigen::Vector2d& p = snap.states[i].translation();
      l.positions.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.02f);
      const double w = snap.log_weights.empty() ? 1.0 : std::exp(snap.log_weights[i] - top);
      l.intensities.push_back(static_cast<float>(std::isfinite(w) ? w : 0.0));
      l.times.push_back(t);
    }
  }
  l.time_mode = TimeMode::Snapshot;
  finish_layer(l);
  return index;
}

std::size_t add_frame(Scene& scene, const SE3d& T_world_frame, double size, std::string name) {
  ROVE_CHECK_MSG(size > 0.0 && std::isfinite(size), "frame size must be positive: {}", size);
  const StampedPose3 pose{0.0, T_world_frame};
  const std::size_t index = scene.layers.size();
  add_frames_along(scene, std::span<const StampedPose3>(&pose, 1), name, 1, size, false);
  scene.layers[index].name = std::move(name);
  return index;
}

std::size_t add_label(Scene& scene, const Eigen::Vector3d& position, std::string text) {
  if (text.empty()) throw InvalidArgument("a label needs text");
  ROVE_CHECK_FINITE(position);
  const std::size_t index = scene.layers.size();
  Layer& l = new_layer(scene, text, LayerKind::Label, Primitive::Points, {255, 255, 255, 255});
  l.positions.push_back(to_f(position));
  l.text = std::move(text);
  finish_layer(l);
  return index;
}

std::size_t add_scans(Scene& scene, std::span<const TimedPoints> scans, std::string name, std::size_t max_points) {
  ROVE_CHECK_GT(max_points, std::size_t{0});
  std::size_t total = 0;
  for (const auto& s : scans) total += s.points.size();
  if (total == 0) throw InvalidArgument(fmt::format("scans '{}': no point", name));
  seed_from_items(scene, scans, true);
  // Keep every k-th point of each scan so that the whole path stays covered.
  const std::size_t stride = (total + max_points - 1) / max_points;
  Layer l;
  l.name = std::move(name);
  l.kind = LayerKind::Scans;
  l.primitive = Primitive::Points;
  l.color = {120, 255, 160, 255};
  l.source_count = total;
  for (const auto& s : scans) {
    const float t = relative_time(scene, s.time);
    for (std::size_t i = 0; i < s.points.size(); i += stride) {
      if (!s.points[i].allFinite()) continue;
      l.positions.push_back(s.points[i]);
      l.times.push_back(t);
    }
  }
  if (l.positions.empty()) throw InvalidArgument(fmt::format("scans '{}': no finite point", l.name));
  l.time_mode = TimeMode::Cumulative;
  scene.layers.push_back(std::move(l));
  return scene.layers.size() - 1;
}

}  // namespace rove
