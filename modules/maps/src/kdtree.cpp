#include "rove/maps/kdtree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <nanoflann.hpp>

#include "rove/core/check.h"

namespace rove {

namespace {

/// nanoflann's dataset interface over a contiguous array of points. The
/// pointer is updated after the points are reordered into tree order.
template <int Dim, typename Scalar>
struct ContiguousPoints {
  const Eigen::Matrix<Scalar, Dim, 1>* data = nullptr;
  std::size_t count = 0;
  std::size_t kdtree_get_point_count() const { return count; }
  Scalar kdtree_get_pt(std::uint32_t idx, std::size_t dim) const { return data[idx][static_cast<Eigen::Index>(dim)]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

/// Squared L2 distance with the dimension known at compile time, reading a
/// point's coordinates together.
template <int Dim, typename Scalar>
struct L2Fixed {
  using ElementType = Scalar;
  using DistanceType = Scalar;
  const ContiguousPoints<Dim, Scalar>& source;
  explicit L2Fixed(const ContiguousPoints<Dim, Scalar>& s) : source(s) {}
  Scalar evalMetric(const Scalar* a, std::uint32_t b_idx, std::size_t) const {
    const auto& b = source.data[b_idx];
    Scalar d = 0;
    for (int i = 0; i < Dim; ++i) {
      const Scalar diff = a[i] - b[i];
      d += diff * diff;
    }
    return d;
  }
  template <typename U, typename V>
  Scalar accum_dist(const U a, const V b, std::size_t) const {
    return (a - b) * (a - b);
  }
};

template <typename Scalar>
bool finite_point(const Scalar* p, int dim) {
  for (int i = 0; i < dim; ++i)
    if (!std::isfinite(p[i])) return false;
  return true;
}

/// A result set for nearest-within-radius: keeps the single best point. The
/// bound starts one ulp above max_distance², because nanoflann admits a
/// point only when its distance is strictly below worstDist(); dist < next(r²)
/// is dist <= r² exactly.
template <typename Scalar>
struct NearestWithin {
  using DistanceType = Scalar;
  using IndexType = std::uint32_t;
  Scalar worst;
  std::uint32_t index = 0;
  bool found = false;
  std::size_t size() const { return found ? 1 : 0; }
  bool full() const { return true; }
  bool addPoint(Scalar dist, std::uint32_t idx) {
    // nanoflann reads worstDist() once per leaf, so check again here.
    if (dist < worst) {
      worst = dist;
      index = idx;
      found = true;
    }
    return true;
  }
  Scalar worstDist() const { return worst; }
};

}  // namespace

template <int Dim, typename Scalar>
struct KdTree<Dim, Scalar>::Impl {
  using Index = nanoflann::KDTreeSingleIndexAdaptor<L2Fixed<Dim, Scalar>, ContiguousPoints<Dim, Scalar>,
                                                    Dim, std::uint32_t>;
  KdTreeOptions options;
  std::size_t source_size = 0;
  std::vector<Point> points;              // indexed points, tree order
  std::vector<std::uint32_t> source_of;   // tree position -> source index
  std::vector<std::uint32_t> position_of; // source index -> tree position (or npos)
  ContiguousPoints<Dim, Scalar> adaptor;
  std::unique_ptr<Index> index;
};

template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::KdTree() : KdTree(std::vector<Point>{}, KdTreeOptions{}) {}

template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::KdTree(std::vector<Point> points, const KdTreeOptions& options)
    : impl_(std::make_unique<Impl>()) {
  ROVE_CHECK_GE(options.leaf_size, std::size_t{1});
  ROVE_CHECK_LT(points.size(), static_cast<std::size_t>(std::numeric_limits<std::uint32_t>::max()));
  Impl& m = *impl_;
  m.options = options;
  m.source_size = points.size();

  // Drop non-finite points, remembering each kept point's source index.
  std::vector<std::uint32_t> kept_source;
  kept_source.reserve(points.size());
  std::size_t w = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!finite_point(points[i].data(), Dim)) continue;
    points[w++] = points[i];
    kept_source.push_back(static_cast<std::uint32_t>(i));
  }
  points.resize(w);

  m.adaptor.data = points.data();
  m.adaptor.count = points.size();
  m.index = std::make_unique<typename Impl::Index>(
      Dim, m.adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(options.leaf_size));

