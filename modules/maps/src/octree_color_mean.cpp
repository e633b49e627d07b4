#include "rove/maps/octree_color_mean.h"

#include <map>

#include "octree_rays.h"
#include "rove/core/check.h"

namespace rove {

OctreeColorMean::OctreeColorMean(double resolution) : resolution_(resolution) {
  ROVE_CHECK_MSG(octree_resolution_valid(resolution), "octree resolution {} m is not valid", resolution);
}

std::size_t OctreeColorMean::add(std::span<const Eigen::Vector3f> points, std::span<const Rgb8> colors) {
  ROVE_CHECK_EQ(points.size(), colors.size());
  std::size_t added = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double p[3] = {points[i].x(), points[i].y(), points[i].z()};
    OctreeKey k;
    if (!points[i].allFinite() || !detail::point_to_key(1.0 / resolution_, p, k)) continue;
    Sum& s = sums_[k];
    s.r += colors[i].r, s.g += colors[i].g, s.b += colors[i].b, ++s.n;
    ++added;
  }
  return added;
}

std::size_t OctreeColorMean::apply(OccupancyOctree& tree) const {
  ROVE_CHECK_MSG(has_channels(tree.channels(), OctreeChannels::Color),
                 "OctreeColorMean::apply needs an octree with the Color channel");
  ROVE_CHECK_EQ(tree.resolution(), resolution_);
  // The cells' sums gathered per leaf (a pruned leaf holds many cells),
  // in key order so the result does not depend on the hash table's.
  std::map<std::pair<OctreeKey, int>, Sum> leaves;
  for (const auto& [key, s] : sums_) {
    const auto node = tree.search(key);
    if (!node) continue;
    Sum& l = leaves[{octree_key_at_depth(key, node->depth), node->depth}];
    l.r += s.r, l.g += s.g, l.b += s.b, l.n += s.n;
  }
  const auto mean = [](std::uint64_t sum, std::uint64_t n) { return static_cast<std::uint8_t>((sum + n / 2) / n); };
  for (const auto& [leaf, s] : leaves) {
    tree.update_color(leaf.first, Rgb8{mean(s.r, s.n), mean(s.g, s.n), mean(s.b, s.n)}, OctreeColorUpdate::Set);
  }
  return leaves.size();
}

}  // namespace rove
