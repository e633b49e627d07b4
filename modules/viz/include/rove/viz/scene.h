#pragma once
/// \file
/// A 3D scene for people to look at: layers of points, lines and triangles
/// in the world frame (meters, z up), each with what it shows (a point
/// cloud, a grid map, a trajectory, a pose graph, ...) so that a viewer can
/// offer toggles, colour modes and a time slider. Scenes are written as
/// glTF 2.0 (glb.h) and shown in a browser (viewer_page.h).
///
/// A scene holds plain arrays; the builders in scene_builders.h turn rove's
/// types (PointCloud, OccupancyGrid, OccupancyOctree, trajectories, pose
/// graphs, particles, covariances) into layers.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace rove {

/// An 8-bit colour with opacity.
struct Rgba8 {
  std::uint8_t r = 255;  ///< red, 0..255
  std::uint8_t g = 255;  ///< green, 0..255
  std::uint8_t b = 255;  ///< blue, 0..255
  std::uint8_t a = 255;  ///< opacity, 0 (transparent) .. 255 (opaque)
  /// Equality.
  friend bool operator==(const Rgba8&, const Rgba8&) = default;
};

/// What a layer shows; the viewer groups, colours and animates by it.
enum class LayerKind : std::uint8_t {
  PointCloud,  ///< a cloud from a file or a map (colour, height, intensity)
  Scans,       ///< range scans placed along a path (time per point)
  Grid,        ///< an occupancy grid: a textured rectangle
  Voxels,      ///< occupied octree cells: boxes
  Trajectory,  ///< poses in time: a line strip (time per vertex)
  Path,        ///< a planned or driven path: a line strip
  Frames,      ///< coordinate frames: x red, y green, z blue
  GraphVertices,  ///< pose-graph vertices: points
  GraphEdges,     ///< pose-graph edges between consecutive vertices
  LoopEdges,      ///< pose-graph edges closing loops (highlighted)
  Covariance,     ///< uncertainty ellipses or ellipsoids: lines
  Particles,      ///< particle sets (time per snapshot)
  Label,          ///< a text at a point
};

/// "point_cloud", "scans", "grid", "voxels", "trajectory", "path", "frames",
/// "graph_vertices", "graph_edges", "loop_edges", "covariance", "particles",
/// "label": the names written into the glTF metadata.
const char* to_string(LayerKind kind) noexcept;

/// How a layer's vertices are joined (glTF's primitive modes).
enum class Primitive : std::uint8_t {
  Points,     ///< each vertex a point
  Lines,      ///< vertices 2k, 2k+1 a segment (or indices in pairs)
  LineStrip,  ///< consecutive vertices joined
  Triangles,  ///< vertices (or indices) in threes
};

/// How a timed layer is shown at slider time t.
enum class TimeMode : std::uint8_t {
  None,        ///< no times: always shown whole
  Cumulative,  ///< the vertices with time ≤ t (a trajectory grows)
  Snapshot,    ///< only the vertices of the latest time ≤ t (one particle set)
};

/// Which way is up in a scene's world frame, for the viewer's camera and
/// its colour by height (positions keep the frame of their files).
enum class SceneUp : std::uint8_t {
  PlusZ,   ///< z up: maps, robots, rove's 2D and 3D SLAM
  MinusY,  ///< −y up: a camera's optical frame (x right, y down, z forward), e.g. rove rgbd-slam
};

/// "z" or "-y": the name written into the glTF metadata.
const char* to_string(SceneUp up) noexcept;

/// The cells behind a grid layer's texture, so that a viewer can tell the
/// cell under the cursor: cell (cx, cy) covers x_min + cx·resolution ..
/// + resolution and likewise in y; its texel is column cx / cells_per_texel,
/// row (size_y − 1 − cy) / cells_per_texel of the texture (row 0 at the
/// top, integer division).
struct GridCells {
  double x_min = 0.0;                ///< meters, left edge of cell column 0
  double y_min = 0.0;                ///< meters, lower edge of cell row 0
  double resolution = 0.0;           ///< meters per cell, > 0
  std::uint32_t size_x = 0;          ///< cells along x
  std::uint32_t size_y = 0;          ///< cells along y
  /// Cells per texel side: 1, or k when the texture was shrunk by k (each
  /// texel the most occupied of its k × k cells).
  std::uint32_t cells_per_texel = 1;
};

