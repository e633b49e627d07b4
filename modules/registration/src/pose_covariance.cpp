#include "rove/registration/pose_covariance.h"

#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "rove/core/check.h"
#include "rove/registration/rigid_transform.h"

namespace rove {

template <int N>
Eigen::Matrix<double, N, N> covariance_from_information(const Eigen::Matrix<double, N, N>& H,
                                                        double scale, double relative_floor,
                                                        int* unconstrained) {
  ROVE_CHECK_FINITE(H);
  ROVE_CHECK_GT(scale, 0.0);
  ROVE_CHECK_MSG(relative_floor > 0.0 && relative_floor < 1.0,
                 "relative_floor must be in (0, 1), got {}", relative_floor);
  const Eigen::Matrix<double, N, N> Hs = 0.5 * (H + H.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(Hs);
  const auto& lambda = eig.eigenvalues();
  const double lambda_max = std::max(lambda.maxCoeff(), 0.0);
  Eigen::Matrix<double, N, N> C = Eigen::Matrix<double, N, N>::Zero();
  int n_free = 0;
  for (int i = 0; i < N; ++i) {
    const auto v = eig.eigenvectors().col(i);
    if (lambda_max <= 0.0 || lambda(i) <= relative_floor * lambda_max) {
      C += kUnconstrainedVariance * v * v.transpose();
      ++n_free;
    } else {
      C += (scale / lambda(i)) * v * v.transpose();
    }
  }
  if (unconstrained) *unconstrained = n_free;
  return 0.5 * (C + C.transpose());
}

template Eigen::Matrix<double, 3, 3> covariance_from_information<3>(const Eigen::Matrix3d&, double,
                                                                    double, int*);
template Eigen::Matrix<double, 6, 6> covariance_from_information<6>(
    const Eigen::Matrix<double, 6, 6>&, double, double, int*);

}  // namespace rove
