#pragma once
/// \file
/// An occupancy octree built from point cloud files (PCD, PLY) and their
/// sensor origins: what `rove octomap build` (and rove.octomap_build) run.
/// Each cloud is inserted as OctoMap's insertPointCloud does
/// (OccupancyOctree::insert_point_cloud), in the order given; clouds with
/// colours make the tree OctoMap's ColorOcTree (octree_color_mean.h).

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/io/octree_files.h"
#include "rove/io/trajectory_files.h"
#include "rove/maps/occupancy_octree.h"

namespace rove {

/// What the clouds' colours do (`--color`).
enum class OctreeColorRule : std::uint8_t {
  Mean,       ///< each leaf the mean colour of the points in it
  Average,    ///< OctoMap's averageNodeColor, point after point
  Integrate,  ///< OctoMap's integrateNodeColor, point after point
  Set,        ///< OctoMap's setNodeColor, point after point
  None,       ///< colours ignored
};

/// Parses "mean", "average", "integrate", "set" or "none"; throws
/// InvalidArgument otherwise.
OctreeColorRule parse_octree_color_rule(std::string_view text);
/// The lowercase name (parse_octree_color_rule's input).
std::string_view to_string(OctreeColorRule rule);

/// Parses "once", "discretized" or "every-ray" (OncePerScan, Discretized,
/// EveryRay); throws InvalidArgument otherwise.
OctreeUpdateMode parse_octree_update_mode(std::string_view text);
/// Parses "double" or "octomap"; throws InvalidArgument otherwise.
OctreeRayArithmetic parse_octree_ray_arithmetic(std::string_view text);

/// Options of build_octree.
struct OctreeBuildOptions {
  /// Edge of the finest cells, m. > 0. Default 0.1.
  double resolution = 0.1;
  /// The sensor origin of every cloud, map frame, m; nullopt: a PCD's
  /// VIEWPOINT, a PLY's (0, 0, 0). Not with `poses`.
  std::optional<Eigen::Vector3d> origin;
  /// One pose T_world_sensor per cloud, in order: the clouds are in the
  /// sensor frame, placed by their pose, whose position is the origin.
  /// Empty: the clouds are in the map frame.
  std::vector<StampedPose3> poses;
  /// Insertion: max_range, mode, arithmetic, threads (skip_invalid_points
  /// is always set: a non-finite point is skipped and counted).
  OctreeInsertOptions insert;
  /// What colours do. Default Mean.
  OctreeColorRule color = OctreeColorRule::Mean;
  /// Called after each cloud with the number inserted so far (may be empty).
  std::function<void(std::size_t done)> on_cloud;
};

/// What the clouds' colours did.
struct OctreeColorSummary {
  std::size_t clouds = 0;       ///< clouds whose colours were used
  std::size_t points = 0;       ///< points whose colour was used
  std::size_t mean_leaves = 0;  ///< leaves coloured by the mean rule
};

/// Something a finished build must tell its user.
struct OctreeBuildIssue {
  std::string code;     ///< "skipped-points" or "empty-map"
  std::string message;  ///< one line for a person, with the counts
};

/// The octree and what went into it.
struct OctreeBuildResult {
  OccupancyOctree tree{0.1};
  std::size_t points = 0;          ///< points given
  std::size_t skipped_points = 0;  ///< not finite or outside the octree
  std::size_t leaves = 0;          ///< leaves of the (pruned) tree
  std::size_t occupied_leaves = 0;
  OctreeColorSummary colors;
  double seconds = 0.0;  ///< wall time of reading and inserting
  std::vector<OctreeBuildIssue> issues;
};

/// Builds an octree from the clouds (.pcd or .ply, by extension). Checks
/// everything before any work: throws IoError for another extension or a
/// file that is not a readable regular file, ParseError (naming `poses_source`)
/// when the poses are not one per cloud, InvalidArgument for bad options
/// (resolution, origin with poses); then what the readers throw, and
/// rove::Interrupted (checked per cloud).
OctreeBuildResult build_octree(const std::vector<std::string>& clouds, const OctreeBuildOptions& options,
                               std::string_view poses_source = "poses");

/// The file format of an octree named `path`: .bt (OctoMap's binary file)
/// or .ot (the full file). Throws IoError for another extension.
OctreeFileFormat octree_output_format(const std::string& path);

/// Writes the built tree to `path` atomically: a .bt holds the maximum
/// likelihood occupancy (pruned), a .ot every log-odds (and the colours).
/// Returns the issues of the writing: "colors-not-written" when coloured
/// clouds went into a .bt. Throws IoError.
std::vector<OctreeBuildIssue> write_built_octree(const std::string& path, const OctreeBuildResult& result);

}  // namespace rove
