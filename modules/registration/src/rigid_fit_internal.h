#pragma once
// The closed-form rigid fits shared by fit_rigid_2d/3d and the ICP loops,
// over pairs given by accessors (so that ICP fits its pairs in place).

#include <cmath>
#include <cstddef>

#include <Eigen/Core>

#include "rove/poses/pose2.h"

namespace rove::detail {

/// Weighted centroids of the n pairs (source(k), target(k), weight(k)); pairs
/// with a weight ≤ 0 are left out. `weight_sum` 0 means no pair counted.
template <int D>
struct WeightedCentroids {
  Eigen::Matrix<double, D, 1> source = Eigen::Matrix<double, D, 1>::Zero();
  Eigen::Matrix<double, D, 1> target = Eigen::Matrix<double, D, 1>::Zero();
  double weight_sum = 0;
  std::size_t pairs = 0;
};

template <int D, class Src, class Tgt, class W>
WeightedCentroids<D> weighted_centroids(std::size_t n, const Src& source, const Tgt& target,
                                        const W& weight) {
  WeightedCentroids<D> c;
  for (std::size_t k = 0; k < n; ++k) {
    const double w = weight(k);
    if (w <= 0.0) continue;
    ++c.pairs;
    c.weight_sum += w;
    c.source += w * source(k);
    c.target += w * target(k);
  }
  if (c.weight_sum > 0) {
    c.source /= c.weight_sum;
    c.target /= c.weight_sum;
  }
  return c;
}

/// The 2D rigid motion T minimizing Σ wₖ ‖T·sₖ − tₖ‖² (Lu & Milios, "Robot
/// pose estimation in unknown environments by matching 2D range scans",
/// 1997, eq. 12-13): centroids, then φ = atan2(Σ w (s̄ₓt̄ᵧ − s̄ᵧt̄ₓ),
/// Σ w (s̄ₓt̄ₓ + s̄ᵧt̄ᵧ)) on the centered points; `c` are the pairs'
/// weighted_centroids. Precondition: c.weight_sum > 0.
template <class Src, class Tgt, class W>
Pose2 centered_rigid_fit_2d(std::size_t n, const Src& source, const Tgt& target, const W& weight,
                            const WeightedCentroids<2>& c) {
  double s_dot = 0, s_cross = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double w = weight(k);
    if (w <= 0.0) continue;
    const Eigen::Vector2d a = source(k) - c.source, b = target(k) - c.target;
    s_dot += w * (a.x() * b.x() + a.y() * b.y());
    s_cross += w * (a.x() * b.y() - a.y() * b.x());
  }
  const double phi = std::atan2(s_cross, s_dot);
  const double cs = std::cos(phi), sn = std::sin(phi);
  const Eigen::Vector2d t =
      c.target - Eigen::Vector2d(cs * c.source.x() - sn * c.source.y(),
                                 sn * c.source.x() + cs * c.source.y());
  return Pose2(t.x(), t.y(), phi);
}

}  // namespace rove::detail
