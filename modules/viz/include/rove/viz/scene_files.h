#pragma once
/// \file
/// Scenes from the files rove reads and writes, and from the output folders
/// of its commands, each recognized by its name and content:
///  - point clouds: `.pcd`, `.ply`;
///  - occupancy grids: ROS `map.yaml` (+ its image);
///  - octrees: OctoMap `.bt`, `.ot`;
///  - trajectories: TUM (`.tum`, or `.txt` with 8 numbers a line), KITTI
///    poses (`.txt` with 12);
///  - pose graphs: g2o `.g2o`, TORO `.graph` (or `.txt` whose first record
///    is a graph record), plain or gzip;
///  - rawlogs (rove, MRPT, CARMEN; `.rawlog`, `.clf`, `.log`, plain or
///    compressed): the 2D scans placed along the odometry path;
///  - particle files of `rove pf-localization` (`particles_*.txt`) and its
///    `steps.txt` (the estimate's covariance ellipses);
///  - landmark maps of `rove kf-slam` (`landmarks.csv`) and beacon maps of
///    its range-only `rove rbpf-slam` (`beacons.csv`): means, ids and 3-sigma
///    ellipses, or ellipsoids in 3D;
///  - output folders: `rove icp-slam` (keyframes.tum + map.simplemap),
///    `rove lidar-slam` (nodes.tum + graph.g2o), `rove pf-localization`
///    (steps.txt), `rove kf-slam` (landmarks.csv + path.tum), `rove rbpf-slam`
///    (ess.csv + path.tum; map.yaml or beacons.csv), `rove nav run` (driven.tum + planned.tum),
///    `rove rgbd-slam` (trajectory.tum + keyframes.tum; map.ply, map.bt, graph.g2o,
///    loops.csv), shown with −y up (its world is a camera's optical frame)
///    when it is the first input.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "rove/viz/scene.h"
#include "rove/viz/scene_builders.h"

namespace rove {

/// What a path holds.
enum class SceneInputKind : std::uint8_t {
  Pcd, Ply, RosMap, Octree, TumTrajectory, KittiTrajectory, PoseGraph, Rawlog, Particles, PfSteps, Landmarks,
  IcpSlamFolder, LidarSlamFolder, PfLocalizationFolder, KfSlamFolder, RbpfSlamFolder, NavRunFolder,
  RgbdSlamFolder,
};

/// "PCD point cloud", "ROS map", ..., "rove lidar-slam output", for messages.
const char* to_string(SceneInputKind kind) noexcept;

/// The kind of the file or folder at `path`, from its name and first bytes.
/// Throws IoError if it cannot be read, ParseError (naming it) for a file or
/// folder rove does not know.
SceneInputKind detect_scene_input(const std::string& path);

/// Options of the scene loaders.
struct SceneLoadOptions {
  CloudLayerOptions cloud;                 ///< point clouds (decimation, point size)
  std::size_t max_scan_points = 2'000'000; ///< points of a rawlog's scans kept at most
  std::size_t max_ellipses = 400;          ///< covariance ellipses of a run kept at most (evenly)
};

/// What loading found besides layers.
struct SceneLoadReport {
  /// One line per input: "<path>: <kind>, <what was added>".
  std::vector<std::string> loaded;
  /// Inputs left out, with the reason ("<path>: <error>").
  std::vector<std::string> skipped;
  /// Points left out because a coordinate was not finite.
  std::size_t skipped_points = 0;
};

/// Adds what `path` holds to `scene` and a line to `report.loaded`. Throws
/// (IoError, ParseError, InvalidArgument) naming the file when it is
/// unknown, unreadable, corrupt or empty; the scene is left as it was
/// (layers, time origin and up axis).
void add_scene_input(Scene& scene, const std::string& path, const SceneLoadOptions& options,
                     SceneLoadReport& report);

/// Adds every path; a path that fails is skipped and listed in
/// `report.skipped` with its error. The scene's title names the inputs.
SceneLoadReport build_scene(Scene& scene, std::span<const std::string> paths, const SceneLoadOptions& options = {});

}  // namespace rove
