#pragma once
/// \file
/// The least-squares rotation, translation and (optionally) scale that map
/// one set of corresponding points onto another: Umeyama, "Least-squares
/// estimation of transformation parameters between two point patterns",
/// IEEE PAMI 13(4), 1991 (Eqs. 38–42). Used to align trajectories and
/// graphs to ground truth before comparing them.

#include <cstddef>
#include <span>

#include <Eigen/Core>

namespace rove {

/// to ≈ scale·R·from + t, the minimizer of Σ‖to_k − (scale·R·from_k + t)‖².
template <int N>
struct PointSetAlignment {
  Eigen::Matrix<double, N, N> R = Eigen::Matrix<double, N, N>::Identity();  ///< det +1
  Eigen::Matrix<double, N, 1> t = Eigen::Matrix<double, N, 1>::Zero();
  double scale = 1.0;  ///< 1 unless estimated
  double rmse = 0.0;   ///< root mean square residual after alignment
  /// True when the points of `from` lie on a line (or a point), so that a
  /// rotation about that line is not determined: R is one of the minimizers.
  bool degenerate = false;
};

/// Aligns `from` onto `to` (same size, paired by index). With `with_scale`
/// the scale is estimated too (Sim(N)), else it is 1 (SE(N)).
/// Throws InvalidArgument if the sizes differ, the sets are empty, a
/// coordinate is not finite, or `with_scale` is asked for points of `from`
/// that all coincide.
template <int N>
PointSetAlignment<N> align_point_sets(std::span<const Eigen::Matrix<double, N, 1>> from,
                                      std::span<const Eigen::Matrix<double, N, 1>> to,
                                      bool with_scale = false);

extern template PointSetAlignment<2> align_point_sets<2>(std::span<const Eigen::Vector2d>,
                                                         std::span<const Eigen::Vector2d>, bool);
extern template PointSetAlignment<3> align_point_sets<3>(std::span<const Eigen::Vector3d>,
                                                         std::span<const Eigen::Vector3d>, bool);

}  // namespace rove