  // Store the points in tree order: leaf k then covers a consecutive range,
  // and nanoflann's permutation becomes the identity.
  auto& perm = m.index->vAcc;
  m.points.resize(points.size());
  m.source_of.resize(points.size());
  for (std::size_t i = 0; i < perm.size(); ++i) {
    m.points[i] = points[perm[i]];
    m.source_of[i] = kept_source[perm[i]];
    perm[i] = static_cast<std::uint32_t>(i);
  }
  m.adaptor.data = m.points.data();
  m.position_of.assign(m.source_size, std::numeric_limits<std::uint32_t>::max());
  for (std::size_t i = 0; i < m.source_of.size(); ++i)
    m.position_of[m.source_of[i]] = static_cast<std::uint32_t>(i);
}

template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::KdTree(KdTree&&) noexcept = default;
template <int Dim, typename Scalar>
KdTree<Dim, Scalar>& KdTree<Dim, Scalar>::operator=(KdTree&&) noexcept = default;
template <int Dim, typename Scalar>
KdTree<Dim, Scalar>::~KdTree() = default;

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::size() const noexcept {
  return impl_ ? impl_->points.size() : 0;
}

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::source_size() const noexcept {
  return impl_ ? impl_->source_size : 0;
}

template <int Dim, typename Scalar>
const KdTreeOptions& KdTree<Dim, Scalar>::options() const noexcept {
  static const KdTreeOptions kDefault;
  return impl_ ? impl_->options : kDefault;
}

template <int Dim, typename Scalar>
typename KdTree<Dim, Scalar>::Point KdTree<Dim, Scalar>::indexed_point(std::uint32_t source_index) const {
  ROVE_CHECK_LT(static_cast<std::size_t>(source_index), source_size());
  const std::uint32_t pos = impl_->position_of[source_index];
  ROVE_CHECK_MSG(pos != std::numeric_limits<std::uint32_t>::max(),
                 "point {} is not indexed (non-finite coordinates)", source_index);
  return impl_->points[pos];
}

template <int Dim, typename Scalar>
std::optional<Neighbor<Scalar>> KdTree<Dim, Scalar>::nearest(const Point& q) const {
  if (empty() || !finite_point(q.data(), Dim)) return std::nullopt;
  std::uint32_t pos = 0;
  Scalar d2 = 0;
  nanoflann::KNNResultSet<Scalar, std::uint32_t, std::size_t> rs(1);
  rs.init(&pos, &d2);
  impl_->index->findNeighbors(rs, q.data(), nanoflann::SearchParams());
  if (rs.size() == 0) return std::nullopt;
  return Result{impl_->source_of[pos], d2};
}

template <int Dim, typename Scalar>
std::optional<Neighbor<Scalar>> KdTree<Dim, Scalar>::nearest(const Point& q, Scalar max_distance) const {
  ROVE_CHECK_GE(max_distance, Scalar(0));
  if (empty() || !finite_point(q.data(), Dim)) return std::nullopt;
  NearestWithin<Scalar> rs{std::nextafter(max_distance * max_distance,
                                          std::numeric_limits<Scalar>::infinity())};
  impl_->index->findNeighbors(rs, q.data(), nanoflann::SearchParams());
  if (!rs.found) return std::nullopt;
  return Result{impl_->source_of[rs.index], rs.worst};
}

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::knn(const Point& q, std::size_t k, std::span<Result> out) const {
  ROVE_CHECK_GE(out.size(), k);
  if (k == 0 || empty() || !finite_point(q.data(), Dim)) return 0;
  k = std::min(k, size());
  constexpr std::size_t kStack = 64;
  std::uint32_t pos_stack[kStack];
  Scalar d_stack[kStack];
  std::vector<std::uint32_t> pos_heap;
  std::vector<Scalar> d_heap;
  std::uint32_t* pos = pos_stack;
  Scalar* d = d_stack;
  if (k > kStack) {
    pos_heap.resize(k);
    d_heap.resize(k);
    pos = pos_heap.data();
    d = d_heap.data();
  }
  nanoflann::KNNResultSet<Scalar, std::uint32_t, std::size_t> rs(k);
  rs.init(pos, d);
  impl_->index->findNeighbors(rs, q.data(), nanoflann::SearchParams());
  const std::size_t n = rs.size();
  for (std::size_t i = 0; i < n; ++i) out[i] = Result{impl_->source_of[pos[i]], d[i]};
  return n;
}

template <int Dim, typename Scalar>
std::vector<Neighbor<Scalar>> KdTree<Dim, Scalar>::knn(const Point& q, std::size_t k) const {
  std::vector<Result> out(std::min(k, size()));
  out.resize(knn(q, out.size(), out));
  return out;
}

template <int Dim, typename Scalar>
std::size_t KdTree<Dim, Scalar>::radius(const Point& q, Scalar radius, std::vector<Result>& out,
                                        bool sorted) const {
  ROVE_CHECK_GE(radius, Scalar(0));
  ROVE_CHECK_FINITE(radius);
  out.clear();
  if (empty() || !finite_point(q.data(), Dim)) return 0;
  // nanoflann's RadiusResultSet keeps dist < r²; bump r² by one ulp so that
  // points exactly on the sphere are included (distance <= radius).
  const Scalar r2 = std::nextafter(radius * radius, std::numeric_limits<Scalar>::infinity());
  std::vector<std::pair<std::uint32_t, Scalar>> hits;
  nanoflann::RadiusResultSet<Scalar, std::uint32_t> rs(r2, hits);
  impl_->index->findNeighbors(rs, q.data(), nanoflann::SearchParams());
  const Scalar exact_r2 = radius * radius;
  out.reserve(hits.size());
  for (const auto& [pos, d2] : hits)
    if (d2 <= exact_r2) out.push_back(Result{impl_->source_of[pos], d2});
  if (sorted)
    std::sort(out.begin(), out.end(), [](const Result& a, const Result& b) {
      return a.sq_distance < b.sq_distance || (a.sq_distance == b.sq_distance && a.index < b.index);
    });
  return out.size();
}

template <int Dim, typename Scalar>
std::vector<Neighbor<Scalar>> KdTree<Dim, Scalar>::radius(const Point& q, Scalar r) const {
  std::vector<Result> out;
  radius(q, r, out, true);
  return out;
}

template class KdTree<2, float>;
template class KdTree<3, float>;
template class KdTree<2, double>;
template class KdTree<3, double>;

}  // namespace rove
