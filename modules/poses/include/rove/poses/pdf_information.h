#pragma once
/// \file
/// Gaussian pose PDFs in information form: mean + information matrix (the
/// inverse covariance), orderings as the covariance forms — Pose2 (x, y, phi),
/// Pose3 (x, y, z, yaw, pitch, roll) (MRPT's CPosePDFGaussianInf and
/// CPose3DPDFGaussianInf). The information matrix may be singular (no
/// information along some direction).
///
/// Transforming by an invertible Jacobian J maps information as
/// Λ' = J⁻ᵀ·Λ·J⁻¹, which stays exact for a singular Λ; this is what the
/// operations with a deterministic pose and inverse() use. (MRPT's
/// CPosePDFGaussianInf::inverse and operator+=(pose) apply J·Λ·Jᵀ, which is
/// the covariance rule, not the information one.) Composing two uncertain
/// poses goes through the covariance form and needs both informations to be
/// positive definite.

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_gaussian3.h"

namespace rove {

/// A Gaussian over Pose2 in information form. A plain value.
class Pose2GaussianInf {
 public:
  /// Information matrix type, ordered (x, y, phi), units 1/m², 1/(m·rad), 1/rad².
  using Matrix = Eigen::Matrix3d;

  /// Identity mean, zero information (no knowledge at all).
  Pose2GaussianInf() = default;
  /// Mean and information. Throws InvalidArgument unless `information` is
  /// finite, symmetric and positive semi-definite; stored symmetrized.
  Pose2GaussianInf(const Pose2& mean, const Matrix& information);
  /// Internal: no validation; `information` must be symmetric PSD.
  Pose2GaussianInf(detail::Unchecked, const Pose2& mean, const Matrix& information) noexcept
      : mean_(mean), info_(information) {}

  /// The mean pose.
  const Pose2& mean() const noexcept { return mean_; }
  /// The information matrix.
  const Matrix& information() const noexcept { return info_; }

  /// Mahalanobis distance sqrt(dᵀΛd) of `p`, d = (dx, dy, wrap(dphi)).
  double mahalanobis_distance(const Pose2& p) const;
  /// Natural log of the density at `p`. Throws InvalidArgument if the
  /// information is not positive definite.
  double log_likelihood(const Pose2& p) const;
  /// The density at `p`.
  double likelihood(const Pose2& p) const;
  /// Draws one pose (requires a positive-definite information).
  Pose2 sample(std::mt19937_64& rng) const;
  /// Draws `n` poses (requires a positive-definite information).
  std::vector<Pose2> sample(std::mt19937_64& rng, std::size_t n) const;

 private:
  Pose2 mean_{};
  Matrix info_ = Matrix::Zero();
};

/// A Gaussian over Pose3 in information form. A plain value.
class Pose3GaussianInf {
 public:
  /// Information matrix type, ordered (x, y, z, yaw, pitch, roll).
  using Matrix = Eigen::Matrix<double, 6, 6>;

  /// Identity mean, zero information.
  Pose3GaussianInf() = default;
  /// Mean and information. Throws InvalidArgument unless `information` is
  /// finite, symmetric and positive semi-definite; stored symmetrized.
  Pose3GaussianInf(const Pose3& mean, const Matrix& information);
  /// Internal: no validation; `information` must be symmetric PSD.
  Pose3GaussianInf(detail::Unchecked, const Pose3& mean, const Matrix& information) noexcept
      : mean_(mean), info_(information) {}

  /// The mean pose.
  const Pose3& mean() const noexcept { return mean_; }
  /// The information matrix.
  const Matrix& information() const noexcept { return info_; }

  /// Mahalanobis distance sqrt(dᵀΛd), d as Pose3Gaussian::difference.
  double mahalanobis_distance(const Pose3& p) const;
  /// Natural log of the density at `p`. Throws InvalidArgument if the
  /// information is not positive definite.
  double log_likelihood(const Pose3& p) const;
  /// The density at `p`.
  double likelihood(const Pose3& p) const;
  /// Draws one pose (requires a positive-definite information).
  Pose3 sample(std::mt19937_64& rng) const;
  /// Draws `n` poses (requires a positive-definite information).
  std::vector<Pose3> sample(std::mt19937_64& rng, std::size_t n) const;

