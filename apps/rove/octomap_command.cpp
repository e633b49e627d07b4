// `rove octomap build INPUT... -o MAP.bt`: a 3D occupancy octree (OctoMap's
// .bt or .ot) from point clouds and their sensor origins, built by
// rove/io/octree_build.h; this file reads the command line and writes the
// outputs.

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "report.h"
#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/core/json.h"
#include "rove/core/parallel.h"
#include "rove/core/timer.h"
#include "rove/io/grid_image.h"
#include "rove/io/octree_build.h"
#include "rove/io/octree_files.h"
#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/io/tum_trajectory.h"
#include "rove/maps/octree_color_mean.h"
#include "rove/maps/octree_export.h"

namespace rove::cli {

namespace {

struct OctomapBuildOptions {
  std::vector<std::string> inputs;
  std::string output;
  double resolution = 0.1;
  std::string origin;
  std::string poses;
  double max_range = -1.0;
  std::string mode = "once";
  std::string arithmetic = "double";
  int threads = 1;
  std::string color = "mean";
  std::string ply, pcd, slice;
  double slice_z = 0.0;
  bool json = false;
};

Eigen::Vector3d parse_origin(const std::string& text) {
  Eigen::Vector3d v;
  std::size_t pos = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t end = i < 2 ? text.find(',', pos) : text.size();
    if (end == std::string::npos) break;
    const std::string tok = text.substr(pos, end - pos);
    char* stop = nullptr;
    v[i] = std::strtod(tok.c_str(), &stop);
    if (tok.empty() || *stop != '\0' || !std::isfinite(v[i])) break;
    if (i == 2) return v;
    pos = end + 1;
  }
  throw ParseError({"--origin", std::nullopt, std::nullopt, "origin"},
                   fmt::format("'{}' is not X,Y,Z (three finite numbers, meters)", printable(text)));
}

// A CLI11 check that a number is finite (CLI::Range lets NaN through).
const CLI::Validator kFinite(
    [](std::string& text) -> std::string {
      char* stop = nullptr;
      const double v = std::strtod(text.c_str(), &stop);
      if (text.empty() || *stop != '\0' || !std::isfinite(v)) return fmt::format("'{}' is not a finite number", text);
      return {};
    },
    "FINITE");

void write_summary_json(const OctomapBuildOptions& o, const OctreeBuildResult& r,
                        const std::vector<std::string>& outputs, const std::vector<Issue>& issues) {
  const OccupancyOctree& t = r.tree;
  const OctreeColorSummary& colors = r.colors;
  JsonWriter j;
  j.begin_object();
  j.key("command").value("octomap build");
  j.key("inputs").begin_array();
  for (const auto& in : o.inputs) j.value(in);
  j.end_array();
  j.key("poses");
  if (o.poses.empty()) {
    j.null();
  } else {
    j.value(o.poses);
  }
  j.key("resolution").value(t.resolution());
  j.key("mode").value(o.mode).key("arithmetic").value(o.arithmetic);
  j.key("max_range").value(o.max_range).key("threads").value(o.threads);
  j.key("points").value(static_cast<std::uint64_t>(r.points));
  j.key("skipped_points").value(static_cast<std::uint64_t>(r.skipped_points));
  j.key("nodes").value(static_cast<std::uint64_t>(t.num_nodes()));
  j.key("leaves").value(static_cast<std::uint64_t>(r.leaves));
  j.key("occupied_leaves").value(static_cast<std::uint64_t>(r.occupied_leaves));
  j.key("memory_bytes").value(static_cast<std::uint64_t>(t.memory_usage()));
  j.key("colors");
  if (colors.clouds == 0) {
    j.null();
  } else {
    j.begin_object().key("rule").value(o.color).key("clouds").value(static_cast<std::uint64_t>(colors.clouds));
    j.key("points").value(static_cast<std::uint64_t>(colors.points));
    j.key("mean_leaves").value(static_cast<std::uint64_t>(colors.mean_leaves)).end_object();
  }
  Eigen::Vector3d lo, hi;
  t.metric_bounds(lo, hi);
  j.key("bounds");
  if (t.empty()) {
    j.null();
  } else {
    j.begin_object().key("min").begin_array().value(lo.x()).value(lo.y()).value(lo.z()).end_array();
    j.key("max").begin_array().value(hi.x()).value(hi.y()).value(hi.z()).end_array().end_object();
  }
  j.key("seconds").value(r.seconds);
  j.key("outputs").begin_array();
  for (const auto& out : outputs) j.value(out);
  j.end_array();
  write_issues(j, issues);
  j.end_object();
  fmt::print("{}\n", j.str());
}

void run_build(const OctomapBuildOptions& o) {
  // Everything the command line names is checked before any work.
  const int threads = resolve_thread_count(o.threads, "--threads");
  (void)octree_output_format(o.output);
  std::vector<std::filesystem::path> inputs;
  for (const auto& in : o.inputs) inputs.emplace_back(in);
  if (!o.poses.empty()) inputs.emplace_back(o.poses);
  if (!o.origin.empty()) (void)parse_origin(o.origin);
  std::vector<std::filesystem::path> outputs{o.output};
  if (!o.ply.empty()) outputs.emplace_back(o.ply);
  if (!o.pcd.empty()) outputs.emplace_back(o.pcd);
  if (!o.slice.empty()) {
    outputs.emplace_back(o.slice + ".png");
    outputs.emplace_back(o.slice + ".yaml");
  }
  check_outputs_distinct(inputs, outputs);
  OctreeBuildOptions bo;
  bo.resolution = o.resolution;
  if (!o.origin.empty()) bo.origin = parse_origin(o.origin);
  if (!o.poses.empty()) bo.poses = read_tum_trajectory(o.poses);
  bo.insert.max_range = o.max_range;
  bo.insert.mode = parse_octree_update_mode(o.mode);
  bo.insert.arithmetic = parse_octree_ray_arithmetic(o.arithmetic);
  bo.insert.num_threads = threads;
  bo.color = parse_octree_color_rule(o.color);
  {
    const OccupancyOctree probe(o.resolution);
    if (!o.slice.empty() && !probe.key_of(Eigen::Vector3d(0.0, 0.0, o.slice_z))) {
      throw InvalidArgument(fmt::format("--slice-z = {}: outside the octree, which spans ±{} m at resolution {} m",
                                        o.slice_z, probe.node_size(0) / 2, o.resolution));
    }
  }
  const OctreeBuildResult r = build_octree(o.inputs, bo, o.poses);
  const OccupancyOctree& tree = r.tree;

  std::vector<std::string> written{o.output};
  std::vector<Issue> issues;
  for (const auto& i : r.issues) issues.push_back({i.code, i.message});
  for (const auto& i : write_built_octree(o.output, r)) issues.push_back({i.code, i.message});
  if (!o.ply.empty() || !o.pcd.empty()) {
    const PointCloud occupied = octree_occupied_cloud(tree);
    if (!o.ply.empty()) {
      write_ply(o.ply, occupied);
      written.push_back(o.ply);
    }
    if (!o.pcd.empty()) {
      write_pcd(o.pcd, occupied);
      written.push_back(o.pcd);
    }
  }
  if (!o.slice.empty()) {
    const RosMapFiles f = save_ros_map(o.slice, octree_slice(tree, o.slice_z));
    written.push_back(f.image);
    written.push_back(f.yaml);
  }

  if (o.json) {
    write_summary_json(o, r, written, issues);
  } else {
    fmt::print("octree: {} clouds, {} points ({} skipped), resolution {} m, mode {}\n", o.inputs.size(), r.points,
               r.skipped_points, o.resolution, o.mode);
    fmt::print("nodes: {} ({} leaves, {} occupied), {:.1f} MB\n", tree.num_nodes(), r.leaves, r.occupied_leaves,
               static_cast<double>(tree.memory_usage()) / 1048576.0);
    if (r.colors.clouds > 0) {
      fmt::print("colours: {} ({} clouds, {} points{})\n", o.color, r.colors.clouds, r.colors.points,
                 o.color == "mean" ? fmt::format(", {} leaves", r.colors.mean_leaves) : "");
    }
    fmt::print("time: {:.3f} s\n", r.seconds);
    for (const auto& w : written) fmt::print("wrote {}\n", printable(w));
    fmt::print("issues: {}\n", issues.empty() ? "none" : std::to_string(issues.size()));
  }
  finish(issues);
}

}  // namespace