/// An image for a textured layer, as PNG bytes.
struct Texture {
  std::uint32_t width = 0;          ///< pixels
  std::uint32_t height = 0;         ///< pixels
  std::vector<std::uint8_t> png;    ///< the encoded image
};

/// One drawable of a scene. Vertex arrays are either empty or as long as
/// `positions`.
struct Layer {
  std::string name;                          ///< shown in the layer list (e.g. the file name)
  LayerKind kind = LayerKind::PointCloud;    ///< what it shows
  Primitive primitive = Primitive::Points;   ///< how vertices are joined
  std::vector<Eigen::Vector3f> positions;    ///< world frame, meters
  std::vector<Rgba8> colors;                 ///< per vertex, or empty (uniform `color`)
  std::vector<float> intensities;            ///< per vertex (sensor units), or empty
  std::vector<float> times;                  ///< per vertex, seconds after Scene::time_origin, or empty
  std::vector<Eigen::Vector2f> uvs;          ///< texture coordinates (glTF: (0,0) top left), or empty
  std::vector<std::uint32_t> indices;        ///< into positions, or empty (vertices in order)
  std::optional<Texture> texture;            ///< image drawn on the triangles (needs uvs)
  Rgba8 color;                               ///< colour when `colors` is empty
  float point_size = 2.0f;                   ///< pixels, for points
  TimeMode time_mode = TimeMode::None;       ///< how `times` animate it
  std::string text;                          ///< a label's text
  /// Drawn when the page opens; false starts the layer hidden (its box in
  /// the layer list unticked), e.g. a map's octree beneath its cloud.
  bool shown = true;
  /// For a Grid layer: its cells (the texture holds p(free) in gray,
  /// 255·p rounded); empty for other layers.
  std::optional<GridCells> grid;
  /// Elements of the source before decimation (points of a cloud, poses);
  /// equals positions.size() when nothing was dropped.
  std::uint64_t source_count = 0;
  /// Vertex i came from source element (i · permutation_step) mod
  /// source_count; 0 means vertex i is element i. Clouds are stored in this
  /// spread order so that any prefix is an even sample (level of detail).
  std::uint64_t permutation_step = 0;
  /// Source element index of vertex i (see permutation_step).
  std::uint64_t source_index(std::uint64_t i) const noexcept;
};

/// Axis-aligned bounds of a scene, meters.
struct SceneBounds {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());  ///< lower corner
  Eigen::Vector3f max = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());  ///< upper corner
  /// True when nothing was added.
  bool empty() const noexcept { return (min.array() > max.array()).any(); }
};

/// A scene: layers in the world frame, z up.
struct Scene {
  std::string title = "rove";              ///< page and glTF scene name
  std::vector<Layer> layers;               ///< drawn in order
  /// Absolute time (seconds, e.g. since the Unix epoch) that layer times are
  /// relative to (floats keep microseconds only near zero); NaN until a
  /// timed layer is added.
  double time_origin = std::numeric_limits<double>::quiet_NaN();
  /// The files the scene was built from.
  std::vector<std::string> sources;
  /// Which way is up in the world frame.
  SceneUp up = SceneUp::PlusZ;

  /// Vertices over all layers.
  std::size_t vertex_count() const noexcept;
  /// Bounds of every position.
  SceneBounds bounds() const noexcept;
  /// Checks every layer: vertex arrays empty or as long as positions,
  /// indices in range and complete primitives, finite positions, uvs with a
  /// texture, a label with text, grid cells only on a textured Grid layer
  /// and consistent with its texture. Throws InvalidArgument naming the layer.
  void check() const;
};

}  // namespace rove
