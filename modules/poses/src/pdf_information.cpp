#include "rove/poses/pdf_information.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/poses/pdf_covariance.h"
#include "rove/poses/pdf_jacobians.h"

namespace rove {
namespace {

// Λ' = J⁻ᵀ·Λ·J⁻¹ for an invertible J; throws NumericError if J is singular
// (Euler-angle Jacobians at gimbal lock).
template <int N>
Eigen::Matrix<double, N, N> transform_information(const Eigen::Matrix<double, N, N>& J,
                                                  const Eigen::Matrix<double, N, N>& info) {
  const Eigen::FullPivLU<Eigen::Matrix<double, N, N>> lu(J);
  if (!lu.isInvertible())
    throw NumericError("information transform: the Jacobian is singular (gimbal lock?)");
  const Eigen::Matrix<double, N, N> Jinv = lu.inverse();
  const Eigen::Matrix<double, N, N> r = Jinv.transpose() * info * Jinv;
  return 0.5 * (r + r.transpose());
}

// mean + L⁻ᵀ·z with Λ = L·Lᵀ: a draw from N(mean, Λ⁻¹).
template <int N>
Eigen::Matrix<double, N, 1> information_draw(const Eigen::LLT<Eigen::Matrix<double, N, N>>& llt,
                                             std::mt19937_64& rng) {
  const Eigen::Matrix<double, N, 1> z = standard_normal_vector(rng, N);
  return llt.matrixU().solve(z);
}

template <int N>
Eigen::LLT<Eigen::Matrix<double, N, N>> information_factor(const Eigen::Matrix<double, N, N>& info) {
  ROVE_CHECK_MSG(is_positive_definite(info),
                 "sampling needs a positive-definite information matrix");
  return Eigen::LLT<Eigen::Matrix<double, N, N>>(info);
}

Pose2 add2(const Pose2& m, const Eigen::Vector3d& v) {
  return Pose2(m.x() + v[0], m.y() + v[1], m.phi() + v[2]);
}

Pose3 add3(const Pose3& m, const Eigen::Matrix<double, 6, 1>& v) {
  const YawPitchRoll a = m.yaw_pitch_roll();
  return Pose3(m.x() + v[0], m.y() + v[1], m.z() + v[2], a.yaw + v[3], a.pitch + v[4],
               a.roll + v[5]);
}

}  // namespace

// ---- Pose2GaussianInf -------------------------------------------------------

Pose2GaussianInf::Pose2GaussianInf(const Pose2& mean, const Matrix& information) : mean_(mean) {
  check_covariance(information, "Pose2GaussianInf information");
  info_ = 0.5 * (information + information.transpose());
}

double Pose2GaussianInf::mahalanobis_distance(const Pose2& p) const {
  const Eigen::Vector3d d = Pose2Gaussian(mean_).difference(p);
  return std::sqrt(std::max(0.0, d.dot(info_ * d)));
}

double Pose2GaussianInf::log_likelihood(const Pose2& p) const {
  return gaussian_log_density_information(Pose2Gaussian(mean_).difference(p), info_);
}

double Pose2GaussianInf::likelihood(const Pose2& p) const { return std::exp(log_likelihood(p)); }

Pose2 Pose2GaussianInf::sample(std::mt19937_64& rng) const {
  return add2(mean_, information_draw<3>(information_factor<3>(info_), rng));
}

std::vector<Pose2> Pose2GaussianInf::sample(std::mt19937_64& rng, std::size_t n) const {
  const auto llt = information_factor<3>(info_);
  std::vector<Pose2> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(add2(mean_, information_draw<3>(llt, rng)));
  return out;
}

// ---- Pose3GaussianInf -------------------------------------------------------

Pose3GaussianInf::Pose3GaussianInf(const Pose3& mean, const Matrix& information) : mean_(mean) {
  check_covariance(information, "Pose3GaussianInf information");
  info_ = 0.5 * (information + information.transpose());
}

double Pose3GaussianInf::mahalanobis_distance(const Pose3& p) const {
  const Pose3Gaussian::Vector d = Pose3Gaussian(mean_).difference(p);
  return std::sqrt(std::max(0.0, d.dot(info_ * d)));
}

double Pose3GaussianInf::log_likelihood(const Pose3& p) const {
  return gaussian_log_density_information(Pose3Gaussian(mean_).difference(p), info_);
}

double Pose3GaussianInf::likelihood(const Pose3& p) const { return std::exp(log_likelihood(p)); }

Pose3 Pose3GaussianInf::sample(std::mt19937_64& rng) const {
  return add3(mean_, information_draw<6>(information_factor<6>(info_), rng));
}

std::vector<Pose3> Pose3GaussianInf::sample(std::mt19937_64& rng, std::size_t n) const {
  const auto llt = information_factor<6>(info_);
  std::vector<Pose3> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) out.push_back(add3(mean_, information_draw<6>(llt, rng)));
  return out;
}

