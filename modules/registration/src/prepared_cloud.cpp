#include "rove/registration/prepared_cloud.h"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "rove/core/check.h"
#include "rove/registration/parallel.h"

namespace rove {

namespace {
template <typename PointOf>
void local_surface(const KdTree3f& tree, const PointOf& point, const Eigen::Vector3f& query,
                   std::size_t k, double gicp_epsilon, Eigen::Vector3f* normal,
                   Eigen::Matrix3d* covariance);
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
  if (options.covariances) covariances_.assign(points_.size(), Eigen::Matrix3d::Identity());
  if (!options.normals && !options.covariances) return;
  // The tree indexes every point of points_ (all finite), so a neighbour's
  // index is its position in points_.
  const auto point = [this](std::uint32_t j) -> const Eigen::Vector3f& { return points_[j]; };
  detail::parallel_for(points_.size(), options.num_threads, [&](std::size_t i) {
    local_surface(tree_, point, points_[i], options.neighbors, options.gicp_epsilon,
                     options.normals ? &normals_[i] : nullptr,
                     options.covariances ? &covariances_[i] : nullptr);
  });
}

namespace {

/// local_surface_3d with the neighbours' coordinates read through `point`
/// (source index → coordinates).
template <typename PointOf>
void local_surface(const KdTree3f& tree, const PointOf& point, const Eigen::Vector3f& query,
                   std::size_t k, double gicp_epsilon, Eigen::Vector3f* normal,
                   Eigen::Matrix3d* covariance) {
  constexpr std::size_t kMaxK = 64;
  Neighbor<float> buf[kMaxK];
  std::vector<Neighbor<float>> big;
  std::span<Neighbor<float>> nn(buf, std::min(k, kMaxK));
  if (k > kMaxK) {
    big.resize(k);
    nn = big;
  }
  const std::size_t m = tree.knn(query, k, nn);
  if (m < 3) {
    if (normal) normal->setZero();
    if (covariance) *covariance = Eigen::Matrix3d::Identity();
    return;
  }
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
    } else {
      // V·diag(ε, 1, 1)·Vᵀ = I − (1 − ε)·v₁v₁ᵀ.
      const Eigen::Vector3d v = eig.eigenvectors().col(0);
      *covariance = Eigen::Matrix3d::Identity() - (1.0 - gicp_epsilon) * v * v.transpose();
    }
  }
}

}  // namespace

void local_surface_3d(const KdTree3f& tree, const Eigen::Vector3f& query, std::size_t k,
                      double gicp_epsilon, Eigen::Vector3f* normal, Eigen::Matrix3d* covariance) {
  local_surface(tree, [&](std::uint32_t i) { return tree.indexed_point(i); }, query, k,
                gicp_epsilon, normal, covariance);
}

}  // namespace rove
