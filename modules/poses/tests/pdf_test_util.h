#pragma once
// Helpers for the pose-PDF tests: central numeric differentiation, sample
// covariances and random SPD matrices.

#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "rove/poses/angle.h"

namespace rove::pdf_test {

// Central differences of f at x, step h; output components listed in
// `wrapped` are angles whose differences are wrapped to (−π, π].
inline Eigen::MatrixXd numeric_jacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
    const std::vector<int>& wrapped = {}, double h = 1e-6) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (Eigen::Index j = 0; j < x.size(); ++j) {
    Eigen::VectorXd xp = x, xm = x;
    xp[j] += h;
    xm[j] -= h;
    Eigen::VectorXd d = f(xp) - f(xm);
    for (int w : wrapped) d[w] = wrap_to_pi(d[w]);
    J.col(j) = d / (2 * h);
  }
  return J;
}

// A random symmetric positive-definite n×n matrix with the given standard
// deviations on the diagonal and correlations up to ±0.5.
inline Eigen::MatrixXd random_covariance(std::mt19937_64& rng, const Eigen::VectorXd& sigmas) {
  const Eigen::Index n = sigmas.size();
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  Eigen::MatrixXd corr = Eigen::MatrixXd::Identity(n, n);
  // A correlation matrix from a random factor, normalized to unit diagonal.
  Eigen::MatrixXd A(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) A(i, j) = u(rng);
  corr = A * A.transpose() + Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd d = corr.diagonal().cwiseSqrt().cwiseInverse();
  corr = d.asDiagonal() * corr * d.asDiagonal();
  return sigmas.asDiagonal() * corr * sigmas.asDiagonal();
}

// Weighted-equal sample covariance of the rows' differences `d` (already
// centered on the reference value): mean of d·dᵀ minus mean·meanᵀ.
inline Eigen::MatrixXd sample_covariance(const std::vector<Eigen::VectorXd>& d) {
  const Eigen::Index n = d.front().size();
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(n, n);
  for (const auto& v : d) {
    mean += v;
    S += v * v.transpose();
  }
  const double N = static_cast<double>(d.size());
  mean /= N;
  return S / N - mean * mean.transpose();
}

// Max over entries of |A − B| / sqrt(B_ii·B_jj): covariance error in units of
// the standard deviations.
inline double normalized_cov_error(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  double worst = 0.0;
  for (Eigen::Index i = 0; i < A.rows(); ++i)
    for (Eigen::Index j = 0; j < A.cols(); ++j) {
      const double s = std::sqrt(B(i, i) * B(j, j));
      worst = std::max(worst, std::abs(A(i, j) - B(i, j)) / s);
    }
  return worst;
}

}  // namespace rove::pdf_test
