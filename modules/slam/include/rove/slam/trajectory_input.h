#pragma once
/// \file
/// Trajectories read for evaluation (`rove eval`, rove.eval_*): a TUM
/// trajectory, KITTI poses or the vertices of a g2o/TORO pose graph, told
/// apart by the file's name and first row; and the two clocks of a CARMEN
/// log, which relate Freiburg's relation times to rove's trajectories.

#include <string>
#include <string_view>
#include <vector>

#include "rove/graph/pose_graph.h"
#include "rove/io/trajectory_files.h"
#include "rove/slam/trajectory_eval.h"

namespace rove {

/// A trajectory read from a file, with what it was read as.
struct LoadedTrajectory {
  std::vector<StampedPose3> poses;  ///< in the file's order
  /// "tum", "kitti", "graph (2D vertices, id as time)" or
  /// "graph (3D vertices, id as time)".
  std::string format;
};

/// Throws InvalidArgument unless `format` is "auto", "tum", "kitti" or
/// "graph" (load_trajectory's formats).
void check_trajectory_format(std::string_view format);

/// Reads a trajectory. `format` is "auto" (the default), "tum" (8 fields a
/// row: t x y z qx qy qz qw), "kitti" (12: the 3×4 [R | t], the row index
/// as time) or "graph" (the vertices of a g2o/TORO graph, the vertex id as
/// time). "auto" takes .g2o, .graph and .gz files and files whose first row
/// starts with a name as graphs, otherwise TUM or KITTI by the first row's
/// field count. Throws InvalidArgument for another `format`, IoError when
/// the file cannot be read, ParseError naming the file (and line and
/// field) for a row that fits no format or a malformed one.
LoadedTrajectory load_trajectory(const std::string& path, std::string_view format = "auto");

/// The vertices of a 2D pose graph as stamped 3D poses (z = 0, rotation
/// about z), the vertex id as time, in id order.
std::vector<StampedPose3> graph_vertices(const PoseGraph2D& graph);
/// The vertices of a 3D pose graph, the vertex id as time, in id order.
std::vector<StampedPose3> graph_vertices(const PoseGraph3D& graph);

/// The ipc and logger timestamps of a CARMEN log's front-laser lines
/// (FLASER, ROBOTLASER1), in the log's order: the clock map_relation_times
/// takes Freiburg's relation times (ipc) to rove's trajectories of the log
/// (logger) with. Throws IoError when the log cannot be read, ParseError
/// for a malformed log or one without a front-laser line.
std::vector<ClockPair> carmen_log_clock(const std::string& path);

}  // namespace rove