// ---- Conversions ------------------------------------------------------------

Pose2GaussianInf to_information(const Pose2Gaussian& p) {
  return {detail::kUnchecked, p.mean(),
          Pose2GaussianInf::Matrix(spd_inverse(p.covariance(), "Pose2Gaussian covariance"))};
}

Pose3GaussianInf to_information(const Pose3Gaussian& p) {
  return {detail::kUnchecked, p.mean(),
          Pose3GaussianInf::Matrix(spd_inverse(p.covariance(), "Pose3Gaussian covariance"))};
}

Pose2Gaussian to_covariance(const Pose2GaussianInf& p) {
  return {detail::kUnchecked, p.mean(),
          Pose2Gaussian::Matrix(spd_inverse(p.information(), "Pose2GaussianInf information"))};
}

Pose3Gaussian to_covariance(const Pose3GaussianInf& p) {
  return {detail::kUnchecked, p.mean(),
          Pose3Gaussian::Matrix(spd_inverse(p.information(), "Pose3GaussianInf information"))};
}

// ---- 2D operations ------------------------------------------------------------

Pose2GaussianInf compose(const Pose2GaussianInf& a, const Pose2GaussianInf& b) {
  return to_information(compose(to_covariance(a), to_covariance(b)));
}

Pose2GaussianInf compose(const Pose2& a, const Pose2GaussianInf& b) {
  const PairJacobians<3> J = jacobians_compose(a, b.mean());
  return {detail::kUnchecked, a + b.mean(), transform_information<3>(J.d_b, b.information())};
}

Pose2GaussianInf compose(const Pose2GaussianInf& a, const Pose2& b) {
  const PairJacobians<3> J = jacobians_compose(a.mean(), b);
  return {detail::kUnchecked, a.mean() + b, transform_information<3>(J.d_a, a.information())};
}

Pose2GaussianInf inverse_compose(const Pose2GaussianInf& a, const Pose2GaussianInf& b) {
  return to_information(inverse_compose(to_covariance(a), to_covariance(b)));
}

Pose2GaussianInf inverse(const Pose2GaussianInf& a) {
  return {detail::kUnchecked, -a.mean(),
          transform_information<3>(jacobian_inverse(a.mean()), a.information())};
}

// ---- 3D operations ------------------------------------------------------------

Pose3GaussianInf compose(const Pose3GaussianInf& a, const Pose3GaussianInf& b) {
  return to_information(compose(to_covariance(a), to_covariance(b)));
}

Pose3GaussianInf compose(const Pose3& a, const Pose3GaussianInf& b) {
  const PairJacobians<6> J = jacobians_compose(a, b.mean());
  return {detail::kUnchecked, a + b.mean(), transform_information<6>(J.d_b, b.information())};
}

Pose3GaussianInf compose(const Pose3GaussianInf& a, const Pose3& b) {
  const PairJacobians<6> J = jacobians_compose(a.mean(), b);
  return {detail::kUnchecked, a.mean() + b, transform_information<6>(J.d_a, a.information())};
}

Pose3GaussianInf inverse_compose(const Pose3GaussianInf& a, const Pose3GaussianInf& b) {
  return to_information(inverse_compose(to_covariance(a), to_covariance(b)));
}

Pose3GaussianInf inverse(const Pose3GaussianInf& a) {
  return {detail::kUnchecked, a.mean().inverse(),
          transform_information<6>(jacobian_inverse(a.mean()), a.information())};
}

Pose2GaussianInf operator+(const Pose2GaussianInf& a, const Pose2GaussianInf& b) {
  return compose(a, b);
}
Pose2GaussianInf operator+(const Pose2& a, const Pose2GaussianInf& b) { return compose(a, b); }
Pose2GaussianInf operator+(const Pose2GaussianInf& a, const Pose2& b) { return compose(a, b); }
Pose2GaussianInf operator-(const Pose2GaussianInf& a, const Pose2GaussianInf& b) {
  return inverse_compose(a, b);
}
Pose2GaussianInf operator-(const Pose2GaussianInf& a) { return inverse(a); }
Pose3GaussianInf operator+(const Pose3GaussianInf& a, const Pose3GaussianInf& b) {
  return compose(a, b);
}
Pose3GaussianInf operator+(const Pose3& a, const Pose3GaussianInf& b) { return compose(a, b); }
Pose3GaussianInf operator+(const Pose3GaussianInf& a, const Pose3& b) { return compose(a, b); }
Pose3GaussianInf operator-(const Pose3GaussianInf& a, const Pose3GaussianInf& b) {
  return inverse_compose(a, b);
}
Pose3GaussianInf operator-(const Pose3GaussianInf& a) { return inverse(a); }

}  // namespace rove