 private:
  Pose3 mean_{};
  Matrix info_ = Matrix::Zero();
};

/// Covariance → information. Throws InvalidArgument if the covariance is not
/// positive definite.
Pose2GaussianInf to_information(const Pose2Gaussian& p);
/// Covariance → information. Throws InvalidArgument if the covariance is not
/// positive definite.
Pose3GaussianInf to_information(const Pose3Gaussian& p);
/// Information → covariance. Throws InvalidArgument if the information is not
/// positive definite.
Pose2Gaussian to_covariance(const Pose2GaussianInf& p);
/// Information → covariance. Throws InvalidArgument if the information is not
/// positive definite.
Pose3Gaussian to_covariance(const Pose3GaussianInf& p);

/// a ⊕ b of independent Gaussians, through the covariance form (both
/// informations must be positive definite).
Pose2GaussianInf compose(const Pose2GaussianInf& a, const Pose2GaussianInf& b);
/// a ⊕ b with a deterministic left pose (Λ' = J⁻ᵀΛJ⁻¹).
Pose2GaussianInf compose(const Pose2& a, const Pose2GaussianInf& b);
/// a ⊕ b with a deterministic right pose (Λ' = J⁻ᵀΛJ⁻¹).
Pose2GaussianInf compose(const Pose2GaussianInf& a, const Pose2& b);
/// a ⊖ b of independent Gaussians, through the covariance form.
Pose2GaussianInf inverse_compose(const Pose2GaussianInf& a, const Pose2GaussianInf& b);
/// a⁻¹ (Λ' = J⁻ᵀΛJ⁻¹, J = d(a⁻¹)/da).
Pose2GaussianInf inverse(const Pose2GaussianInf& a);

/// a ⊕ b of independent Gaussians, through the covariance form.
Pose3GaussianInf compose(const Pose3GaussianInf& a, const Pose3GaussianInf& b);
/// a ⊕ b with a deterministic left pose. Throws NumericError at gimbal lock,
/// where the yaw-pitch-roll Jacobian is singular.
Pose3GaussianInf compose(const Pose3& a, const Pose3GaussianInf& b);
/// a ⊕ b with a deterministic right pose. Throws NumericError at gimbal lock.
Pose3GaussianInf compose(const Pose3GaussianInf& a, const Pose3& b);
/// a ⊖ b of independent Gaussians, through the covariance form.
Pose3GaussianInf inverse_compose(const Pose3GaussianInf& a, const Pose3GaussianInf& b);
/// a⁻¹. Throws NumericError at gimbal lock.
Pose3GaussianInf inverse(const Pose3GaussianInf& a);

/// Same as compose(a, b).
Pose2GaussianInf operator+(const Pose2GaussianInf& a, const Pose2GaussianInf& b);
/// Same as compose(a, b).
Pose2GaussianInf operator+(const Pose2& a, const Pose2GaussianInf& b);
/// Same as compose(a, b).
Pose2GaussianInf operator+(const Pose2GaussianInf& a, const Pose2& b);
/// Same as inverse_compose(a, b).
Pose2GaussianInf operator-(const Pose2GaussianInf& a, const Pose2GaussianInf& b);
/// Same as inverse(a).
Pose2GaussianInf operator-(const Pose2GaussianInf& a);
/// Same as compose(a, b).
Pose3GaussianInf operator+(const Pose3GaussianInf& a, const Pose3GaussianInf& b);
/// Same as compose(a, b).
Pose3GaussianInf operator+(const Pose3& a, const Pose3GaussianInf& b);
/// Same as compose(a, b).
Pose3GaussianInf operator+(const Pose3GaussianInf& a, const Pose3& b);
/// Same as inverse_compose(a, b).
Pose3GaussianInf operator-(const Pose3GaussianInf& a, const Pose3GaussianInf& b);
/// Same as inverse(a).
Pose3GaussianInf operator-(const Pose3GaussianInf& a);

}  // namespace rove
