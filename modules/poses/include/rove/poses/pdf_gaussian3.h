#pragma once
/// \file
/// Pose3Gaussian: a 3D pose with Gaussian uncertainty, mean + 6×6 covariance
/// ordered (x, y, z, yaw, pitch, roll), units m and rad (MRPT's
/// CPose3DPDFGaussian). Composition and inversion propagate the covariance to
/// first order with the exact Jacobians of pdf_jacobians.h (the chain through
/// the quaternion parameterization, as MRPT), C = J₁·C₁·J₁ᵀ + J₂·C₂·J₂ᵀ.
/// Conversions to and from Pose3QuatGaussian are in pdf_gaussian3_quat.h.

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pose3.h"

namespace rove {

/// A Gaussian distribution over Pose3: the mean pose and the covariance of
/// (x, y, z, yaw, pitch, roll) around it. A plain value; thread-compatible.
class Pose3Gaussian {
 public:
  /// Covariance type, ordered (x, y, z, yaw, pitch, roll).
  using Matrix = Eigen::Matrix<double, 6, 6>;
  /// A difference vector (dx, dy, dz, dyaw, dpitch, droll).
  using Vector = Eigen::Matrix<double, 6, 1>;

  /// Identity mean, zero covariance.
  Pose3Gaussian() = default;
  /// A pose without uncertainty (zero covariance).
  explicit Pose3Gaussian(const Pose3& mean);
  /// Mean and covariance (m², m·rad, rad²). Throws InvalidArgument unless the
  /// covariance is finite, symmetric and positive semi-definite
  /// (check_covariance); it is stored symmetrized.
  Pose3Gaussian(const Pose3& mean, const Matrix& covariance);

  /// Internal: no validation; `covariance` must already be symmetric PSD
  /// (results of propagation).
  Pose3Gaussian(detail::Unchecked, const Pose3& mean, const Matrix& covariance) noexcept
      : mean_(mean), cov_(covariance) {}

  /// The mean pose.
  const Pose3& mean() const noexcept { return mean_; }
  /// The covariance of (x, y, z, yaw, pitch, roll).
  const Matrix& covariance() const noexcept { return cov_; }

  /// p − mean on the parameters (x, y, z, yaw, pitch, roll), each angle
  /// difference wrapped to (−π, π].
  Vector difference(const Pose3& p) const;

  /// Mahalanobis distance of `p` on difference(p); +inf if p differs along a
  /// direction of zero variance.
  double mahalanobis_distance(const Pose3& p) const;
  /// Mahalanobis distance between the means of two independent Gaussians
  /// under the sum of their covariances (MRPT's mahalanobisDistanceTo, with
  /// the angle differences wrapped).
  double mahalanobis_distance(const Pose3Gaussian& other) const;
  /// Natural log of the density at `p` on difference(p). Throws
  /// InvalidArgument if the covariance is not positive definite.
  double log_likelihood(const Pose3& p) const;
  /// The density at `p` (exp of log_likelihood).
  double likelihood(const Pose3& p) const;

  /// Draws one pose: parameters mean + S·z, z ~ N(0, I), S·Sᵀ = covariance
  /// (psd_sqrt, so singular covariances work), as MRPT's drawSingleSample.
  Pose3 sample(std::mt19937_64& rng) const;
  /// Draws `n` poses, factoring the covariance once.
  std::vector<Pose3> sample(std::mt19937_64& rng, std::size_t n) const;

 private:
  Pose3 mean_{};
  Matrix cov_ = Matrix::Zero();
};

/// a ⊕ b of independent Gaussians (MRPT's CPose3DPDFGaussian::operator+=).
Pose3Gaussian compose(const Pose3Gaussian& a, const Pose3Gaussian& b);
/// a ⊕ b with a deterministic left pose (MRPT's changeCoordinatesReference).
Pose3Gaussian compose(const Pose3& a, const Pose3Gaussian& b);
/// a ⊕ b with a deterministic right pose (MRPT's operator+=(CPose3D)).
Pose3Gaussian compose(const Pose3Gaussian& a, const Pose3& b);
/// a ⊖ b = b⁻¹ ⊕ a of independent Gaussians (MRPT's operator-=).
Pose3Gaussian inverse_compose(const Pose3Gaussian& a, const Pose3Gaussian& b);
/// a ⊖ b with deterministic b.
Pose3Gaussian inverse_compose(const Pose3Gaussian& a, const Pose3& b);
/// a ⊖ b with deterministic a.
Pose3Gaussian inverse_compose(const Pose3& a, const Pose3Gaussian& b);
/// a⁻¹ (MRPT's CPose3DPDFGaussian::inverse).
Pose3Gaussian inverse(const Pose3Gaussian& a);

/// Same as compose(a, b).
Pose3Gaussian operator+(const Pose3Gaussian& a, const Pose3Gaussian& b);
/// Same as compose(a, b).
Pose3Gaussian operator+(const Pose3& a, const Pose3Gaussian& b);
/// Same as compose(a, b).
Pose3Gaussian operator+(const Pose3Gaussian& a, const Pose3& b);
/// Same as inverse_compose(a, b).
Pose3Gaussian operator-(const Pose3Gaussian& a, const Pose3Gaussian& b);
/// Same as inverse_compose(a, b).
Pose3Gaussian operator-(const Pose3Gaussian& a, const Pose3& b);
/// Same as inverse_compose(a, b).
Pose3Gaussian operator-(const Pose3& a, const Pose3Gaussian& b);
/// Same as inverse(a).
Pose3Gaussian operator-(const Pose3Gaussian& a);

/// The 2D Gaussian as a 3D one: mean (x, y, 0, phi, 0, 0), the covariance of
/// (x, y, phi) moved to (x, y, yaw), zero elsewhere (MRPT's
/// CPose3DPDFGaussian(const CPosePDFGaussian&)).
Pose3Gaussian to_3d(const Pose2Gaussian& p);
/// The marginal over (x, y, yaw) as a Pose2Gaussian (MRPT's
/// CPosePDFGaussian::copyFrom(CPose3DPDF)).
Pose2Gaussian to_2d(const Pose3Gaussian& p);

}  // namespace rove
