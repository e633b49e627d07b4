#include "rove/poses/pdf_covariance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "rove/core/check.h"

namespace rove {
namespace {

double scale_of(const Eigen::Ref<const Eigen::MatrixXd>& m) {
  return m.size() == 0 ? 0.0 : m.cwiseAbs().maxCoeff();
}

}  // namespace

void check_covariance(const Eigen::Ref<const Eigen::MatrixXd>& m, std::string_view what) {
  ROVE_CHECK_MSG(m.rows() == m.cols(), "{} must be square, got {}x{}", what, m.rows(), m.cols());
  ROVE_CHECK_MSG(m.allFinite(), "{} holds NaN or Inf", what);
  const double scale = scale_of(m);
  const double asym = (m - m.transpose()).cwiseAbs().maxCoeff();
  ROVE_CHECK_MSG(asym <= kCovarianceTolerance * scale,
                 "{} is not symmetric: max |m - mᵀ| = {} for max |m| = {}", what, asym, scale);
  if (scale == 0.0) return;
  const Eigen::MatrixXd sym = 0.5 * (m + m.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sym, Eigen::EigenvaluesOnly);
  const double min_eig = es.eigenvalues().minCoeff();
  ROVE_CHECK_MSG(min_eig >= -kCovarianceTolerance * scale,
                 "{} is not positive semi-definite: smallest eigenvalue {} for max |m| = {}", what,
                 min_eig, scale);
}

bool is_positive_definite(const Eigen::Ref<const Eigen::MatrixXd>& m) {
  if (m.rows() != m.cols() || m.rows() == 0 || !m.allFinite()) return false;
  Eigen::LLT<Eigen::MatrixXd> llt(m);
  if (llt.info() != Eigen::Success) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m, Eigen::EigenvaluesOnly);
  const auto& ev = es.eigenvalues();
  return ev.minCoeff() > kCovarianceTolerance * ev.maxCoeff();
}

Eigen::MatrixXd spd_inverse(const Eigen::Ref<const Eigen::MatrixXd>& m, std::string_view what) {
  ROVE_CHECK_MSG(is_positive_definite(m), "{} must be positive definite to be inverted", what);
  Eigen::LLT<Eigen::MatrixXd> llt(m);
  Eigen::MatrixXd inv = llt.solve(Eigen::MatrixXd::Identity(m.rows(), m.cols()));
  return 0.5 * (inv + inv.transpose());
}

Eigen::MatrixXd psd_sqrt(const Eigen::Ref<const Eigen::MatrixXd>& m) {
  ROVE_CHECK_EQ(m.rows(), m.cols());
  const Eigen::MatrixXd sym = 0.5 * (m + m.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sym);
  ROVE_CHECK_MSG(es.info() == Eigen::Success, "eigen-decomposition failed");
  const Eigen::VectorXd sqrt_ev = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return es.eigenvectors() * sqrt_ev.asDiagonal();
}

Eigen::VectorXd standard_normal_vector(std::mt19937_64& rng, Eigen::Index n) {
  ROVE_CHECK_GE(n, 0);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd z(n);
  for (Eigen::Index i = 0; i < n; ++i) z[i] = normal(rng);
  return z;
}

double mahalanobis_distance(const Eigen::Ref<const Eigen::VectorXd>& d,
                            const Eigen::Ref<const Eigen::MatrixXd>& cov) {
  ROVE_CHECK_EQ(cov.rows(), cov.cols());
  ROVE_CHECK_EQ(d.size(), cov.rows());
  ROVE_CHECK_FINITE(d);
  if (d.isZero(0.0)) return 0.0;
  const Eigen::MatrixXd sym = 0.5 * (cov + cov.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sym);
  ROVE_CHECK_MSG(es.info() == Eigen::Success, "eigen-decomposition failed");
  const Eigen::VectorXd& ev = es.eigenvalues();
  const double ev_tol = kCovarianceTolerance * std::max(ev.cwiseAbs().maxCoeff(), 0.0);
  const Eigen::VectorXd proj = es.eigenvectors().transpose() * d;
  const double d_norm = d.norm();
  double sum = 0.0;
  for (Eigen::Index i = 0; i < ev.size(); ++i) {
    if (ev[i] <= ev_tol) {
      if (std::abs(proj[i]) > kCovarianceTolerance * d_norm)
        return std::numeric_limits<double>::infinity();
      continue;
    }
    sum += proj[i] * proj[i] / ev[i];
  }
  return std::sqrt(sum);
}

double gaussian_log_density(const Eigen::Ref<const Eigen::VectorXd>& d,
                            const Eigen::Ref<const Eigen::MatrixXd>& cov) {
  ROVE_CHECK_EQ(d.size(), cov.rows());
  ROVE_CHECK_MSG(is_positive_definite(cov),
                 "the covariance must be positive definite to evaluate a density");
  Eigen::LLT<Eigen::MatrixXd> llt(cov);
  const Eigen::VectorXd y = llt.matrixL().solve(d);
  const double log_det = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
  const double n = static_cast<double>(d.size());
  return -0.5 * (y.squaredNorm() + log_det + n * std::log(2.0 * std::numbers::pi));
}

double gaussian_log_density_information(const Eigen::Ref<const Eigen::VectorXd>& d,
                                        const Eigen::Ref<const Eigen::MatrixXd>& information) {
  ROVE_CHECK_EQ(d.size(), information.rows());
  ROVE_CHECK_MSG(is_positive_definite(information),
                 "the information matrix must be positive definite to evaluate a density");
  Eigen::LLT<Eigen::MatrixXd> llt(information);
  const double log_det = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
  const double n = static_cast<double>(d.size());
  return -0.5 * (d.dot(information * d) - log_det + n * std::log(2.0 * std::numbers::pi));
}

}  // namespace rove
