#pragma once
/// \file
/// Layers from rove's types: point clouds, occupancy grids, octrees,
/// trajectories, pose graphs, covariance ellipses, particles, frames and
/// labels. Every builder appends to a Scene and returns the index of the
/// first layer it added. Positions are in the world (map) frame, meters.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/graph/pose_graph.h"
#include "rove/io/trajectory_files.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/maps/occupancy_octree.h"
#include "rove/maps/point_cloud.h"
#include "rove/math/se2.h"
#include "rove/math/se3.h"
#include "rove/viz/scene.h"

namespace rove {

/// Options of add_point_cloud.
struct CloudLayerOptions {
  /// Points kept at most: larger clouds keep an even sample of this many
  /// (the first of the spread order, see Layer::permutation_step).
  std::size_t max_points = 4'000'000;
  float point_size = 2.0f;           ///< pixels
  LayerKind kind = LayerKind::PointCloud;  ///< PointCloud, Voxels or Particles
};

/// What add_point_cloud kept.
struct CloudLayerReport {
  std::size_t layer = 0;        ///< index of the layer added
  std::size_t finite = 0;       ///< points with finite coordinates
  std::size_t skipped = 0;      ///< points with a NaN or infinite coordinate (left out)
  std::size_t kept = 0;         ///< points in the layer (≤ max_points)
};

/// Adds a cloud as points, in spread order (any prefix an even sample),
/// with its colours and intensities when it has them. Points that are not
/// finite are left out and counted; vertex i's source index counts the
/// finite points in cloud order. Throws InvalidArgument if no point is
/// finite or max_points is 0.
CloudLayerReport add_point_cloud(Scene& scene, const PointCloud& cloud, std::string name,
                                 const CloudLayerOptions& options = {});

/// Options of add_occupancy_grid.
struct GridLayerOptions {
  float z = 0.0f;  ///< height of the plane, meters
  /// Longest side of the texture, pixels: larger grids are shrunk by an
  /// integer factor, each texel the most occupied of its cells (WebGL
  /// guarantees 4096).
  std::uint32_t max_texture_side = 4096;
};

/// Adds a grid as a rectangle over its area textured with p(free) in gray
/// (white free, black occupied, mid gray unknown), cells sharp (nearest
/// filtering), with its cells' geometry (Layer::grid) for picking. Throws
/// InvalidArgument for a grid without cells.
std::size_t add_occupancy_grid(Scene& scene, const OccupancyGrid& grid, std::string name,
                               const GridLayerOptions& options = {});

/// Options of add_octree.
struct VoxelLayerOptions {
  /// Occupied leaves drawn as boxes at most; a tree with more is drawn as
  /// the leaves' centres (points) instead.
  std::size_t max_boxes = 200'000;
};

/// Adds the occupied leaves of an octree as boxes of their size, coloured
/// by the tree's colours when it has them, else by height. Throws
/// InvalidArgument when no leaf is occupied.
std::size_t add_octree(Scene& scene, const OccupancyOctree& tree, std::string name,
                       const VoxelLayerOptions& options = {});

/// Options of add_trajectory.
struct TrajectoryLayerOptions {
  LayerKind kind = LayerKind::Trajectory;  ///< Trajectory or Path
  Rgba8 color{255, 200, 40, 255};          ///< line colour
  /// Coordinate frames drawn along it (evenly over the poses), 0 for none.
  std::size_t frames = 12;
  /// Frame axis length, meters; 0 picks 4% of the path's extent (≥ 5 cm).
  double frame_size = 0.0;
  /// Animate with the time slider (Cumulative).
  bool timed = true;
};

/// Adds poses as a line strip with the time of each pose, and frames along
/// it in a second layer. Throws InvalidArgument for no poses or a time that
/// is not finite.
std::size_t add_trajectory(Scene& scene, std::span<const StampedPose3> poses, std::string name,
                           const TrajectoryLayerOptions& options = {});

/// Adds a 2D pose graph (z = 0): vertices as points, edges between
/// consecutive vertex ids in one layer and the others (loop closures)
/// highlighted in another; edges joining the same two vertices (measured
/// both ways, or repeated) are drawn once. Throws InvalidArgument for a
/// graph without vertices.
std::size_t add_pose_graph(Scene& scene, const PoseGraph2D& graph, std::string name);
/// Adds a 3D pose graph (as the 2D overload).
std::size_t add_pose_graph(Scene& scene, const PoseGraph3D& graph, std::string name);

/// A 2D Gaussian position at a time.
struct PositionCovariance2 {
  double time = 0.0;                               ///< seconds (absolute)
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();  ///< meters
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  ///< m², symmetric PSD
};

/// A 3D Gaussian position.
struct PositionCovariance3 {
  double time = 0.0;                               ///< seconds (absolute)
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  ///< meters
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  ///< m², symmetric PSD
};

/// Options of the covariance builders.
struct CovarianceLayerOptions {
  double sigmas = 3.0;          ///< the ellipse is the k-sigma contour, > 0
  std::size_t segments = 48;    ///< segments per ellipse, ≥ 8
  float z = 0.0f;               ///< height of 2D ellipses, meters
  bool timed = true;            ///< Snapshot: one ellipse at a time on the slider
};

/// Adds the k-sigma ellipse of each covariance (line segments, the time of
/// each on its vertices). Throws InvalidArgument for a covariance that is
/// not symmetric positive semi-definite or not finite.
std::size_t add_covariance_ellipses(Scene& scene, std::span<const PositionCovariance2> items,
                                    std::string name, const CovarianceLayerOptions& options = {});
/// Adds each 3D covariance as its k-sigma ellipsoid drawn by its three
/// principal ellipses.
std::size_t add_covariance_ellipsoids(Scene& scene, std::span<const PositionCovariance3> items,
                                      std::string name, const CovarianceLayerOptions& options = {});

/// One particle set at a time.
struct ParticleSnapshot {
  double time = 0.0;                 ///< seconds (absolute)
  std::vector<SE2d> states;          ///< T_map_robot of each particle
  std::vector<double> log_weights;   ///< same size, or empty (equal weights)
};

/// Adds particle sets as points (Snapshot time mode: the slider shows one
/// set), each point's intensity its weight relative to the set's largest.
/// Throws InvalidArgument for an empty set or mismatched weights.
std::size_t add_particles(Scene& scene, std::span<const ParticleSnapshot> snapshots, std::string name);

/// Adds a coordinate frame: axes of `size` meters, x red, y green, z blue.
std::size_t add_frame(Scene& scene, const SE3d& T_world_frame, double size, std::string name);

/// Adds a text label at a point. Throws InvalidArgument for empty text.
std::size_t add_label(Scene& scene, const Eigen::Vector3d& position, std::string text);

/// Points stamped with a time (a scan placed in the world).
struct TimedPoints {
  double time = 0.0;                         ///< seconds (absolute)
  std::vector<Eigen::Vector3f> points;       ///< world frame, meters
};

/// Adds scans placed along a path as one cloud (Cumulative: the slider
/// shows the scans up to its time), at most `max_points` (whole scans
/// thinned evenly). Throws InvalidArgument when there is no point.
std::size_t add_scans(Scene& scene, std::span<const TimedPoints> scans, std::string name,
                      std::size_t max_points = 4'000'000);

/// A colour ramp for t in [0, 1] (blue, cyan, green, yellow, red); t is clamped.
Rgba8 ramp_color(float t) noexcept;

}  // namespace rove
