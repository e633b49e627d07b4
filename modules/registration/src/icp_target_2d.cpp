#include "rove/registration/icp_target_2d.h"

#include <cmath>
#include <type_traits>

#include <Eigen/Eigenvalues>

#include "rove/core/check.h"
#include "rove/core/parallel.h"

namespace rove {
namespace {

std::vector<Eigen::Vector2d> finite_only(std::vector<Eigen::Vector2d> pts, Arithmetic arithmetic) {
  // MRPT's point maps hold float values: a point out of float's range
  // becomes infinite and is dropped with the non-finite ones.
  if (arithmetic == Arithmetic::Mrpt)
    for (auto& p : pts) p = p.cast<float>().cast<double>();
  std::erase_if(pts, [](const Eigen::Vector2d& p) { return !p.allFinite(); });
  return pts;
}

}  // namespace

IcpTarget2D::IcpTarget2D() = default;
IcpTarget2D::IcpTarget2D(IcpTarget2D&&) noexcept = default;
IcpTarget2D& IcpTarget2D::operator=(IcpTarget2D&&) noexcept = default;
IcpTarget2D::~IcpTarget2D() = default;

IcpTarget2D::IcpTarget2D(std::vector<Eigen::Vector2d> points, const IcpTarget2DOptions& options)
    : points_(finite_only(std::move(points), options.arithmetic)), options_(options) {
  ROVE_CHECK_MSG(options.normal_neighbors == 0 || options.normal_neighbors >= 3,
                 "normal_neighbors must be 0 or >= 3, got {}", options.normal_neighbors);
  ROVE_CHECK_MSG(options.occupied_below_free_probability > 0.0f &&
                     options.occupied_below_free_probability <= 1.0f,
                 "occupied_below_free_probability must be in (0, 1], got {}",
                 options.occupied_below_free_probability);
  if (options.arithmetic == Arithmetic::Mrpt) {
    std::vector<Eigen::Vector2f> as_float(points_.size());
    for (std::size_t i = 0; i < points_.size(); ++i) as_float[i] = points_[i].cast<float>();
    mrpt_tree_ = KdTree2f(std::move(as_float));
  } else {
    tree_ = KdTree2d(points_);
  }
  if (options.normal_neighbors > 0 && !points_.empty()) {
    normals_ = with_tree([&](const auto& tree) {
      return estimate_normals_2d(points_, tree, options.normal_neighbors);
    });
  }
}

template <GridCell Cell>
IcpTarget2D IcpTarget2D::from_grid(const OccupancyGridT<Cell>& grid,
                                   const IcpTarget2DOptions& options) {
  std::vector<Eigen::Vector2d> pts;
  for (std::uint32_t cy = 0; cy < grid.size_y(); ++cy)
    for (std::uint32_t cx = 0; cx < grid.size_x(); ++cx)
      if (grid.free_probability(static_cast<int>(cx), static_cast<int>(cy)) <
          options.occupied_below_free_probability)
        pts.emplace_back(grid.idx_to_x(cx), grid.idx_to_y(cy));
  return IcpTarget2D(std::move(pts), options);
}

template IcpTarget2D IcpTarget2D::from_grid(const OccupancyGridT<std::int8_t>&,
                                            const IcpTarget2DOptions&);
template IcpTarget2D IcpTarget2D::from_grid(const OccupancyGridT<std::int16_t>&,
                                            const IcpTarget2DOptions&);

namespace {

/// The PCA normal at p over its k nearest points of `tree` (nn: scratch of
/// at least k entries); (0, 0) when they have no extent.
template <typename Scalar>
Eigen::Vector2d pca_normal(const KdTree<2, Scalar>& tree, const Eigen::Vector2d& p, std::size_t k,
                           std::vector<Neighbor<Scalar>>& nn) {
  const std::size_t m = tree.knn(p.template cast<Scalar>(), k, nn);
  if (m < 2) return Eigen::Vector2d::Zero();
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::size_t j = 0; j < m; ++j) mean += tree.indexed_point(nn[j].index).template cast<double>();
  mean /= static_cast<double>(m);
  Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
  for (std::size_t j = 0; j < m; ++j) {
    const Eigen::Vector2d d = tree.indexed_point(nn[j].index).template cast<double>() - mean;
    C += d * d.transpose();
  }
  if (C.trace() <= 0.0) return Eigen::Vector2d::Zero();
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(C).eigenvectors().col(0).normalized();
}

}  // namespace

Eigen::Vector2d IcpTarget2D::normal_at(std::uint32_t i, std::size_t k) const {
  ROVE_CHECK_LT(i, points_.size());
  ROVE_CHECK_GE(k, std::size_t{2});
  if (has_normals()) return normals_[i];
  return with_tree([&](const auto& tree) {
    std::vector<typename std::decay_t<decltype(tree)>::Result> nn(k);
    return pca_normal(tree, points_[i], k, nn);
  });
}

template <typename Scalar>
std::vector<Eigen::Vector2d> estimate_normals_2d(std::span<const Eigen::Vector2d> points,
                                                 const KdTree<2, Scalar>& tree, std::size_t k,
                                                 int num_threads) {
  ROVE_CHECK_GE(k, std::size_t{2});
  std::vector<Eigen::Vector2d> normals(points.size(), Eigen::Vector2d::Zero());
  parallel_reduce(points.size(), resolve_thread_count(num_threads, "num_threads"), 0,
                  [&](std::size_t b, std::size_t e, int&) {
    std::vector<Neighbor<Scalar>> nn(k);
    for (std::size_t i = b; i < e; ++i) normals[i] = pca_normal(tree, points[i], k, nn);
  });
  return normals;
}

template std::vector<Eigen::Vector2d> estimate_normals_2d(std::span<const Eigen::Vector2d>,
                                                          const KdTree<2, float>&, std::size_t, int);
template std::vector<Eigen::Vector2d> estimate_normals_2d(std::span<const Eigen::Vector2d>,
                                                          const KdTree<2, double>&, std::size_t,
                                                          int);

}  // namespace rove