void add_octomap_command(CLI::App& app) {
  auto* octomap = app.add_subcommand("octomap", "3D occupancy octrees (OctoMap's .bt and .ot files)");
  octomap->require_subcommand(1);
  auto o = std::make_shared<OctomapBuildOptions>();
  auto* cmd = octomap->add_subcommand(
      "build",
      "Build an octree from point clouds (PCD or PLY) and their sensor origins; exit status 3 when points were "
      "skipped or nothing was inserted (the issue is listed)");
  cmd->add_option("inputs", o->inputs,
                  "Clouds (.pcd or .ply), in the map frame (or the sensor frame with --poses); a PCD's VIEWPOINT "
                  "is its sensor origin")
      ->required();
  cmd->add_option("-o,--output", o->output,
                  "The octree: .bt (OctoMap's binary file, maximum likelihood, pruned) or .ot (full: every "
                  "log-odds); written atomically, never over an input")
      ->required();
  cmd->add_option("--res", o->resolution, "Edge of the finest cells, m")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  auto* origin = cmd->add_option("--origin", o->origin,
                                 "Sensor origin X,Y,Z (m) of every cloud; default: a PCD's VIEWPOINT, a PLY's 0,0,0");
  cmd->add_option("--poses", o->poses,
                  "TUM trajectory (t x y z qx qy qz qw), one pose per cloud in order: the clouds are in the "
                  "sensor frame and the poses place them (the origin is the pose's position); default none")
      ->excludes(origin);
  cmd->add_option("--max-range", o->max_range, "Cut rays longer than this (m) and mark no obstacle; < 0: no limit")
      ->check(kFinite)
      ->capture_default_str();
  cmd->add_option("--mode", o->mode,
                  "once: each cell once per cloud (OctoMap's insertPointCloud); discretized: rays to cell centres; "
                  "every-ray: every ray updates its cells")
      ->check(CLI::IsMember({"once", "discretized", "every-ray"}))
      ->capture_default_str();
  cmd->add_option("--arithmetic", o->arithmetic,
                  "Ray traversal: double, or octomap (OctoMap 1.9's float arithmetic, its cells exactly)")
      ->check(CLI::IsMember({"double", "octomap"}))
      ->capture_default_str();
  cmd->add_option("--threads", o->threads,
                  fmt::format("Threads, 1 to {}, 0 for all hardware threads (the octree does not depend on it)",
                              kMaxThreads))
      ->capture_default_str();
  cmd->add_option("--color", o->color,
                  "Colours of the clouds that have them (PLY red green blue, PCD rgb): mean (each leaf the mean "
                  "colour of the points in it), average, integrate or set (OctoMap's ColorOcTree rules, point after "
                  "point), none (ignored). With colours the octree is OctoMap's ColorOcTree: write .ot (a .bt keeps "
                  "no colours)")
      ->check(CLI::IsMember({"mean", "average", "integrate", "set", "none"}))
      ->capture_default_str();
  cmd->add_option("--ply", o->ply, "Also write the occupied cells' centres (with their colours) as a PLY cloud; default none");
  cmd->add_option("--pcd", o->pcd, "Also write the occupied cells' centres (with their colours) as a PCD cloud; default none");
  cmd->add_option("--slice", o->slice,
                  "Also write the cells at height --slice-z as a ROS map (PREFIX.png, PREFIX.yaml); default none");
  cmd->add_option("--slice-z", o->slice_z, "Height of --slice, m")->check(kFinite)->capture_default_str();
  cmd->add_flag("--json", o->json, "Print the summary as one JSON object (with an issues array)");
  cmd->callback([o] { run_build(*o); });
}

}  // namespace rove::cli
