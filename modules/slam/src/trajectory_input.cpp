#include "rove/slam/trajectory_input.h"

#include <fmt/format.h>

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <optional>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/graph/graph_io.h"
#include "rove/io/carmen_log.h"
#include "rove/io/tum_trajectory.h"

namespace rove {

namespace {

std::string lower_extension(const std::string& path) {
  std::string lower;
  for (const char c : std::filesystem::path(path).extension().string())
    lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

// The format "auto" stands for, from the name and the first row.
std::string detect_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".g2o" || ext == ".graph" || ext == ".gz") return "graph";
  const std::vector<std::string> first =
      first_row_fields(read_input_file(path, std::uint64_t{1} << 32, "trajectory"));
  const std::size_t n = first.size();
  if (n > 0 && std::isalpha(static_cast<unsigned char>(first[0][0]))) return "graph";
  if (n == 8) return "tum";
  if (n == 12) return "kitti";
  throw ParseError({printable(path), std::nullopt, std::nullopt, "format"},
                   fmt::format("the first row has {} fields: not a TUM trajectory (8: t x y z "
                               "qx qy qz qw) nor KITTI poses (12); name the format (tum, kitti or graph)",
                               n));
}

}  // namespace

std::vector<StampedPose3> graph_vertices(const PoseGraph2D& graph) {
  std::vector<StampedPose3> out;
  out.reserve(graph.num_vertices());
  for (const auto& [id, v] : graph.vertices()) {
    const Eigen::Matrix3d R(Eigen::AngleAxisd(v.pose.angle(), Eigen::Vector3d::UnitZ()));
    const Eigen::Vector3d t(v.pose.translation().x(), v.pose.translation().y(), 0.0);
    out.push_back({static_cast<double>(id), SE3d(R, t)});
  }
  return out;
}

std::vector<StampedPose3> graph_vertices(const PoseGraph3D& graph) {
  std::vector<StampedPose3> out;
  out.reserve(graph.num_vertices());
  for (const auto& [id, v] : graph.vertices()) out.push_back({static_cast<double>(id), v.pose});
  return out;
}

void check_trajectory_format(std::string_view format) {
  if (format != "auto" && format != "tum" && format != "kitti" && format != "graph")
    throw InvalidArgument(fmt::format("trajectory format '{}': expected auto, tum, kitti or graph",
                                      printable(format)));
}

LoadedTrajectory load_trajectory(const std::string& path, std::string_view format) {
  check_trajectory_format(format);
  check_regular_input(path, "trajectory");
  const std::string f = format == "auto" ? detect_format(path) : std::string(format);
  if (f == "tum") return {read_tum_trajectory(path), "tum"};
  if (f == "kitti") return {read_kitti_trajectory(path), "kitti"};
  if (detect_graph_dimension(path) == GraphDimension::ThreeD)
    return {graph_vertices(read_graph_3d(path)), "graph (3D vertices, id as time)"};
  return {graph_vertices(read_graph_2d(path)), "graph (2D vertices, id as time)"};
}

std::vector<ClockPair> carmen_log_clock(const std::string& path) {
  check_regular_input(path, "CARMEN log");
  CarmenLogReader reader = CarmenLogReader::open(path);
  std::vector<ClockPair> clock;
  CarmenRecord record;
  while (reader.next(record))
    if (record.type == CarmenMessage::Flaser || record.type == CarmenMessage::RobotLaser1)
      clock.push_back({record.ipc_timestamp, record.logger_timestamp});
  if (clock.empty())
    throw ParseError({printable(path), std::nullopt, std::nullopt, "FLASER"},
                     "the log has no front-laser line (FLASER or ROBOTLASER1) to take times from");
  return clock;
}

}  // namespace rove
