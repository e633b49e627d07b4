#include "rove/poses/pdf_gaussian3_quat.h"

#include <cmath>

#include "rove/poses/pdf_covariance.h"
#include "rove/poses/pdf_euler_quat.h"
#include "rove/poses/pdf_jacobians.h"

namespace rove {
namespace {

using Matrix = Pose3QuatGaussian::Matrix;
using Vector = Pose3QuatGaussian::Vector;

Matrix propagate(const Matrix& J, const Matrix& C) {
  const Matrix r = J * C * J.transpose();
  return 0.5 * (r + r.transpose());
}

Pose3Quat add_to_mean(const Pose3Quat& mean, const Vector& v) {
  const Vector m = mean.to_vector() + v;
  return Pose3Quat(m[0], m[1], m[2], m[3], m[4], m[5], m[6]);
}

}  // namespace

Pose3QuatGaussian::Pose3QuatGaussian(const Pose3Quat& mean) : mean_(mean), cov_(Matrix::Zero()) {}

Pose3QuatGaussian::Pose3QuatGaussian(const Pose3Quat& mean, const Matrix& covariance)
    : mean_(mean) {
  check_covariance(covariance, "Pose3QuatGaussian covariance");
  cov_ = 0.5 * (covariance + covariance.transpose());
}

Vector Pose3QuatGaussian::difference(const Pose3Quat& p) const {
  Vector v = p.to_vector();
  const Vector m = mean_.to_vector();
  if (v.tail<4>().dot(m.tail<4>()) < 0.0) v.tail<4>() *= -1.0;
  return v - m;
}

double Pose3QuatGaussian::mahalanobis_distance(const Pose3Quat& p) const {
  return rove::mahalanobis_distance(difference(p), cov_);
}

double Pose3QuatGaussian::mahalanobis_distance(const Pose3QuatGaussian& other) const {
  return rove::mahalanobis_distance(difference(other.mean_), Matrix(cov_ + other.cov_));
}

double Pose3QuatGaussian::log_likelihood(const Pose3Quat& p) const {
  return gaussian_log_density(difference(p), cov_);
}

double Pose3QuatGaussian::likelihood(const Pose3Quat& p) const {
  return std::exp(log_likelihood(p));
}

Pose3Quat Pose3QuatGaussian::sample(std::mt19937_64& rng) const {
  const Matrix S = psd_sqrt(cov_);
  return add_to_mean(mean_, S * standard_normal_vector(rng, 7));
}

std::vector<Pose3Quat> Pose3QuatGaussian::sample(std::mt19937_64& rng, std::size_t n) const {
  const Matrix S = psd_sqrt(cov_);
  std::vector<Pose3Quat> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(add_to_mean(mean_, S * standard_normal_vector(rng, 7)));
  return out;
}

Pose3QuatGaussian compose(const Pose3QuatGaussian& a, const Pose3QuatGaussian& b) {
  const PairJacobians<7> J = jacobians_compose(a.mean(), b.mean());
  return {detail::kUnchecked, a.mean() + b.mean(),
          Matrix(propagate(J.d_a, a.covariance()) + propagate(J.d_b, b.covariance()))};
}

Pose3QuatGaussian compose(const Pose3Quat& a, const Pose3QuatGaussian& b) {
  const PairJacobians<7> J = jacobians_compose(a, b.mean());
  return {detail::kUnchecked, a + b.mean(), propagate(J.d_b, b.covariance())};
}

Pose3QuatGaussian compose(const Pose3QuatGaussian& a, const Pose3Quat& b) {
  const PairJacobians<7> J = jacobians_compose(a.mean(), b);
  return {detail::kUnchecked, a.mean() + b, propagate(J.d_a, a.covariance())};
}

Pose3QuatGaussian inverse_compose(const Pose3QuatGaussian& a, const Pose3QuatGaussian& b) {
  const PairJacobians<7> J = jacobians_inverse_compose(a.mean(), b.mean());
  return {detail::kUnchecked, a.mean() - b.mean(),
          Matrix(propagate(J.d_a, a.covariance()) + propagate(J.d_b, b.covariance()))};
}

Pose3QuatGaussian inverse_compose(const Pose3QuatGaussian& a, const Pose3Quat& b) {
  const PairJacobians<7> J = jacobians_inverse_compose(a.mean(), b);
  return {detail::kUnchecked, a.mean() - b, propagate(J.d_a, a.covariance())};
}

Pose3QuatGaussian inverse_compose(const Pose3Quat& a, const Pose3QuatGaussian& b) {
  const PairJacobians<7> J = jacobians_inverse_compose(a, b.mean());
  return {detail::kUnchecked, a - b.mean(), propagate(J.d_b, b.covariance())};
}

Pose3QuatGaussian inverse(const Pose3QuatGaussian& a) {
  return {detail::kUnchecked, a.mean().inverse(),
          propagate(jacobian_inverse(a.mean()), a.covariance())};
}

Pose3QuatGaussian operator+(const Pose3QuatGaussian& a, const Pose3QuatGaussian& b) {
  return compose(a, b);
}
Pose3QuatGaussian operator+(const Pose3Quat& a, const Pose3QuatGaussian& b) {
  return compose(a, b);
}
Pose3QuatGaussian operator+(const Pose3QuatGaussian& a, const Pose3Quat& b) {
  return compose(a, b);
}
Pose3QuatGaussian operator-(const Pose3QuatGaussian& a, const Pose3QuatGaussian& b) {
  return inverse_compose(a, b);
}
Pose3QuatGaussian operator-(const Pose3QuatGaussian& a, const Pose3Quat& b) {
  return inverse_compose(a, b);
}
Pose3QuatGaussian operator-(const Pose3Quat& a, const Pose3QuatGaussian& b) {
  return inverse_compose(a, b);
}
Pose3QuatGaussian operator-(const Pose3QuatGaussian& a) { return inverse(a); }

Pose3QuatGaussian to_quat_gaussian(const Pose3Gaussian& p) {
  const Eigen::Matrix<double, 7, 6> J = jacobian_pose3_to_quat(p.mean());
  const Matrix C = J * p.covariance() * J.transpose();
  return {detail::kUnchecked, Pose3Quat(p.mean()), Matrix(0.5 * (C + C.transpose()))};
}

Pose3QuatGaussian to_quat_gaussian(const Pose2Gaussian& p) { return to_quat_gaussian(to_3d(p)); }

Pose3Gaussian to_euler_gaussian(const Pose3QuatGaussian& q) {
  const Pose3Quat& m = q.mean();
  const Eigen::Vector4d qv(m.qw(), m.qx(), m.qy(), m.qz());
  const Eigen::Vector3d ypr = quat_to_ypr(qv);
  const Eigen::Matrix<double, 6, 7> J = jacobian_quat_to_pose3(m);
  const Pose3Gaussian::Matrix C = J * q.covariance() * J.transpose();
  return {detail::kUnchecked, Pose3(m.x(), m.y(), m.z(), ypr[0], ypr[1], ypr[2]),
          Pose3Gaussian::Matrix(0.5 * (C + C.transpose()))};
}

}  // namespace rove
