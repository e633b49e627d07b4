#pragma once
/// \file
/// OctreeColorMean: the colour of each leaf of an octree as the mean colour
/// of the points that fell in it, over any number of clouds. OctoMap's
/// ColorOcTree updates a leaf point after point (OccupancyOctree::
/// update_color: set, (old + new) / 2, or weighted by occupancy), so its
/// colours depend on the order of the points; this is rove's order-free
/// rule, what `rove octomap build` uses for coloured clouds by default.

#include <cstddef>
#include <cstdint>
#include <span>
#include <unordered_map>

#include <Eigen/Core>

#include "rove/maps/occupancy_octree.h"
#include "rove/maps/point_cloud.h"

namespace rove {

/// Sums of point colours per finest cell (see the file comment).
/// Not thread-safe.
class OctreeColorMean {
 public:
  /// An empty accumulator for trees of `resolution` (meters). Throws
  /// InvalidArgument unless octree_resolution_valid(resolution).
  explicit OctreeColorMean(double resolution);

  /// Adds each point's colour to the finest cell it falls in (map frame,
  /// meters); points not finite or outside the tree are skipped. Returns
  /// the points added. Precondition: one colour per point.
  std::size_t add(std::span<const Eigen::Vector3f> points, std::span<const Rgb8> colors);

  /// Sets the colour of every leaf of `tree` that holds at least one added
  /// point to the mean of those points' colours, per channel, rounded to
  /// the nearest integer (OctreeColorUpdate::Set; inner nodes are refreshed
  /// as update_color does). A leaf that no longer exists (its cells unknown)
  /// keeps nothing. Returns the leaves coloured. Preconditions: the tree
  /// has the Color channel and this resolution.
  std::size_t apply(OccupancyOctree& tree) const;

  /// Finest cells with at least one point.
  std::size_t cells() const noexcept { return sums_.size(); }

 private:
  struct Sum {
    std::uint64_t r = 0, g = 0, b = 0, n = 0;
  };
  double resolution_;
  std::unordered_map<OctreeKey, Sum, OctreeKeyHash> sums_;
};

}  // namespace rove
