#pragma once
/// \file
/// Pose3QuatGaussian: a 3D pose with Gaussian uncertainty in the quaternion
/// parameterization, mean + 7×7 covariance ordered (x, y, z, qw, qx, qy, qz)
/// (MRPT's CPose3DQuatPDFGaussian), and the conversions between it and
/// Pose3Gaussian through the conversion Jacobians. The covariance of a
/// quaternion Gaussian obtained from yaw-pitch-roll has rank ≤ 6: it has no
/// variance along the quaternion itself (the normalization direction).

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "rove/poses/pdf_gaussian3.h"
#include "rove/poses/pose3_quat.h"

namespace rove {

/// A Gaussian distribution over Pose3Quat: mean and covariance of
/// (x, y, z, qw, qx, qy, qz). A plain value; thread-compatible.
class Pose3QuatGaussian {
 public:
  /// Covariance type, ordered (x, y, z, qw, qx, qy, qz).
  using Matrix = Eigen::Matrix<double, 7, 7>;
  /// A difference vector of the 7 parameters.
  using Vector = Eigen::Matrix<double, 7, 1>;

  /// Identity mean, zero covariance.
  Pose3QuatGaussian() = default;
  /// A pose without uncertainty (zero covariance).
  explicit Pose3QuatGaussian(const Pose3Quat& mean);
  /// Mean and covariance. Throws InvalidArgument unless the covariance is
  /// finite, symmetric and positive semi-definite (check_covariance); it is
  /// stored symmetrized.
  Pose3QuatGaussian(const Pose3Quat& mean, const Matrix& covariance);

  /// Internal: no validation; `covariance` must already be symmetric PSD
  /// (results of propagation).
  Pose3QuatGaussian(detail::Unchecked, const Pose3Quat& mean, const Matrix& covariance) noexcept
      : mean_(mean), cov_(covariance) {}

  /// The mean pose.
  const Pose3Quat& mean() const noexcept { return mean_; }
  /// The covariance of (x, y, z, qw, qx, qy, qz).
  const Matrix& covariance() const noexcept { return cov_; }

  /// p − mean on the 7 parameters, with p's quaternion taken with the sign
  /// closer to the mean's (q and −q are the same rotation).
  Vector difference(const Pose3Quat& p) const;

  /// Mahalanobis distance of `p` on difference(p) (pseudo-inverse of the
  /// covariance; +inf along directions of zero variance).
  double mahalanobis_distance(const Pose3Quat& p) const;
  /// Mahalanobis distance between the means of two independent Gaussians
  /// under the sum of their covariances.
  double mahalanobis_distance(const Pose3QuatGaussian& other) const;
  /// Natural log of the density at `p` on difference(p). Throws
  /// InvalidArgument if the covariance is not positive definite (a covariance
  /// converted from yaw-pitch-roll is singular and has no density).
  double log_likelihood(const Pose3Quat& p) const;
  /// The density at `p` (exp of log_likelihood).
  double likelihood(const Pose3Quat& p) const;

  /// Draws one pose: parameters mean + S·z, z ~ N(0, I), S·Sᵀ = covariance;
  /// the quaternion is then normalized by the Pose3Quat constructor.
  Pose3Quat sample(std::mt19937_64& rng) const;
  /// Draws `n` poses, factoring the covariance once.
  std::vector<Pose3Quat> sample(std::mt19937_64& rng, std::size_t n) const;

 private:
  Pose3Quat mean_{};
  Matrix cov_ = Matrix::Zero();
};

/// a ⊕ b of independent Gaussians (MRPT's CPose3DQuatPDFGaussian::operator+=).
Pose3QuatGaussian compose(const Pose3QuatGaussian& a, const Pose3QuatGaussian& b);
/// a ⊕ b with a deterministic left pose (MRPT's changeCoordinatesReference).
Pose3QuatGaussian compose(const Pose3Quat& a, const Pose3QuatGaussian& b);
/// a ⊕ b with a deterministic right pose.
Pose3QuatGaussian compose(const Pose3QuatGaussian& a, const Pose3Quat& b);
/// a ⊖ b = b⁻¹ ⊕ a of independent Gaussians (MRPT's operator-=).
Pose3QuatGaussian inverse_compose(const Pose3QuatGaussian& a, const Pose3QuatGaussian& b);
/// a ⊖ b with deterministic b.
Pose3QuatGaussian inverse_compose(const Pose3QuatGaussian& a, const Pose3Quat& b);
/// a ⊖ b with deterministic a.
Pose3QuatGaussian inverse_compose(const Pose3Quat& a, const Pose3QuatGaussian& b);
/// a⁻¹ (MRPT's CPose3DQuatPDFGaussian::inverse).
Pose3QuatGaussian inverse(const Pose3QuatGaussian& a);

/// Same as compose(a, b).
Pose3QuatGaussian operator+(const Pose3QuatGaussian& a, const Pose3QuatGaussian& b);
/// Same as compose(a, b).
Pose3QuatGaussian operator+(const Pose3Quat& a, const Pose3QuatGaussian& b);
/// Same as compose(a, b).
Pose3QuatGaussian operator+(const Pose3QuatGaussian& a, const Pose3Quat& b);
/// Same as inverse_compose(a, b).
Pose3QuatGaussian operator-(const Pose3QuatGaussian& a, const Pose3QuatGaussian& b);
/// Same as inverse_compose(a, b).
Pose3QuatGaussian operator-(const Pose3QuatGaussian& a, const Pose3Quat& b);
/// Same as inverse_compose(a, b).
Pose3QuatGaussian operator-(const Pose3Quat& a, const Pose3QuatGaussian& b);
/// Same as inverse(a).
Pose3QuatGaussian operator-(const Pose3QuatGaussian& a);

/// Yaw-pitch-roll → quaternion: mean converted with ypr_to_quat, covariance
/// J·C·Jᵀ with J = jacobian_pose3_to_quat (MRPT's
/// CPose3DQuatPDFGaussian::copyFrom(CPose3DPDFGaussian), Jacobian method).
Pose3QuatGaussian to_quat_gaussian(const Pose3Gaussian& p);
/// The 2D Gaussian in the quaternion parameterization (via to_3d).
Pose3QuatGaussian to_quat_gaussian(const Pose2Gaussian& p);
/// Quaternion → yaw-pitch-roll: mean from quat_to_ypr, covariance J·C·Jᵀ with
/// J = jacobian_quat_to_pose3, which includes the normalization Jacobian
/// (MRPT's CPose3DPDFGaussian::copyFrom(CPose3DQuatPDFGaussian)).
Pose3Gaussian to_euler_gaussian(const Pose3QuatGaussian& q);

}  // namespace rove
