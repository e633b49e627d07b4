#include "rove/registration/icp_target_2d.h"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "rove/core/check.h"
#include "rove/core/parallel.h"

namespace rove {
namespace {

std::vector<Eigen::Vector2d> finite_only(std::vector<Eigen::Vector2d> pts) {
  // Float values; a non-finite point, or one out of float's range (it
  // becomes infinite), is dropped.
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
    : points_(finite_only(std::move(points))), options_(options) {
  ROVE_CHECK_MSG(options.normal_neighbors == 0 || options.normal_neighbors >= 3,
                 "normal_neighbors must be 0 or >= 3, got {}", options.normal_neighbors);
  ROVE_CHECK_MSG(options.occupied_below_free_probability > 0.0f &&
                     options.occupied_below_free_probability <= 1.0f,
                 "occupied_below_free_probability must be in (0, 1], got {}",
                 options.occupied_below_free_probability);
  std::vector<Eigen::Vector2f> as_float(points_.size());
  for (std::size_t i = 0; i < points_.size(); ++i) as_float[i] = points_[i].cast<float>();
  tree_ = KdTree2f(std::move(as_float));
  if (options.normal_neighbors > 0 && !points_.empty())
    normals_ = estimate_normals_2d(points_, tree_, options.normal_neighbors);
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

std::vector<Eigen::Vector2d> estimate_normals_2d(std::span<const Eigen::Vector2d> points,
                                                 const KdTree2f& tree, std::size_t k,
                                                 int num_threads) {
  ROVE_CHECK_GE(k, std::size_t{2});
  std::vector<Eigen::Vector2d> normals(points.size(), Eigen::Vector2d::Zero());
  parallel_reduce(points.size(), resolve_thread_count(num_threads, "num_threads"), 0,
                          [&](std::size_t b, std::size_t e, int&) {
    std::vector<Neighbor<float>> nn(k);
    for (std::size_t i = b; i < e; ++i) {
      const std::size_t m = tree.knn(points[i].cast<float>(), k, nn);
      if (m < 2) continue;
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for (std::size_t j = 0; j < m; ++j) mean += tree.indexed_point(nn[j].index).cast<double>();
      mean /= static_cast<double>(m);
      Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
      for (std::size_t j = 0; j < m; ++j) {
        const Eigen::Vector2d d = tree.indexed_point(nn[j].index).cast<double>() - mean;
        C += d * d.transpose();
      }
      if (C.trace() <= 0.0) continue;
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(C);
      normals[i] = eig.eigenvectors().col(0).normalized();
    }
  });
  return normals;
}

}  // namespace rove
