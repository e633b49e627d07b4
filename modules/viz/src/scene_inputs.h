#pragma once
// The loaders behind add_scene_input, one per kind of input (internal).

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "rove/viz/scene_files.h"

namespace rove::detail {

/// Whether `s` ends with `suffix`, ignoring ASCII case.
bool ends_with_ci(std::string_view s, std::string_view suffix);
/// The file (or folder) name of a path, printable, for layer names.
std::string display_name(const std::string& path);

/// Each adds its input to the scene and returns what it added, for the report.
std::string add_cloud_file(Scene& scene, const std::string& path, bool pcd, const SceneLoadOptions& o,
                           SceneLoadReport& report);
std::string add_map_file(Scene& scene, const std::string& path);
std::string add_octree_file(Scene& scene, const std::string& path);
std::string add_trajectory_file(Scene& scene, const std::string& path, bool kitti, const TrajectoryLayerOptions& o);
std::string add_graph_file(Scene& scene, const std::string& path);
std::string add_rawlog_file(Scene& scene, const std::string& path, const SceneLoadOptions& o);
/// Particle files of rove pf-localization, times from `step_times` (step
/// index → seconds; the step index itself when absent).
std::string add_particle_files(Scene& scene, const std::vector<std::string>& paths,
                               const std::vector<double>& step_times);
std::string add_steps_file(Scene& scene, const std::string& path, const SceneLoadOptions& o);
/// The landmark map of rove kf-slam (landmarks.csv) or the beacon map of its
/// range-only rbpf-slam (beacons.csv): means, ids and 3-sigma ellipses (or
/// ellipsoids in 3D); `noun` names them in the report.
std::string add_landmarks_file(Scene& scene, const std::string& path, std::string_view noun = "landmarks");
/// `main` (a TUM file in `dir`) as the trajectory, `secondary` (if present) as a path beside it.
std::string add_paths(Scene& scene, const std::filesystem::path& dir, const std::string& main, const char* secondary,
                      Rgba8 secondary_color);
/// The output folders of rove kf-slam and rove rbpf-slam.
std::string add_filter_slam_folder(Scene& scene, const std::string& path, SceneInputKind kind);
/// The output folder of rove rgbd-slam (sets the scene's up to −y when it
/// has no layer yet).
std::string add_rgbd_slam_folder(Scene& scene, const std::string& path, const SceneLoadOptions& o,
                                 SceneLoadReport& report);
std::string add_output_folder(Scene& scene, const std::string& path, SceneInputKind kind, const SceneLoadOptions& o,
                              SceneLoadReport& report);

}  // namespace rove::detail
