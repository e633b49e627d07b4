#include "rove/maps/octree_export.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/memory_budget.h"

namespace rove {

PointCloud octree_occupied_cloud(const OccupancyOctree& tree, const OctreeCloudOptions& options) {
  const bool colors = has_channels(tree.channels(), OctreeChannels::Color);
  PointCloud cloud;
  if (colors) cloud.set_channels(PointChannels::Color);
  const auto add = [&](const Eigen::Vector3d& p, const OctreeKey& k) {
    if (cloud.size() >= options.max_points) {
      throw ResourceError(fmt::format("octree cloud: more than {} occupied cells", options.max_points));
    }
    if (colors) {
      cloud.push_back(p.cast<float>(), tree.color_at(k).value_or(Rgb8{255, 255, 255}));
    } else {
      cloud.push_back(p.cast<float>());
    }
  };
  tree.for_each_leaf([&](const OctreeLeaf& l) {
    if (!tree.is_occupied(l.log_odds)) return;
    if (!options.finest_cells || l.depth == kOctreeDepth) {
      add(tree.center_of(l.key, l.depth), l.key);
      return;
    }
    const int n = 1 << (kOctreeDepth - l.depth);
    if (cloud.size() + static_cast<std::size_t>(n) * n * n > options.max_points) {
      throw ResourceError(fmt::format("octree cloud: more than {} occupied cells", options.max_points));
    }
    for (int dz = 0; dz < n; ++dz) {
      for (int dy = 0; dy < n; ++dy) {
        for (int dx = 0; dx < n; ++dx) {
          const OctreeKey k{static_cast<std::uint16_t>(l.key.x + dx), static_cast<std::uint16_t>(l.key.y + dy),
                            static_cast<std::uint16_t>(l.key.z + dz)};
          add(tree.center_of(k), k);
        }
      }
    }
  });
  return cloud;
}

OccupancyGrid octree_slice(const OccupancyOctree& tree, double z, const OctreeSliceOptions& options) {
  const double res = tree.resolution();
  const auto kz = tree.key_of(Eigen::Vector3d(0.0, 0.0, z));
  ROVE_CHECK_MSG(kz.has_value(), "octree_slice: height {} is not finite or outside the octree", z);
  Eigen::Vector4d area;
  if (options.area) {
    area = *options.area;
    ROVE_CHECK_MSG(area.allFinite() && area[0] < area[2] && area[1] < area[3],
                   "octree_slice: area ({}, {}, {}, {}) is not a box", area[0], area[1], area[2], area[3]);
  } else {
    Eigen::Vector3d lo, hi;
    tree.metric_bounds(lo, hi);
    if (lo.x() > hi.x()) lo = hi = Eigen::Vector3d::Zero(), hi.x() = hi.y() = res;
    area = Eigen::Vector4d(lo.x(), lo.y(), hi.x(), hi.y());
  }
  // Align the grid with the tree's cells, within the tree's extent.
  const double half = 0.5 * static_cast<double>(2 * kOctreeKeyOffset) * res;
  const double x0 = std::max(std::floor(area[0] / res) * res, -half);
  const double y0 = std::max(std::floor(area[1] / res) * res, -half);
  const double x1 = std::min(std::max(std::ceil(area[2] / res) * res, x0 + res), half);
  const double y1 = std::min(std::max(std::ceil(area[3] / res) * res, y0 + res), half);
  ROVE_CHECK_MSG(x0 < x1 && y0 < y1, "octree_slice: area ({}, {}, {}, {}) is outside the octree", area[0], area[1],
                 area[2], area[3]);
  const double cells = std::round((x1 - x0) / res) * std::round((y1 - y0) / res);
  if (!(cells <= static_cast<double>(options.max_cells))) {
    throw ResourceError(fmt::format("octree slice: {:.0f} cells exceed the limit of {}", cells, options.max_cells));
  }
  check_memory_budget(checked_bytes(static_cast<std::uint64_t>(cells), 2), "octree slice");
  OccupancyGrid grid(static_cast<float>(x0), static_cast<float>(x1), static_cast<float>(y0), static_cast<float>(y1),
                     static_cast<float>(res), 0.5f);
  // Grid cell (ix, iy) is the finest cell of key (kx0 + ix, ky0 + iy): the
  // leaves are placed by their keys, clipped to the grid (a pruned leaf may
  // cover far more than the area).
  const OctreeKey k0 = tree.key_checked(Eigen::Vector3d(x0 + 0.5 * res, y0 + 0.5 * res, z));
  const long nx = grid.size_x(), ny = grid.size_y();
  const double zc = tree.center_of(*kz).z();
  tree.for_each_leaf_in_box(Eigen::Vector3d(x0 + 0.5 * res, y0 + 0.5 * res, zc),
                            Eigen::Vector3d(x1 - 0.5 * res, y1 - 0.5 * res, zc), [&](const OctreeLeaf& l) {
                              const float p_free = static_cast<float>(1.0 - octree_probability(l.log_odds));
                              const long n = 1L << (kOctreeDepth - l.depth);
                              const long ix0 = static_cast<long>(l.key.x) - k0.x, iy0 = static_cast<long>(l.key.y) - k0.y;
                              for (long iy = std::max(iy0, 0L); iy < std::min(iy0 + n, ny); ++iy) {
                                for (long ix = std::max(ix0, 0L); ix < std::min(ix0 + n, nx); ++ix) {
                                  grid.set_free_probability(static_cast<int>(ix), static_cast<int>(iy), p_free);
                                }
                              }
                            });
  grid.set_empty(tree.empty());
  return grid;
}

}  // namespace rove
