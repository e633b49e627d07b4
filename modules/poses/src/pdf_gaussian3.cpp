#include "rove/poses/pdf_gaussian3.h"

#include <cmath>

#include "rove/poses/angle.h"
#include "rove/poses/pdf_covariance.h"
#include "rove/poses/pdf_jacobians.h"

namespace rove {
namespace {

using Matrix = Pose3Gaussian::Matrix;
using Vector = Pose3Gaussian::Vector;

Matrix propagate(const Matrix& J, const Matrix& C) {
  const Matrix r = J * C * J.transpose();
  return 0.5 * (r + r.transpose());
}

Pose3 add_to_mean(const Pose3& mean, const Vector& v) {
  const YawPitchRoll a = mean.yaw_pitch_roll();
  return Pose3(mean.x() + v[0], mean.y() + v[1], mean.z() + v[2], a.yaw + v[3], a.pitch + v[4],
               a.roll + v[5]);
}

}  // namespace

Pose3Gaussian::Pose3Gaussian(const Pose3& mean) : mean_(mean), cov_(Matrix::Zero()) {}

Pose3Gaussian::Pose3Gaussian(const Pose3& mean, const Matrix& covariance) : mean_(mean) {
  check_covariance(covariance, "Pose3Gaussian covariance");
  cov_ = 0.5 * (covariance + covariance.transpose());
}

Vector Pose3Gaussian::difference(const Pose3& p) const {
  const YawPitchRoll a = p.yaw_pitch_roll(), m = mean_.yaw_pitch_roll();
  Vector d;
  d << p.translation() - mean_.translation(), wrap_to_pi(a.yaw - m.yaw),
      wrap_to_pi(a.pitch - m.pitch), wrap_to_pi(a.roll - m.roll);
  return d;
}

double Pose3Gaussian::mahalanobis_distance(const Pose3& p) const {
  return rove::mahalanobis_distance(difference(p), cov_);
}

double Pose3Gaussian::mahalanobis_distance(const Pose3Gaussian& other) const {
  return rove::mahalanobis_distance(difference(other.mean_), Matrix(cov_ + other.cov_));
}

double Pose3Gaussian::log_likelihood(const Pose3& p) const {
  return gaussian_log_density(difference(p), cov_);
}

double Pose3Gaussian::likelihood(const Pose3& p) const { return std::exp(log_likelihood(p)); }

Pose3 Pose3Gaussian::sample(std::mt19937_64& rng) const {
  const Matrix S = psd_sqrt(cov_);
  return add_to_mean(mean_, S * standard_normal_vector(rng, 6));
}

std::vector<Pose3> Pose3Gaussian::sample(std::mt19937_64& rng, std::size_t n) const {
  const Matrix S = psd_sqrt(cov_);
  std::vector<Pose3> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(add_to_mean(mean_, S * standard_normal_vector(rng, 6)));
  return out;
}

Pose3Gaussian compose(const Pose3Gaussian& a, const Pose3Gaussian& b) {
  const PairJacobians<6> J = jacobians_compose(a.mean(), b.mean());
  return {detail::kUnchecked, a.mean() + b.mean(),
          Matrix(propagate(J.d_a, a.covariance()) + propagate(J.d_b, b.covariance()))};
}

Pose3Gaussian compose(const Pose3& a, const Pose3Gaussian& b) {
  const PairJacobians<6> J = jacobians_compose(a, b.mean());
  return {detail::kUnchecked, a + b.mean(), propagate(J.d_b, b.covariance())};
}

Pose3Gaussian compose(const Pose3Gaussian& a, const Pose3& b) {
  const PairJacobians<6> J = jacobians_compose(a.mean(), b);
  return {detail::kUnchecked, a.mean() + b, propagate(J.d_a, a.covariance())};
}

Pose3Gaussian inverse_compose(const Pose3Gaussian& a, const Pose3Gaussian& b) {
  const PairJacobians<6> J = jacobians_inverse_compose(a.mean(), b.mean());
  return {detail::kUnchecked, a.mean() - b.mean(),
          Matrix(propagate(J.d_a, a.covariance()) + propagate(J.d_b, b.covariance()))};
}

Pose3Gaussian inverse_compose(const Pose3Gaussian& a, const Pose3& b) {
  const PairJacobians<6> J = jacobians_inverse_compose(a.mean(), b);
  return {detail::kUnchecked, a.mean() - b, propagate(J.d_a, a.covariance())};
}

Pose3Gaussian inverse_compose(const Pose3& a, const Pose3Gaussian& b) {
  const PairJacobians<6> J = jacobians_inverse_compose(a, b.mean());
  return {detail::kUnchecked, a - b.mean(), propagate(J.d_b, b.covariance())};
}

Pose3Gaussian inverse(const Pose3Gaussian& a) {
  return {detail::kUnchecked, a.mean().inverse(),
          propagate(jacobian_inverse(a.mean()), a.covariance())};
}

Pose3Gaussian operator+(const Pose3Gaussian& a, const Pose3Gaussian& b) { return compose(a, b); }
Pose3Gaussian operator+(const Pose3& a, const Pose3Gaussian& b) { return compose(a, b); }
Pose3Gaussian operator+(const Pose3Gaussian& a, const Pose3& b) { return compose(a, b); }
Pose3Gaussian operator-(const Pose3Gaussian& a, const Pose3Gaussian& b) {
  return inverse_compose(a, b);
}
Pose3Gaussian operator-(const Pose3Gaussian& a, const Pose3& b) { return inverse_compose(a, b); }
Pose3Gaussian operator-(const Pose3& a, const Pose3Gaussian& b) { return inverse_compose(a, b); }
Pose3Gaussian operator-(const Pose3Gaussian& a) { return inverse(a); }

Pose3Gaussian to_3d(const Pose2Gaussian& p) {
  // Indices of (x, y, phi) in (x, y, z, yaw, pitch, roll).
  constexpr int kMap[3] = {0, 1, 3};
  Matrix C = Matrix::Zero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(kMap[i], kMap[j]) = p.covariance()(i, j);
  return {detail::kUnchecked, Pose3(p.mean()), C};
}

Pose2Gaussian to_2d(const Pose3Gaussian& p) {
  constexpr int kMap[3] = {0, 1, 3};
  Pose2Gaussian::Matrix C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(i, j) = p.covariance()(kMap[i], kMap[j]);
  return {detail::kUnchecked, Pose2(p.mean()), C};
}

}  // namespace rove
