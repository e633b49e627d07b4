#pragma once
/// \file
/// PoseSOG<Pose>: a sum of Gaussians over Pose2 or Pose3, each mode a
/// Pose2Gaussian / Pose3Gaussian with a log-weight (MRPT's CPosePDFSOG /
/// CPose3DPDFSOG). The mean is the weighted mean of the mode means
/// (pdf_pose_average.h); the covariance is the law of total covariance
/// Σ w̄ᵢ (Cᵢ + dᵢ dᵢᵀ), dᵢ = pose_difference(meanᵢ, mean) with angles wrapped.

#include <cstddef>
#include <random>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_gaussian3.h"
#include "rove/poses/pdf_pose_average.h"

namespace rove {

/// The Gaussian PDF type of a pose type: Pose2 → Pose2Gaussian,
/// Pose3 → Pose3Gaussian.
template <PdfPose Pose>
using GaussianOf = std::conditional_t<std::same_as<Pose, Pose2>, Pose2Gaussian, Pose3Gaussian>;

/// A weighted sum of Gaussian modes. A plain value; thread-compatible.
template <PdfPose Pose>
class PoseSOG {
 public:
  /// The mode type.
  using Gaussian = GaussianOf<Pose>;
  /// Covariance type.
  using Matrix = typename Gaussian::Matrix;

  /// One weighted Gaussian mode.
  struct Mode {
    Gaussian gaussian{};      ///< the mode
    double log_weight = 0.0;  ///< natural log of its (unnormalized) weight
  };

  /// No modes.
  PoseSOG() = default;
  /// From modes. Throws InvalidArgument if a log-weight is NaN or +inf.
  explicit PoseSOG(std::vector<Mode> modes);

  /// Appends a mode (same checks as the constructor).
  void push_back(const Gaussian& gaussian, double log_weight = 0.0);
  /// The modes.
  const std::vector<Mode>& modes() const noexcept { return modes_; }
  /// Number of modes.
  std::size_t size() const noexcept { return modes_.size(); }
  /// True if there are no modes.
  bool empty() const noexcept { return modes_.empty(); }

  /// Shifts the log-weights so that the weights sum to one (log-sum-exp).
  /// Precondition: not empty, not all weights zero.
  void normalize_weights();
  /// The weights exp(log_weight), scaled to sum to one.
  std::vector<double> normalized_weights() const;

  /// The weighted mean of the mode means. Precondition: not empty.
  Pose mean() const;
  /// The law-of-total-covariance covariance around mean().
  Matrix covariance() const;
  /// The mode of largest weight (first on ties). Precondition: not empty.
  const Mode& most_likely() const;
  /// Draws a pose: a mode chosen with probability proportional to its
  /// weight, then a sample of that Gaussian.
  Pose sample(std::mt19937_64& rng) const;

 private:
  std::vector<Mode> modes_;
};

extern template class PoseSOG<Pose2>;
extern template class PoseSOG<Pose3>;

/// Sum of Gaussians over Pose2.
using Pose2SOG = PoseSOG<Pose2>;
/// Sum of Gaussians over Pose3.
using Pose3SOG = PoseSOG<Pose3>;

}  // namespace rove
