#include "rove/viz/scene_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <map>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/graph/graph_io.h"
#include "rove/io/grid_image.h"
#include "rove/io/octree_files.h"
#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/io/tum_trajectory.h"
#include "scene_inputs.h"

namespace rove {

namespace fs = std::filesystem;

const char* to_string(SceneInputKind kind) noexcept {
  switch (kind) {
    case SceneInputKind::Pcd: return "PCD point cloud";
    case SceneInputKind::Ply: return "PLY point cloud";
    case SceneInputKind::RosMap: return "ROS map";
    case SceneInputKind::Octree: return "OctoMap octree";
    case SceneInputKind::TumTrajectory: return "TUM trajectory";
    case SceneInputKind::KittiTrajectory: return "KITTI trajectory";
    case SceneInputKind::PoseGraph: return "pose graph";
    case SceneInputKind::Rawlog: return "rawlog";
    case SceneInputKind::Particles: return "particle file";
    case SceneInputKind::PfSteps: return "pf-localization steps";
    case SceneInputKind::Landmarks: return "landmark or beacon map";
    case SceneInputKind::IcpSlamFolder: return "rove icp-slam output";
    case SceneInputKind::LidarSlamFolder: return "rove lidar-slam output";
    case SceneInputKind::PfLocalizationFolder: return "rove pf-localization output";
    case SceneInputKind::KfSlamFolder: return "rove kf-slam output";
    case SceneInputKind::RbpfSlamFolder: return "rove rbpf-slam output";
    case SceneInputKind::NavRunFolder: return "rove nav run output";
    case SceneInputKind::RgbdSlamFolder: return "rove rgbd-slam output";
  }
  return "unknown";
}

namespace detail {

bool ends_with_ci(std::string_view s, std::string_view suffix) {
  if (s.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) !=
        std::tolower(static_cast<unsigned char>(suffix[i]))) {
      return false;
    }
  }
  return true;
}

std::string display_name(const std::string& path) {
  const fs::path p(path);
  const std::string name = p.filename().string();
  return printable(name.empty() ? p.parent_path().filename().string() : name);
}

}  // namespace detail

