#pragma once
/// \file
/// KdTree: exact nearest, k-nearest and radius search over 2D or 3D points.
///
///   rove::KdTree3f tree(cloud);                 // any PointCloudLike
///   if (auto nn = tree.nearest(q))              // q: Eigen::Vector3f
///     use(nn->index, nn->sq_distance);          // index into `cloud`
///   auto knn = tree.knn(q, 8);                  // sorted, nearest first
///   tree.radius(q, 0.5f, neighbors);            // radius in meters
///
/// The tree copies the coordinates it indexes (the first Dim coordinates of
/// each point, converted to Scalar) and stores them in tree order, so a leaf
/// scan reads consecutive memory; the source cloud may change or go away
/// afterwards without affecting the tree. The build sorts that copy into
/// tree order as it goes, partitioning it in place: each node splits its
/// cell in the middle of the cell's widest side, sliding the split onto the
/// points when it misses them (the sliding-midpoint rule, as nanoflann and
/// FLANN). Points with a NaN or infinite coordinate are not indexed (as
/// PCL's KdTreeFLANN); indices in results always refer to the source cloud.
///
/// Ties (equal distances) are broken in an unspecified but deterministic
/// order. Distances are squared Euclidean distances in Scalar precision,
/// computed as sum over d of (q_d - p_d)^2.
///
/// Thread-safety: every const member may be called from any number of
/// threads at once; construction and assignment need exclusive access.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "rove/maps/point_cloud_concept.h"

namespace rove {

/// Options of KdTree.
struct KdTreeOptions {
  /// Largest number of points in a leaf. Smaller leaves mean a deeper tree
  /// (slower build, more memory); larger leaves mean more distance
  /// evaluations per query. 10 was the fastest for build + kNN(k = 1..10) on
  /// the room_scan clouds (docs/point-maps.md). Must be >= 1.
  std::size_t leaf_size = 10;
};

/// One search result: the index of the point in the source cloud and its
/// squared distance to the query, meters².
template <typename Scalar>
struct Neighbor {
  std::uint32_t index = 0;
  Scalar sq_distance = 0;
  friend bool operator==(const Neighbor&, const Neighbor&) = default;
};

/// An exact KD-tree over Dim-dimensional points (Dim = 2 or 3) with Scalar
/// coordinates (float or double). See the file comment.
template <int Dim, typename Scalar>
class KdTree {
  static_assert(Dim == 2 || Dim == 3, "KdTree supports 2D and 3D points");
  static_assert(std::is_same_v<Scalar, float> || std::is_same_v<Scalar, double>,
                "KdTree supports float and double coordinates");

 public:
  using Point = Eigen::Matrix<Scalar, Dim, 1>;
  using Result = Neighbor<Scalar>;

  /// An empty tree: every search finds nothing.
  KdTree();
  /// Indexes the first Dim coordinates of every finite point of `cloud`.
  /// Precondition (InvalidArgument): the cloud has fewer than 2^32 points,
  /// options.leaf_size >= 1.
  template <PointCloudLike C>
    requires(cloud_dim_v<C> >= Dim)
  explicit KdTree(const C& cloud, const KdTreeOptions& options = {})
      : KdTree(finite_points(cloud), options) {}
  /// Indexes `points` (the indices in results refer to this vector).
  explicit KdTree(std::vector<Point> points, const KdTreeOptions& options = {});

  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;
  KdTree(const KdTree&) = delete;
  KdTree& operator=(const KdTree&) = delete;
  ~KdTree();

  /// Number of indexed (finite) points.
  std::size_t size() const noexcept;
  /// True when no point is indexed.
  bool empty() const noexcept { return size() == 0; }
  /// Number of points of the source cloud (indexed or not).
  std::size_t source_size() const noexcept;
  /// The options the tree was built with.
  const KdTreeOptions& options() const noexcept;
  /// The indexed point with source index `i`, in Scalar precision.
  /// Precondition: i < source_size() and point i was finite.
  Point indexed_point(std::uint32_t source_index) const;

