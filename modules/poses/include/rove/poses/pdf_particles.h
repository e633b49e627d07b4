#pragma once
/// \file
/// PoseParticles<Pose>: a pose PDF represented by weighted samples with
/// log-weights (MRPT's CPosePDFParticles / CPose3DPDFParticles), for Pose2
/// and Pose3. Mean and rotation average as pdf_pose_average.h; the covariance
/// is Σ w̄ᵢ dᵢ dᵢᵀ with dᵢ = pose_difference(poseᵢ, mean) (angles wrapped
/// around the mean) and w̄ the normalized weights.

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "rove/poses/pdf_pose_average.h"

namespace rove {

/// Weighted pose samples. A plain value; thread-compatible.
template <PdfPose Pose>
class PoseParticles {
 public:
  /// Number of parameters of Pose (3 or 6).
  static constexpr int kDim = std::same_as<Pose, Pose2> ? 3 : 6;
  /// Covariance type, ordered as the pose's Gaussian.
  using Matrix = Eigen::Matrix<double, kDim, kDim>;

  /// One weighted sample.
  struct Particle {
    Pose pose{};              ///< the sample
    double log_weight = 0.0;  ///< natural log of its (unnormalized) weight
  };

  /// No particles.
  PoseParticles() = default;
  /// From particles. Throws InvalidArgument if a log-weight is NaN or +inf
  /// (−inf, a zero weight, is allowed).
  explicit PoseParticles(std::vector<Particle> particles);
  /// `n` copies of `pose`, equal weights (log-weight 0).
  PoseParticles(std::size_t n, const Pose& pose);

  /// Appends a particle (same checks as the constructor).
  void push_back(const Pose& pose, double log_weight = 0.0);
  /// The particles.
  const std::vector<Particle>& particles() const noexcept { return particles_; }
  /// Number of particles.
  std::size_t size() const noexcept { return particles_.size(); }
  /// True if there are no particles.
  bool empty() const noexcept { return particles_.empty(); }

  /// Shifts the log-weights so that the weights sum to one (log-sum-exp).
  /// Precondition: not empty, not all weights zero.
  void normalize_weights();
  /// The weights exp(log_weight), scaled to sum to one.
  /// Precondition: not empty, not all weights zero.
  std::vector<double> normalized_weights() const;
  /// Effective sample size 1 / Σ w̄ᵢ², in [1, size()].
  /// Precondition: not empty, not all weights zero.
  double effective_sample_size() const;

  /// The weighted mean (weighted_mean of the particles).
  Pose mean() const;
  /// The weighted covariance around mean() (biased, normalized weights).
  Matrix covariance() const;
  /// The particle of largest weight (the first one on ties).
  /// Precondition: not empty.
  const Particle& most_likely() const;
  /// Draws a particle's pose with probability proportional to its weight.
  /// Precondition: not empty, not all weights zero.
  Pose sample(std::mt19937_64& rng) const;

 private:
  std::vector<Particle> particles_;
};

extern template class PoseParticles<Pose2>;
extern template class PoseParticles<Pose3>;

/// Particles over Pose2.
using Pose2Particles = PoseParticles<Pose2>;
/// Particles over Pose3.
using Pose3Particles = PoseParticles<Pose3>;

}  // namespace rove
