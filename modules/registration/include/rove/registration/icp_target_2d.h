#pragma once
/// \file
/// IcpTarget2D: the reference ("map") side of 2D scan matching — a set of
/// planar points with a KD-tree and, optionally, unit normals — built from a
/// point set, any PointCloudLike cloud (x, y used), or the occupied cells of
/// an occupancy grid. Build it once per map revision and match many scans
/// against it (ICP-SLAM rebuilds it when the map changes).
///
/// Thread-safety: immutable after construction; any number of icp_2d calls
/// may share one target concurrently.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/core/arithmetic.h"
#include "rove/maps/kdtree.h"
#include "rove/maps/occupancy_grid.h"
#include "rove/maps/point_cloud_concept.h"

namespace rove {

/// Options of IcpTarget2D.
struct IcpTarget2DOptions {
  /// Neighbours (including the point) used to fit each point's normal by
  /// PCA; 0 computes no normals. Normals are needed by the point-to-line
  /// metric. ≥ 3 when not 0. Default 0.
  std::size_t normal_neighbors = 0;
  /// Grid only: a cell is occupied (becomes a target point at its center)
  /// when its probability of being free is below this (MRPT's
  /// determineMatching2D uses 0.5). In (0, 1]. Default 0.5.
  float occupied_below_free_probability = 0.5f;
  /// The arithmetic of the ICP runs that will use the target (it must equal
  /// their Icp2dOptions::arithmetic). Double: the points as given, searched
  /// in double. Mrpt: the points rounded to float as MRPT's point maps hold
  /// them, searched by a float KD-tree whose squared distances are MRPT's
  /// (nanoflann's) to the bit. Default Double.
  Arithmetic arithmetic = Arithmetic::Double;
};

/// The reference side of 2D ICP. See the file comment.
class IcpTarget2D {
 public:
  /// An empty target (every match fails with TooFewCorrespondences).
  IcpTarget2D();
  /// Indexes the finite points of `points` (meters, map frame; rounded to
  /// float with Arithmetic::Mrpt); non-finite points, and with Mrpt those
  /// beyond float's range, are dropped.
  /// Preconditions (InvalidArgument): options valid.
  explicit IcpTarget2D(std::vector<Eigen::Vector2d> points, const IcpTarget2DOptions& options = {});
  /// The x, y of every point of a cloud.
  template <PointCloudLike C>
  static IcpTarget2D from_cloud(const C& cloud, const IcpTarget2DOptions& options = {}) {
    std::vector<Eigen::Vector2d> pts;
    const std::size_t n = point_count(cloud);
    pts.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& p = point_at(cloud, i);
      pts.emplace_back(static_cast<double>(p[0]), static_cast<double>(p[1]));
    }
    return IcpTarget2D(std::move(pts), options);
  }
  /// The centers of the occupied cells of a grid (see
  /// IcpTarget2DOptions::occupied_below_free_probability), in row order.
  template <GridCell Cell>
  static IcpTarget2D from_grid(const OccupancyGridT<Cell>& grid,
                               const IcpTarget2DOptions& options = {});

  IcpTarget2D(IcpTarget2D&&) noexcept;
  IcpTarget2D& operator=(IcpTarget2D&&) noexcept;
  ~IcpTarget2D();

  /// Number of indexed points.
  std::size_t size() const noexcept { return points_.size(); }
  /// True when there is no point.
  bool empty() const noexcept { return points_.empty(); }
  /// The indexed points, meters (finite only; float values with
  /// Arithmetic::Mrpt).
  const std::vector<Eigen::Vector2d>& points() const noexcept { return points_; }
  /// The arithmetic the target was built for (IcpTarget2DOptions).
  Arithmetic arithmetic() const noexcept { return options_.arithmetic; }
  /// The KD-tree over points() in double (indices refer to points()).
  /// Empty unless arithmetic() is Double.
  const KdTree2d& tree() const noexcept { return tree_; }
  /// The KD-tree over points() in float, searched as MRPT's KD-tree over its
  /// point maps: the same nearest point and the same squared distance, to
  /// the bit. Empty unless arithmetic() is Mrpt.
  const KdTree2f& mrpt_tree() const noexcept { return mrpt_tree_; }
  /// Calls f(tree()) or f(mrpt_tree()), whichever the arithmetic built.
  template <typename F>
  decltype(auto) with_tree(F&& f) const {
    return options_.arithmetic == Arithmetic::Mrpt ? f(mrpt_tree_) : f(tree_);
  }
  /// True when normals were computed.
  bool has_normals() const noexcept { return !normals_.empty(); }
  /// Unit normals, one per point (empty unless has_normals()). A point whose
  /// neighbourhood is degenerate (all neighbours equal) gets (0, 0).
  std::span<const Eigen::Vector2d> normals() const noexcept { return normals_; }
  /// The unit normal at point i: normals()[i] when has_normals(), else
  /// fitted as estimate_normals_2d does over the k nearest points ((0, 0)
  /// when they have no extent). Preconditions: i < size(), k ≥ 2.
  Eigen::Vector2d normal_at(std::uint32_t i, std::size_t k) const;
  /// The options the target was built with.
  const IcpTarget2DOptions& options() const noexcept { return options_; }

 private:
  std::vector<Eigen::Vector2d> points_;
  std::vector<Eigen::Vector2d> normals_;
  KdTree2d tree_;
  KdTree2f mrpt_tree_;
  IcpTarget2DOptions options_;
};

/// Unit normals of `points` by PCA over the k nearest neighbours in `tree`
/// (built over the same points): the eigenvector of the smallest eigenvalue
/// of the neighbourhood covariance, (0, 0) when the neighbourhood has no
/// extent. Preconditions: k ≥ 2; num_threads in [0, kMaxThreads] (0: all
/// hardware threads).
template <typename Scalar>
std::vector<Eigen::Vector2d> estimate_normals_2d(std::span<const Eigen::Vector2d> points,
                                                 const KdTree<2, Scalar>& tree, std::size_t k,
                                                 int num_threads = 1);
extern template std::vector<Eigen::Vector2d> estimate_normals_2d(
    std::span<const Eigen::Vector2d>, const KdTree<2, float>&, std::size_t, int);
extern template std::vector<Eigen::Vector2d> estimate_normals_2d(
    std::span<const Eigen::Vector2d>, const KdTree<2, double>&, std::size_t, int);

extern template IcpTarget2D IcpTarget2D::from_grid(const OccupancyGridT<std::int8_t>&,
                                                   const IcpTarget2DOptions&);
extern template IcpTarget2D IcpTarget2D::from_grid(const OccupancyGridT<std::int16_t>&,
                                                   const IcpTarget2DOptions&);

}  // namespace rove
