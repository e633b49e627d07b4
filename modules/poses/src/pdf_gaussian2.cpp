#include "rove/poses/pdf_gaussian2.h"

#include <cmath>

#include "rove/poses/angle.h"
#include "rove/poses/pdf_covariance.h"
#include "rove/poses/pdf_jacobians.h"

namespace rove {
namespace {

using Matrix = Pose2Gaussian::Matrix;

// J·C·Jᵀ, symmetrized against round-off.
Matrix propagate(const Matrix& J, const Matrix& C) {
  const Matrix r = J * C * J.transpose();
  return 0.5 * (r + r.transpose());
}

Pose2 add_to_mean(const Pose2& mean, const Eigen::Vector3d& v) {
  return Pose2(mean.x() + v[0], mean.y() + v[1], mean.phi() + v[2]);
}

}  // namespace

Pose2Gaussian::Pose2Gaussian(const Pose2& mean) : mean_(mean), cov_(Matrix::Zero()) {}

Pose2Gaussian::Pose2Gaussian(const Pose2& mean, const Matrix& covariance) : mean_(mean) {
  check_covariance(covariance, "Pose2Gaussian covariance");
  cov_ = 0.5 * (covariance + covariance.transpose());
}

Pose2Gaussian::Vector Pose2Gaussian::difference(const Pose2& p) const {
  return {p.x() - mean_.x(), p.y() - mean_.y(), wrap_to_pi(p.phi() - mean_.phi())};
}

double Pose2Gaussian::mahalanobis_distance(const Pose2& p) const {
  return rove::mahalanobis_distance(difference(p), cov_);
}

double Pose2Gaussian::mahalanobis_distance(const Pose2Gaussian& other) const {
  return rove::mahalanobis_distance(difference(other.mean_), Matrix(cov_ + other.cov_));
}

double Pose2Gaussian::log_likelihood(const Pose2& p) const {
  return gaussian_log_density(difference(p), cov_);
}

double Pose2Gaussian::likelihood(const Pose2& p) const { return std::exp(log_likelihood(p)); }

Pose2 Pose2Gaussian::sample(std::mt19937_64& rng) const {
  const Matrix S = psd_sqrt(cov_);
  return add_to_mean(mean_, S * standard_normal_vector(rng, 3));
}

std::vector<Pose2> Pose2Gaussian::sample(std::mt19937_64& rng, std::size_t n) const {
  const Matrix S = psd_sqrt(cov_);
  std::vector<Pose2> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(add_to_mean(mean_, S * standard_normal_vector(rng, 3)));
  return out;
}

Pose2Gaussian compose(const Pose2Gaussian& a, const Pose2Gaussian& b) {
  const PairJacobians<3> J = jacobians_compose(a.mean(), b.mean());
  return {detail::kUnchecked, a.mean() + b.mean(),
          Matrix(propagate(J.d_a, a.covariance()) + propagate(J.d_b, b.covariance()))};
}

Pose2Gaussian compose(const Pose2& a, const Pose2Gaussian& b) {
  const PairJacobians<3> J = jacobians_compose(a, b.mean());
  return {detail::kUnchecked, a + b.mean(), propagate(J.d_b, b.covariance())};
}

Pose2Gaussian compose(const Pose2Gaussian& a, const Pose2& b) {
  const PairJacobians<3> J = jacobians_compose(a.mean(), b);
  return {detail::kUnchecked, a.mean() + b, propagate(J.d_a, a.covariance())};
}

Pose2Gaussian inverse_compose(const Pose2Gaussian& a, const Pose2Gaussian& b) {
  const PairJacobians<3> J = jacobians_inverse_compose(a.mean(), b.mean());
  return {detail::kUnchecked, a.mean() - b.mean(),
          Matrix(propagate(J.d_a, a.covariance()) + propagate(J.d_b, b.covariance()))};
}

Pose2Gaussian inverse_compose(const Pose2Gaussian& a, const Pose2& b) {
  const PairJacobians<3> J = jacobians_inverse_compose(a.mean(), b);
  return {detail::kUnchecked, a.mean() - b, propagate(J.d_a, a.covariance())};
}

Pose2Gaussian inverse_compose(const Pose2& a, const Pose2Gaussian& b) {
  const PairJacobians<3> J = jacobians_inverse_compose(a, b.mean());
  return {detail::kUnchecked, a - b.mean(), propagate(J.d_b, b.covariance())};
}

Pose2Gaussian inverse(const Pose2Gaussian& a) {
  return {detail::kUnchecked, -a.mean(), propagate(jacobian_inverse(a.mean()), a.covariance())};
}

Pose2Gaussian operator+(const Pose2Gaussian& a, const Pose2Gaussian& b) { return compose(a, b); }
Pose2Gaussian operator+(const Pose2& a, const Pose2Gaussian& b) { return compose(a, b); }
Pose2Gaussian operator+(const Pose2Gaussian& a, const Pose2& b) { return compose(a, b); }
Pose2Gaussian operator-(const Pose2Gaussian& a, const Pose2Gaussian& b) {
  return inverse_compose(a, b);
}
Pose2Gaussian operator-(const Pose2Gaussian& a, const Pose2& b) { return inverse_compose(a, b); }
Pose2Gaussian operator-(const Pose2& a, const Pose2Gaussian& b) { return inverse_compose(a, b); }
Pose2Gaussian operator-(const Pose2Gaussian& a) { return inverse(a); }

}  // namespace rove
