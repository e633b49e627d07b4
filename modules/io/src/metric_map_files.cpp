#include "rove/io/metric_map_files.h"

#include <fmt/format.h>

#include "rove/core/error.h"
#include "rove/core/files.h"
#include "rove/io/grid_image.h"
#include "rove/io/octree_files.h"
#include "rove/io/pcd.h"
#include "rove/io/ply.h"
#include "rove/maps/beacon_map.h"
#include "rove/maps/height_map.h"
#include "rove/maps/landmark_map.h"
#include "rove/maps/metric_map_occupancy_grid.h"
#include "rove/maps/metric_map_octree.h"
#include "rove/maps/metric_map_points.h"
#include "rove/maps/multi_metric_map.h"
#include "rove/maps/octree_export.h"

namespace rove {
namespace {

std::vector<std::string> save_grid_map(const std::string& prefix, const OccupancyGrid& grid) {
  const std::string img = prefix + ".pgm";
  GridImageOptions scale;
  scale.mode = RosMapMode::Scale;
  write_gray_image(img, grid_to_image(grid, scale), ImageFormat::Pgm);
  const std::string lim = prefix + "_limits.txt";
  write_text_file_atomically(
      lim, "% Grid limits: [x_min x_max y_min y_max]\n" +
               fmt::format("{:.6f} {:.6f} {:.6f} {:.6f}\n", grid.x_min(), grid.x_max(),
                           grid.y_min(), grid.y_max()));
  return {img, lim};
}

std::vector<std::string> save_points_map(const std::string& prefix, const PointCloud& cloud) {
  write_ply(prefix + ".ply", cloud);
  write_pcd(prefix + ".pcd", cloud);
  return {prefix + ".ply", prefix + ".pcd"};
}

std::vector<std::string> save_beacon_map(const std::string& prefix, const BeaconMap& map) {
  const std::string path = prefix + "_beacons.txt";
  std::string f = "% id x y z var_x var_y var_z det2d det3d c_xy c_xz c_yz kind\n";
  for (const auto& b : map.beacons()) {
    const PointGaussian3 g = b.moments();
    const auto& C = g.covariance;
    f += fmt::format("{} {:.6f} {:.6f} {:.6f} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e} "
                     "{:.6e} {}\n",
                     b.id, g.mean.x(), g.mean.y(), g.mean.z(), C(0, 0), C(1, 1), C(2, 2),
                     C.topLeftCorner<2, 2>().determinant(), C.determinant(), C(0, 1), C(0, 2),
                     C(1, 2), to_string(b.kind));
  }
  write_text_file_atomically(path, f);
  return {path};
}

std::vector<std::string> save_landmark_map(const std::string& prefix, const LandmarkMap& map) {
  const std::string path = prefix + "_landmarks.txt";
  std::string f = "% id x y z c_xx c_yy c_zz c_xy c_xz c_yz times_seen\n";
  for (const auto& l : map.landmarks()) {
    const auto& C = l.position.covariance;
    f += fmt::format("{} {:.6f} {:.6f} {:.6f} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e} {:.6e} {}\n",
                     l.id, l.position.mean.x(), l.position.mean.y(), l.position.mean.z(), C(0, 0),
                     C(1, 1), C(2, 2), C(0, 1), C(0, 2), C(1, 2), l.times_seen);
  }
  write_text_file_atomically(path, f);
  return {path};
}

std::vector<std::string> save_height_map(const std::string& prefix, const HeightMap& map) {
  std::vector<std::string> out;
  for (const bool means : {true, false}) {
    const std::string path = prefix + (means ? "_mean.txt" : "_count.txt");
    std::string f;
    for (std::uint32_t cy = 0; cy < map.size_y(); ++cy) {
      std::string line;
      for (std::uint32_t cx = 0; cx < map.size_x(); ++cx) {
        const HeightCell& c = map.cell(cx, cy);
        if (cx > 0) line += ' ';
        line += means ? fmt::format("{:.6g}", c.mean_z) : fmt::format("{}", c.count);
      }
      f += line;
      f += '\n';
    }
    write_text_file_atomically(path, f);
    out.push_back(path);
  }
  return out;
}

std::vector<std::string> save_octree_map(const std::string& prefix, const OccupancyOctree& tree) {
  // The .bt as MRPT writes it (OctoMap's writeBinaryConst), the full .ot of
  // a coloured tree (the colours), and the occupied cells as a point cloud.
  std::vector<std::string> out{prefix + ".bt"};
  write_octree(out.back(), tree, OctreeFileFormat::Binary, OctreeBinaryContent::AsIs);
  if (has_channels(tree.channels(), OctreeChannels::Color)) {
    out.push_back(prefix + ".ot");
    write_octree(out.back(), tree, OctreeFileFormat::Full);
  }
  out.push_back(prefix + "_occupied.ply");
  write_ply(out.back(), octree_occupied_cloud(tree));
  return out;
}

}  // namespace

std::vector<std::string> save_metric_map(const std::string& prefix, const MetricMap& map) {
  if (const auto* m = dynamic_cast<const MultiMetricMap*>(&map)) {
    std::vector<std::string> out;
    for (std::size_t i = 0; i < m->entries().size(); ++i) {
      const MetricMap& sub = *m->entries()[i].map;
      const auto files = save_metric_map(fmt::format("{}_{:02}_{}", prefix, i, sub.kind()), sub);
      out.insert(out.end(), files.begin(), files.end());
    }
    return out;
  }
  if (const auto* g = dynamic_cast<const OccupancyGridMetricMap*>(&map)) {
    return save_grid_map(prefix, g->grid());
  }
  if (const auto* p = dynamic_cast<const PointsMetricMap*>(&map)) {
    return save_points_map(prefix, p->points().cloud());
  }
  if (const auto* b = dynamic_cast<const BeaconMap*>(&map)) return save_beacon_map(prefix, *b);
  if (const auto* l = dynamic_cast<const LandmarkMap*>(&map)) return save_landmark_map(prefix, *l);
  if (const auto* h = dynamic_cast<const HeightMap*>(&map)) return save_height_map(prefix, *h);
  if (const auto* o = dynamic_cast<const OctreeMetricMap*>(&map)) return save_octree_map(prefix, o->tree());
  throw InvalidArgument(fmt::format("no file format for a map of kind '{}'", map.kind()));
}

}  // namespace rove
