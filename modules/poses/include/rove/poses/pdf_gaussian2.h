#pragma once
/// \file
/// Pose2Gaussian: a 2D pose with Gaussian uncertainty, mean + 3×3 covariance
/// ordered (x, y, phi), units m and rad (MRPT's CPosePDFGaussian).
/// Composition and inversion propagate the covariance to first order with the
/// exact Jacobians of pdf_jacobians.h: C = J₁·C₁·J₁ᵀ + J₂·C₂·J₂ᵀ.

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "rove/poses/pose2.h"

namespace rove {

/// A Gaussian distribution over Pose2: the mean pose and the covariance of
/// (x, y, phi) around it. A plain value; thread-compatible.
class Pose2Gaussian {
 public:
  /// Covariance (or Jacobian) type, ordered (x, y, phi).
  using Matrix = Eigen::Matrix3d;
  /// A difference vector (dx, dy, dphi).
  using Vector = Eigen::Vector3d;

  /// Identity mean, zero covariance.
  Pose2Gaussian() = default;
  /// A pose without uncertainty (zero covariance).
  explicit Pose2Gaussian(const Pose2& mean);
  /// Mean and covariance (m², m·rad, rad²). Throws InvalidArgument unless the
  /// covariance is finite, symmetric and positive semi-definite
  /// (check_covariance); it is stored symmetrized.
  Pose2Gaussian(const Pose2& mean, const Matrix& covariance);

  /// Internal: no validation; `covariance` must already be symmetric PSD
  /// (results of propagation).
  Pose2Gaussian(detail::Unchecked, const Pose2& mean, const Matrix& covariance) noexcept
      : mean_(mean), cov_(covariance) {}

  /// The mean pose.
  const Pose2& mean() const noexcept { return mean_; }
  /// The covariance of (x, y, phi).
  const Matrix& covariance() const noexcept { return cov_; }

  /// p − mean as (dx, dy, wrap(dphi)): the difference used by the density.
  Vector difference(const Pose2& p) const;

  /// Mahalanobis distance of `p` from this distribution, on difference(p);
  /// +inf if p differs along a direction of zero variance.
  double mahalanobis_distance(const Pose2& p) const;
  /// Mahalanobis distance between the means of two independent Gaussians
  /// under the sum of their covariances (MRPT's mahalanobisDistanceTo).
  double mahalanobis_distance(const Pose2Gaussian& other) const;
  /// Natural log of the density at `p` (MRPT's evaluatePDF, in log), with the
  /// angle difference wrapped. Throws InvalidArgument if the covariance is not
  /// positive definite.
  double log_likelihood(const Pose2& p) const;
  /// The density at `p` (exp of log_likelihood), in 1/(m²·rad).
  double likelihood(const Pose2& p) const;

  /// Draws one pose: mean + S·z, z ~ N(0, I), S·Sᵀ = covariance (psd_sqrt,
  /// so a singular or zero covariance works), phi wrapped.
  Pose2 sample(std::mt19937_64& rng) const;
  /// Draws `n` poses, factoring the covariance once.
  std::vector<Pose2> sample(std::mt19937_64& rng, std::size_t n) const;

 private:
  Pose2 mean_{};
  Matrix cov_ = Matrix::Zero();
};

/// a ⊕ b of independent Gaussians; mean a.mean ⊕ b.mean.
Pose2Gaussian compose(const Pose2Gaussian& a, const Pose2Gaussian& b);
/// a ⊕ b with a deterministic left pose (change of reference frame).
Pose2Gaussian compose(const Pose2& a, const Pose2Gaussian& b);
/// a ⊕ b with a deterministic right pose (exact Jacobian d(a⊕b)/da; MRPT's
/// `operator+=(CPose2D)` only rotates the covariance, which is not first-order
/// exact).
Pose2Gaussian compose(const Pose2Gaussian& a, const Pose2& b);
/// a ⊖ b = b⁻¹ ⊕ a of independent Gaussians, "a as seen from b" (MRPT's
/// CPosePDFGaussian::inverseComposition).
Pose2Gaussian inverse_compose(const Pose2Gaussian& a, const Pose2Gaussian& b);
/// a ⊖ b with deterministic b.
Pose2Gaussian inverse_compose(const Pose2Gaussian& a, const Pose2& b);
/// a ⊖ b with deterministic a.
Pose2Gaussian inverse_compose(const Pose2& a, const Pose2Gaussian& b);
/// a⁻¹ (MRPT's CPosePDFGaussian::inverse).
Pose2Gaussian inverse(const Pose2Gaussian& a);

/// Same as compose(a, b).
Pose2Gaussian operator+(const Pose2Gaussian& a, const Pose2Gaussian& b);
/// Same as compose(a, b).
Pose2Gaussian operator+(const Pose2& a, const Pose2Gaussian& b);
/// Same as compose(a, b).
Pose2Gaussian operator+(const Pose2Gaussian& a, const Pose2& b);
/// Same as inverse_compose(a, b).
Pose2Gaussian operator-(const Pose2Gaussian& a, const Pose2Gaussian& b);
/// Same as inverse_compose(a, b).
Pose2Gaussian operator-(const Pose2Gaussian& a, const Pose2& b);
/// Same as inverse_compose(a, b).
Pose2Gaussian operator-(const Pose2& a, const Pose2Gaussian& b);
/// Same as inverse(a).
Pose2Gaussian operator-(const Pose2Gaussian& a);

}  // namespace rove
