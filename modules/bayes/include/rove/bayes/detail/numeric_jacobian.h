#pragma once
/// \file
/// Central-difference Jacobians for rove/bayes/kalman.h; include that header.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace rove {
struct KalmanOptions;
namespace detail {

/// The step of component j for a central difference at x_j.
double numeric_jacobian_step(double x_j, const KalmanOptions& options);

/// J(:, j) = diff(x + hⱼ eⱼ, x − hⱼ eⱼ) / (2 hⱼ), where diff(a, b) is the
/// model's output at a minus (⊖) its output at b.
template <typename Diff>
Eigen::MatrixXd numeric_jacobian(const Eigen::VectorXd& x, const KalmanOptions& options,
                                 Diff&& diff) {
  Eigen::MatrixXd J;
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    const double h = numeric_jacobian_step(x[j], options);
    Eigen::VectorXd plus = x, minus = x;
    plus[j] += h;
    minus[j] -= h;
    const Eigen::VectorXd column = diff(plus, minus) / (2.0 * h);
    if (j == 0) J.resize(column.size(), x.size());
    J.col(j) = column;
  }
  return J;
}

}  // namespace detail
}  // namespace rove