  /// The nearest indexed point to q; nullopt when the tree is empty or q is
  /// not finite.
  std::optional<Result> nearest(const Point& q) const;
  /// The nearest indexed point within `max_distance` meters of q (inclusive);
  /// nullopt if there is none. Precondition: max_distance >= 0.
  std::optional<Result> nearest(const Point& q, Scalar max_distance) const;
  /// As above, with a guess: `hint` is the source index of a point likely
  /// to be (nearly) the nearest, e.g. the partner of the same query point
  /// in the previous ICP iteration. Its distance bounds the search, and the
  /// search starts at the hint's leaf and climbs only to the smallest node
  /// whose cell holds the whole ball of that radius (nothing outside it can
  /// be nearer), so it visits a few nodes instead of descending from the
  /// root. The result is the same as without the hint, ties included. A
  /// hint that is out of range or not indexed is ignored.
  std::optional<Result> nearest(const Point& q, Scalar max_distance, std::uint32_t hint) const;

  /// The min(k, size()) nearest points to q, nearest first, written to the
  /// front of `out`; returns how many were written (0 if q is not finite).
  /// Precondition: out.size() >= k.
  std::size_t knn(const Point& q, std::size_t k, std::span<Result> out) const;
  /// As above, returned in a new vector.
  std::vector<Result> knn(const Point& q, std::size_t k) const;
  /// The min(k, size()) nearest points to q among those within
  /// `max_distance` meters of it (inclusive), nearest first, written to the
  /// front of `out`; returns how many were written (fewer than k when fewer
  /// lie within max_distance). When it returns k, the same distances as the
  /// unbounded knn(), and the same points but for which of several tied at
  /// the k-th distance is kept; a good bound only prunes more of the tree.
  /// Preconditions: out.size() >= k, max_distance >= 0 (may be
  /// infinite).
  std::size_t knn(const Point& q, std::size_t k, std::span<Result> out, Scalar max_distance) const;

  /// The source indices of the indexed points in the tree's storage order:
  /// points that are close in this order are close in space (every leaf is
  /// a consecutive run). Visiting queries in this order gives consecutive
  /// searches overlapping paths and neighbourhoods.
  std::span<const std::uint32_t> tree_order() const noexcept;

  /// Every indexed point within `radius` meters of q (distance <= radius),
  /// replacing the contents of `out`; nearest first when `sorted`. Returns
  /// out.size(). Precondition: radius >= 0 and finite.
  std::size_t radius(const Point& q, Scalar radius, std::vector<Result>& out,
                     bool sorted = true) const;
  /// As above, returned in a new vector (sorted).
  std::vector<Result> radius(const Point& q, Scalar radius) const;

 private:
  /// The finite points of a source cloud in Scalar precision, each with its
  /// index in the source.
  struct FinitePoints {
    std::vector<Point> points;
    std::vector<std::uint32_t> source_index;
    std::size_t source_size = 0;
  };

  template <PointCloudLike C>
  static FinitePoints finite_points(const C& cloud) {
    FinitePoints f;
    const std::size_t n = point_count(cloud);
    f.source_size = n;
    if (n >= std::size_t{0xffffffffu}) return f;  // rejected by the constructor
    f.points.resize(n);
    f.source_index.resize(n);
    std::size_t w = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const Point p = point_at(cloud, i).template head<Dim>().template cast<Scalar>();
      bool finite = true;
      for (int d = 0; d < Dim; ++d) finite = finite && std::isfinite(p[d]);
      if (!finite) continue;
      f.points[w] = p;
      f.source_index[w] = static_cast<std::uint32_t>(i);
      ++w;
    }
    f.points.resize(w);
    f.source_index.resize(w);
    return f;
  }

  explicit KdTree(FinitePoints finite, const KdTreeOptions& options);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

using KdTree2f = KdTree<2, float>;
using KdTree3f = KdTree<3, float>;
using KdTree2d = KdTree<2, double>;
using KdTree3d = KdTree<3, double>;

extern template class KdTree<2, float>;
extern template class KdTree<3, float>;
extern template class KdTree<2, double>;
extern template class KdTree<3, double>;

}  // namespace rove