namespace {

using detail::ends_with_ci;

// The first kilobytes of a file, for telling text formats apart.
std::string head_of(const std::string& path) {
  check_regular_input(path);
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

bool all_numbers(const std::vector<std::string>& fields) {
  for (const auto& f : fields) {
    double v = 0.0;
    const auto r = std::from_chars(f.data(), f.data() + f.size(), v);
    if (r.ec != std::errc() || r.ptr != f.data() + f.size()) return false;
  }
  return !fields.empty();
}

SceneInputKind detect_folder(const std::string& path) {
  const fs::path d(path);
  const auto has = [&](const char* name) {
    std::error_code ec;
    return fs::is_regular_file(d / name, ec);
  };
  if (has("trajectory.tum") && has("keyframes.tum")) return SceneInputKind::RgbdSlamFolder;
  if (has("nodes.tum") && has("graph.g2o")) return SceneInputKind::LidarSlamFolder;
  if (has("keyframes.tum") && has("path.tum")) return SceneInputKind::IcpSlamFolder;
  if (has("landmarks.csv") && has("path.tum")) return SceneInputKind::KfSlamFolder;
  if (has("ess.csv") && has("path.tum")) return SceneInputKind::RbpfSlamFolder;
  if (has("steps.txt") && has("path.tum")) return SceneInputKind::PfLocalizationFolder;
  if (has("driven.tum") && has("planned.tum")) return SceneInputKind::NavRunFolder;
  throw ParseError({printable(path), std::nullopt, std::nullopt, "folder"},
                   "not an output folder of rove icp-slam (keyframes.tum, path.tum), lidar-slam (nodes.tum, "
                   "graph.g2o), pf-localization (steps.txt, path.tum), kf-slam (landmarks.csv, path.tum), "
                   "rbpf-slam (ess.csv, path.tum), rgbd-slam (trajectory.tum, keyframes.tum) or nav run (driven.tum, "
                   "planned.tum)");
}

SceneInputKind detect_text(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  if (name.rfind("particles_", 0) == 0) return SceneInputKind::Particles;
  const std::string head = head_of(path);
  if (head.rfind("# step time x y phi", 0) == 0) return SceneInputKind::PfSteps;
  // Cut at the last full line so that a long first line is not misread.
  const std::size_t last = head.rfind('\n');
  const std::vector<std::string> fields =
      first_row_fields(std::string_view(head).substr(0, last == std::string::npos ? head.size() : last));
  if (fields.size() == 8 && all_numbers(fields)) return SceneInputKind::TumTrajectory;
  if (fields.size() == 12 && all_numbers(fields)) return SceneInputKind::KittiTrajectory;
  if (!fields.empty() && !all_numbers(fields)) {
    std::string tag = fields.front();
    for (char& c : tag) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (tag.rfind("VERTEX", 0) == 0 || tag.rfind("EDGE", 0) == 0) return SceneInputKind::PoseGraph;
  }
  throw ParseError({printable(path), 1, std::nullopt, "format"},
                   fmt::format("a text file rove cannot show: its first row has {} fields (a TUM trajectory has 8, "
                               "KITTI poses 12, a pose graph starts with VERTEX or EDGE)",
                               fields.size()));
}

}  // namespace

SceneInputKind detect_scene_input(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return detect_folder(path);
  if (!fs::exists(path, ec)) throw IoError(printable(path), "no such file or folder");
  const std::string p = path;
  if (ends_with_ci(p, ".pcd")) return SceneInputKind::Pcd;
  if (ends_with_ci(p, ".ply")) return SceneInputKind::Ply;
  if (ends_with_ci(p, ".yaml") || ends_with_ci(p, ".yml")) return SceneInputKind::RosMap;
  if (ends_with_ci(p, ".bt") || ends_with_ci(p, ".ot")) return SceneInputKind::Octree;
  if (ends_with_ci(p, ".tum")) return SceneInputKind::TumTrajectory;
  for (const char* ext : {".g2o", ".g2o.gz", ".graph", ".graph.gz"}) {
    if (ends_with_ci(p, ext)) return SceneInputKind::PoseGraph;
  }
  for (const char* ext : {".rawlog", ".rawlog.gz", ".rawlog.bz2", ".clf", ".clf.gz", ".clf.bz2", ".log", ".log.gz",
                          ".log.bz2"}) {
    if (ends_with_ci(p, ext)) return SceneInputKind::Rawlog;
  }
  if (ends_with_ci(p, ".txt")) return detect_text(path);
  if (ends_with_ci(p, ".csv")) return SceneInputKind::Landmarks;
  throw ParseError({printable(path), std::nullopt, std::nullopt, "format"},
                   "a file rove cannot show (known: .pcd .ply map .yaml .bt .ot .tum .txt trajectories, .g2o "
                   ".graph, rawlogs, kf-slam landmarks .csv, and the output folders of rove's commands)");
}

namespace detail {

std::string add_cloud_file(Scene& scene, const std::string& path, bool pcd, const SceneLoadOptions& o,
                           SceneLoadReport& report) {
  const PointCloud cloud = pcd ? read_pcd(path) : read_ply(path);
  if (cloud.empty()) throw ParseError({printable(path), std::nullopt, std::nullopt, "points"}, "the cloud has no point");
  CloudLayerReport r;
  try {
    r = add_point_cloud(scene, cloud, display_name(path), o.cloud);
  } catch (const InvalidArgument&) {
    throw ParseError({printable(path), std::nullopt, std::nullopt, "points"},
                     fmt::format("none of its {} points is finite", cloud.size()));
  }
  report.skipped_points += r.skipped;
  std::string s = fmt::format("{} points", r.finite);
  if (r.kept < r.finite) s += fmt::format(" ({} shown, an even sample)", r.kept);
  if (r.skipped > 0) s += fmt::format(", {} not finite left out", r.skipped);
  return s;
}

std::string add_map_file(Scene& scene, const std::string& path) {
  const RosMap map = load_ros_map(path);
  add_occupancy_grid(scene, map.grid, display_name(path));
  return fmt::format("{} x {} cells of {} m", map.grid.size_x(), map.grid.size_y(), map.grid.resolution());
}

std::string add_octree_file(Scene& scene, const std::string& path) {
  const OccupancyOctree tree = read_octree(path);
  try {
    add_octree(scene, tree, display_name(path));
  } catch (const InvalidArgument&) {
    throw ParseError({printable(path), std::nullopt, std::nullopt, "nodes"}, "the octree has no occupied cell");
  }
  return fmt::format("{} leaves, resolution {} m", tree.num_leaves(), tree.resolution());
}

std::string add_trajectory_file(Scene& scene, const std::string& path, bool kitti, const TrajectoryLayerOptions& o) {
  const std::vector<StampedPose3> poses = kitti ? read_kitti_trajectory(path) : read_tum_trajectory(path);
  if (poses.empty()) throw ParseError({printable(path), std::nullopt, std::nullopt, "poses"}, "no pose");
  add_trajectory(scene, poses, display_name(path), o);
  return fmt::format("{} poses", poses.size());
}

std::string add_graph_file(Scene& scene, const std::string& path) {
  const std::string name = display_name(path);
  // "(N loop closures)": the pairs of vertices joined by a loop-closure
  // edge, with the edges' count when some pair has several (measured both
  // ways, repeated, or merged by EQUIV).
  const auto summary = [&](std::size_t first, const auto& graph) {
    std::size_t pairs = 0, edges = 0;
    for (std::size_t i = first; i < scene.layers.size(); ++i) {
      if (scene.layers[i].kind == LayerKind::LoopEdges) pairs = scene.layers[i].positions.size() / 2;
    }
    for (const auto& e : graph.edges()) edges += (e.to != e.from + 1 && e.from != e.to + 1) ? 1 : 0;
    return fmt::format("{} vertices, {} edges ({} loop closures{})", graph.num_vertices(), graph.num_edges(), pairs,
                       edges != pairs ? fmt::format(" by {} edges", edges) : std::string());
  };
  const std::size_t first = scene.layers.size();
  if (detect_graph_dimension(path) == GraphDimension::ThreeD) {
    const PoseGraph3D g = read_graph_3d(path);
    add_pose_graph(scene, g, name);
    return "3D, " + summary(first, g);
  }
  const PoseGraph2D g = read_graph_2d(path);
  if (g.num_vertices() == 0) throw ParseError({printable(path), std::nullopt, std::nullopt, "vertices"}, "no vertex");
  add_pose_graph(scene, g, name);
  return "2D, " + summary(first, g);
}

}  // namespace detail

namespace {

std::string add_input_of_kind(Scene& scene, const std::string& path, SceneInputKind kind,
                              const SceneLoadOptions& options, SceneLoadReport& report) {
  switch (kind) {
    case SceneInputKind::Pcd: return detail::add_cloud_file(scene, path, true, options, report);
    case SceneInputKind::Ply: return detail::add_cloud_file(scene, path, false, options, report);
    case SceneInputKind::RosMap: return detail::add_map_file(scene, path);
    case SceneInputKind::Octree: return detail::add_octree_file(scene, path);
    case SceneInputKind::TumTrajectory: return detail::add_trajectory_file(scene, path, false, {});
    case SceneInputKind::KittiTrajectory: return detail::add_trajectory_file(scene, path, true, {});
    case SceneInputKind::PoseGraph: return detail::add_graph_file(scene, path);
    case SceneInputKind::Rawlog: return detail::add_rawlog_file(scene, path, options);
    case SceneInputKind::Particles: return detail::add_particle_files(scene, {path}, {});
    case SceneInputKind::PfSteps: return detail::add_steps_file(scene, path, options);
    case SceneInputKind::Landmarks:
      return detail::add_landmarks_file(scene, path,
                                        detail::ends_with_ci(path, "beacons.csv") ? "beacons" : "landmarks");
    default: return detail::add_output_folder(scene, path, kind, options, report);
  }
}

}  // namespace

void add_scene_input(Scene& scene, const std::string& path, const SceneLoadOptions& options, SceneLoadReport& report) {
  const SceneInputKind kind = detect_scene_input(path);
  // On failure the scene is put back as it was: the layers added so far
  // dropped, the time origin restored.
  const std::size_t layers_before = scene.layers.size();
  const double origin_before = scene.time_origin;
  const SceneUp up_before = scene.up;
  const std::size_t skipped_before = report.skipped_points;
  std::string what;
  try {
    what = add_input_of_kind(scene, path, kind, options, report);
  } catch (...) {
    scene.layers.resize(layers_before);
    scene.time_origin = origin_before;
    scene.up = up_before;
    report.skipped_points = skipped_before;
    throw;
  }
  scene.sources.push_back(path);
  report.loaded.push_back(fmt::format("{}: {}, {}", printable(path), to_string(kind), what));
}

SceneLoadReport build_scene(Scene& scene, std::span<const std::string> paths, const SceneLoadOptions& options) {
  SceneLoadReport report;
  std::vector<std::string> names;
  for (const auto& p : paths) {
    try {
      add_scene_input(scene, p, options, report);
      names.push_back(detail::display_name(p));
    } catch (const Interrupted&) {
      throw;
    } catch (const Error& e) {
      const std::string name = printable(p);
      report.skipped.push_back(e.message().find(name) == std::string::npos ? name + ": " + e.message() : e.message());
    } catch (const std::exception& e) {
      report.skipped.push_back(fmt::format("{}: {}", printable(p), e.what()));
    }
  }
  if (!names.empty()) {
    std::string title = names.front();
    for (std::size_t i = 1; i < names.size() && i < 4; ++i) title += ", " + names[i];
    if (names.size() > 4) title += fmt::format(" and {} more", names.size() - 4);
    scene.title = title;
  }
  return report;
}

}  // namespace rove
