#include "rove/io/octree_build.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <utility>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/core/interrupt.h"
#include "rove/core/timer.h"
#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/maps/octree_color_mean.h"

namespace rove {

namespace {

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

// One cloud with its sensor origin, in the map frame.
struct Scan {
  PointCloud cloud;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
};

Scan read_scan(const std::string& path, const OctreeBuildOptions& o, std::size_t i) {
  Scan s;
  if (lower_extension(path) == ".pcd") {
    PcdHeader h;
    s.cloud = read_pcd(path, &h);
    s.origin = Eigen::Vector3d(h.viewpoint[0], h.viewpoint[1], h.viewpoint[2]);
  } else {
    s.cloud = read_ply(path);
  }
  if (o.origin) s.origin = *o.origin;
  if (!o.poses.empty()) {
    // Points in the sensor frame, mapped by the sensor's pose.
    const SE3d& T = o.poses[i].pose;  // T_world_sensor
    for (auto& p : s.cloud.points_mut()) {
      if (p.allFinite()) p = (T * p.cast<double>()).cast<float>();
    }
    s.origin = T.translation();
  }
  return s;
}

// The tree with the Color channel added (every node white: no colour yet),
// for when the first coloured cloud comes after clouds without colours.
OccupancyOctree with_color_channel(const OccupancyOctree& t) {
  std::vector<OctreeNodeRecord> nodes;
  nodes.reserve(t.num_nodes());
  t.for_each_node([&](const OctreeNodeRecord& n) { nodes.push_back(n); });
  OccupancyOctree c(t.resolution(), t.params(), t.channels() | OctreeChannels::Color);
  c.assign_preorder(nodes);
  return c;
}

// Inserts one cloud, with its colours when the rule uses them.
OctreeInsertResult insert_scan(OccupancyOctree& tree, const Scan& s, const OctreeInsertOptions& io,
                               OctreeColorRule color, OctreeColorMean& means, OctreeColorSummary& summary) {
  if (color == OctreeColorRule::None || !s.cloud.has_colors())
    return tree.insert_point_cloud(s.cloud.points(), s.origin, io);
  if (!has_channels(tree.channels(), OctreeChannels::Color)) tree = with_color_channel(tree);
  ++summary.clouds;
  if (color == OctreeColorRule::Mean) {
    summary.points += means.add(s.cloud.points(), s.cloud.colors());
    return tree.insert_point_cloud(s.cloud.points(), s.origin, io);
  }
  const OctreeColorUpdate how = color == OctreeColorRule::Set       ? OctreeColorUpdate::Set
                                : color == OctreeColorRule::Average ? OctreeColorUpdate::Average
                                                                    : OctreeColorUpdate::Integrate;
  const OctreeInsertResult r = tree.insert_point_cloud(s.cloud.points(), s.cloud.colors(), s.origin, io, how);
  summary.points += r.points - r.skipped_points;
  return r;
}

}  // namespace

OctreeColorRule parse_octree_color_rule(std::string_view text) {
  if (text == "mean") return OctreeColorRule::Mean;
  if (text == "average") return OctreeColorRule::Average;
  if (text == "integrate") return OctreeColorRule::Integrate;
  if (text == "set") return OctreeColorRule::Set;
  if (text == "none") return OctreeColorRule::None;
  throw InvalidArgument(
      fmt::format("colour rule '{}': expected mean, average, integrate, set or none", printable(text)));
}

std::string_view to_string(OctreeColorRule rule) {
  switch (rule) {
    case OctreeColorRule::Mean: return "mean";
    case OctreeColorRule::Average: return "average";
    case OctreeColorRule::Integrate: return "integrate";
    case OctreeColorRule::Set: return "set";
    case OctreeColorRule::None: return "none";
  }
  return "?";
}

OctreeUpdateMode parse_octree_update_mode(std::string_view text) {
  if (text == "once") return OctreeUpdateMode::OncePerScan;
  if (text == "discretized") return OctreeUpdateMode::Discretized;
  if (text == "every-ray") return OctreeUpdateMode::EveryRay;
  throw InvalidArgument(
      fmt::format("octree update mode '{}': expected once, discretized or every-ray", printable(text)));
}

OctreeRayArithmetic parse_octree_ray_arithmetic(std::string_view text) {
  if (text == "double") return OctreeRayArithmetic::Double;
  if (text == "octomap") return OctreeRayArithmetic::OctoMap;
  throw InvalidArgument(fmt::format("ray arithmetic '{}': expected double or octomap", printable(text)));
}

OctreeBuildResult build_octree(const std::vector<std::string>& clouds, const OctreeBuildOptions& o,
                               std::string_view poses_source) {
  for (const auto& in : clouds) {
    const std::string e = lower_extension(in);
    if (e != ".pcd" && e != ".ply") throw IoError(printable(in), "unknown point cloud format (expected .pcd or .ply)");
    check_regular_input(in, "point cloud");
  }
  if (o.origin && !o.poses.empty())
    throw InvalidArgument("an origin for every cloud and poses: the poses give the origins, give one or the other");
  if (o.origin && !o.origin->allFinite())
    throw InvalidArgument(fmt::format("origin ({}, {}, {}): not finite", o.origin->x(), o.origin->y(), o.origin->z()));
  if (!o.poses.empty() && o.poses.size() != clouds.size())
    throw ParseError({printable(poses_source), std::nullopt, std::nullopt, "poses"},
                     fmt::format("{} poses for {} clouds: give one pose per cloud, in order", o.poses.size(),
                                 clouds.size()));
  OctreeBuildResult r;
  r.tree = OccupancyOctree(o.resolution);
  OccupancyOctree& tree = r.tree;
  OctreeInsertOptions io = o.insert;
  io.skip_invalid_points = true;
  OctreeColorMean means(o.resolution);
  const Stopwatch clock;
  for (std::size_t i = 0; i < clouds.size(); ++i) {
    throw_if_interrupted();
    const Scan s = read_scan(clouds[i], o, i);
    const OctreeInsertResult ir = insert_scan(tree, s, io, o.color, means, r.colors);
    r.points += ir.points;
    r.skipped_points += ir.skipped_points;
    if (o.on_cloud) o.on_cloud(i + 1);
  }
  if (means.cells() > 0) r.colors.mean_leaves = means.apply(tree);
  r.seconds = clock.elapsed();
  tree.for_each_leaf([&](const OctreeLeaf& l) {
    ++r.leaves;
    r.occupied_leaves += tree.is_occupied(l.log_odds) ? 1 : 0;
  });
  if (r.skipped_points > 0) {
    r.issues.push_back({"skipped-points", fmt::format("{} of {} points were not finite or outside the octree and "
                                                      "were skipped",
                                                      r.skipped_points, r.points)});
  }
  if (tree.empty()) r.issues.push_back({"empty-map", "no point was inserted: the octree is empty"});
  return r;
}

OctreeFileFormat octree_output_format(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".bt") return OctreeFileFormat::Binary;
  if (ext == ".ot") return OctreeFileFormat::Full;
  throw IoError(printable(path), "unknown octree format (expected .bt or .ot)");
}

std::vector<OctreeBuildIssue> write_built_octree(const std::string& path, const OctreeBuildResult& r) {
  const OctreeFileFormat format = octree_output_format(path);
  write_octree(path, r.tree, format, OctreeBinaryContent::MaxLikelihood);
  std::vector<OctreeBuildIssue> issues;
  if (r.colors.clouds > 0 && format == OctreeFileFormat::Binary) {
    issues.push_back({"colors-not-written", fmt::format("{} holds no colours (OctoMap's .bt keeps occupancy only): "
                                                        "write .ot for a ColorOcTree, or leave the colours out "
                                                        "(colour rule none)",
                                                        printable(path))});
  }
  return issues;
}

}  // namespace rove
