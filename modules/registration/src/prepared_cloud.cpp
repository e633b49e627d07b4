#include "rove/registration/prepared_cloud.h"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "rove/core/check.h"
#include "rove/registration/parallel.h"

namespace rove {

namespace {
struct Nothing {
  Nothing& operator+=(const Nothing&) { return *this; }
};
// Returns the distance to the farthest of the neighbours used (0 if fewer
// than 3 were found); `bound` limits the search (infinite: none).
// `neighbors` (k entries, or null) receives the neighbours' indices and
// `sq_distances` (k entries, or null) their squared distances.
template <typename PointOf>
float local_surface(const KdTree3f& tree, const PointOf& point, const Eigen::Vector3f& query,
                    std::size_t k, double gicp_epsilon, Eigen::Vector3f* normal,
                    Eigen::Matrix3d* covariance, float bound, std::uint32_t* neighbors = nullptr,
                    float* sq_distances = nullptr, Eigen::Vector3d* axis = nullptr);
}  // namespace

PreparedCloud3D::PreparedCloud3D() = default;
PreparedCloud3D::PreparedCloud3D(PreparedCloud3D&&) noexcept = default;
PreparedCloud3D& PreparedCloud3D::operator=(PreparedCloud3D&&) noexcept = default;
PreparedCloud3D::~PreparedCloud3D() = default;

PreparedCloud3D::PreparedCloud3D(std::vector<Eigen::Vector3f> points, const PrepareOptions& options)
    : points_(std::move(points)), options_(options) {
  ROVE_CHECK_GE(options.neighbors, std::size_t{3});
  ROVE_CHECK_MSG(options.gicp_epsilon > 0 && options.gicp_epsilon <= 1,
                 "gicp_epsilon must be in (0, 1], got {}", options.gicp_epsilon);
  ROVE_CHECK_GE(options.num_threads, 1);
  ROVE_CHECK_LT(points_.size(), std::size_t{std::numeric_limits<std::uint32_t>::max()});
  std::erase_if(points_, [](const Eigen::Vector3f& p) { return !p.allFinite(); });
  tree_ = KdTree3f(points_);
  if (points_.empty()) return;
  if (options.normals) normals_.assign(points_.size(), Eigen::Vector3f::Zero());
  if (options.covariances) {
    covariances_.assign(points_.size(), Eigen::Matrix3d::Identity());
    gicp_axes_.assign(points_.size(), Eigen::Vector3d::Zero());
  }
  if (!options.normals && !options.covariances) return;
  // The tree indexes every point of points_ (all finite), so a neighbour's
  // index is its position in points_.
  const auto point = [this](std::uint32_t j) -> const Eigen::Vector3f& { return points_[j]; };
  // Points are visited in the tree's order, so consecutive queries are
  // close in space, and each search is bounded by what the previous one
  // found: the k neighbours of p, within r of it, are within r + |q − p| of
  // q, so q's k nearest all lie in that ball and the search needs to look
  // nowhere else (the same neighbours as an unbounded search, but for which
  // of several points tied at the k-th distance is kept; far fewer nodes
  // visited). Blocks of the order run in parallel, each from an
  // unbounded first search, so the results do not depend on the threads.
  const std::span<const std::uint32_t> order = tree_.tree_order();
  const std::size_t k = std::min(options.neighbors, points_.size());
  neighbors_per_point_ = k;
  neighbor_indices_.assign(points_.size() * k, 0);
  neighbor_sq_distances_.assign(points_.size() * k, 0.0f);
  constexpr float kInf = std::numeric_limits<float>::infinity();
  detail::parallel_reduce(order.size(), options.num_threads, Nothing{},
                          [&](std::size_t begin, std::size_t end, Nothing&) {
    float reach = kInf;  // previous query's farthest neighbour, meters
    Eigen::Vector3f prev = Eigen::Vector3f::Zero();
    for (std::size_t t = begin; t < end; ++t) {
      const std::uint32_t i = order[t];
      const Eigen::Vector3f& q = points_[i];
      // A hair above, so rounding cannot drop a neighbour on the sphere.
      const float bound =
          reach == kInf ? kInf : (reach + (q - prev).norm()) * (1 + 1e-5f) + 1e-6f;
      reach = local_surface(tree_, point, q, k, options.gicp_epsilon,
                            options.normals ? &normals_[i] : nullptr,
                            options.covariances ? &covariances_[i] : nullptr, bound,
                            &neighbor_indices_[i * k], &neighbor_sq_distances_[i * k],
                            options.covariances ? &gicp_axes_[i] : nullptr);
      prev = q;
    }
  });
}

namespace {

/// local_surface_3d with the neighbours' coordinates read through `point`
/// (source index → coordinates).
template <typename PointOf>
float local_surface(const KdTree3f& tree, const PointOf& point, const Eigen::Vector3f& query,
                    std::size_t k, double gicp_epsilon, Eigen::Vector3f* normal,
                    Eigen::Matrix3d* covariance, float bound, std::uint32_t* neighbors,
                    float* sq_distances, Eigen::Vector3d* axis) {
  constexpr std::size_t kMaxK = 64;
  Neighbor<float> buf[kMaxK];
  std::vector<Neighbor<float>> big;
  std::span<Neighbor<float>> nn(buf, std::min(k, kMaxK));
  if (k > kMaxK) {
    big.resize(k);
    nn = big;
  }
  std::size_t m = std::isfinite(bound) ? tree.knn(query, k, nn, bound) : tree.knn(query, k, nn);
  if (m < std::min(k, tree.size())) m = tree.knn(query, k, nn);  // the bound was too tight
  for (std::size_t j = 0; j < m; ++j) {
    if (neighbors) neighbors[j] = nn[j].index;
    if (sq_distances) sq_distances[j] = nn[j].sq_distance;
  }
  if (m < 3) {
    if (normal) normal->setZero();
    if (covariance) *covariance = Eigen::Matrix3d::Identity();
    if (axis) axis->setZero();
    return std::numeric_limits<float>::infinity();
  }
  const float reach = std::sqrt(nn[m - 1].sq_distance);
  // Moments about the query point: the sums stay small, so the covariance
  // keeps its precision far from the origin.
  const Eigen::Vector3d origin = query.cast<double>();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  for (std::size_t j = 0; j < m; ++j) {
    const Eigen::Vector3d p = Eigen::Vector3f(point(nn[j].index)).cast<double>() - origin;
    mean += p;
    S.noalias() += p * p.transpose();
  }
  mean /= static_cast<double>(m);
  Eigen::Matrix3d C = S / static_cast<double>(m);
  C.noalias() -= mean * mean.transpose();
  // Closed-form 3×3 eigen-decomposition (as small_gicp): the iterative
  // solver costs more than the neighbour search here.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(C);
  const bool flat = !(eig.eigenvalues()(2) > 0);
  if (normal) *normal = flat ? Eigen::Vector3f::Zero() : Eigen::Vector3f(eig.eigenvectors().col(0).cast<float>());
  if (covariance) {
    if (flat) {
      *covariance = Eigen::Matrix3d::Identity();
      if (axis) axis->setZero();
    } else {
      // V·diag(ε, 1, 1)·Vᵀ = I − (1 − ε)·v₁v₁ᵀ.
      const Eigen::Vector3d v = eig.eigenvectors().col(0);
      *covariance = Eigen::Matrix3d::Identity() - (1.0 - gicp_epsilon) * v * v.transpose();
      if (axis) *axis = v;
    }
  }
  return reach;
}

}  // namespace

void local_surface_3d(const KdTree3f& tree, const Eigen::Vector3f& query, std::size_t k,
                      double gicp_epsilon, Eigen::Vector3f* normal, Eigen::Matrix3d* covariance) {
  local_surface(tree, [&](std::uint32_t i) { return tree.indexed_point(i); }, query, k,
                gicp_epsilon, normal, covariance, std::numeric_limits<float>::infinity());
}

}  // namespace rove
