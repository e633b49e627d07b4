#pragma once
/// \file
/// The two probabilistic odometry motion models of MRPT's
/// CActionRobotMovement2D: the PDF of the true pose increment given the
/// increment odometry reports, u = (Δx, Δy, Δφ) in the robot frame at the
/// start of the motion.

#include <array>
#include <random>

#include "rove/obs/motion_model_options.h"
#include "rove/poses/pdf_gaussian2.h"
#include "rove/poses/pdf_particles.h"
#include "rove/poses/pose2.h"

namespace rove {

/// Gaussian motion model (MRPT's computeFromOdometry_modelGaussian; see
/// MRPT's tutorial "Probabilistic motion models", after Eliazar & Parr,
/// "Learning probabilistic motion models for mobile robots", ICML 2004).
///
/// With d = ‖(Δx, Δy)‖ (m) and |Δφ| (rad):
///   σ_xy = minStdXY + α1·d + α2·|Δφ|,  σ_φ = minStdPHI + α3·d + α4·|Δφ|,
///   Σ = diag(σ_xy², σ_xy², σ_φ²),
///   J = [ cos(Δφ/2)  −sin(Δφ/2)  −sin(Δφ/2)·Δx − cos(Δφ/2)·Δy ]
///       [ sin(Δφ/2)   cos(Δφ/2)   cos(Δφ/2)·Δx − sin(Δφ/2)·Δy ]
///       [ 0           0           1                            ],
///   mean = u, covariance C = J Σ Jᵀ.
/// This is MRPT's formula term for term (its third column is not the exact
/// derivative of the rotation by Δφ/2, which would carry a factor ½; kept
/// for agreement with MRPT). Precondition (InvalidArgument): options.check().
Pose2Gaussian gaussian_motion_model(const Pose2& odometry_increment,
                                    const GaussianMotionOptions& options);

/// One sample of Thrun's odometry model as MRPT implements it
/// (computeFromOdometry_modelThrun / drawSingleSample_modelThrun), after
/// Thrun, Burgard, Fox, "Probabilistic Robotics", table 5.6
/// (sample_motion_model_odometry), for a start pose at the origin:
///   δrot1 = atan2(Δy, Δx) (0 if Δx = Δy = 0), δtrans = ‖(Δx, Δy)‖,
///   δrot2 = wrap(Δφ − δrot1);
///   δ̂rot1  = δrot1  − (α1|δrot1| + α2 δtrans)·n1,
///   δ̂trans = δtrans − (α3 δtrans + α4(|δrot1| + |δrot2|))·n2,
///   δ̂rot2  = δrot2  − (α1|δrot2| + α2 δtrans)·n3,
///   x = δ̂trans cos δ̂rot1 + σxy n4,  y = δ̂trans sin δ̂rot1 + σxy n5,
///   φ = wrap(δ̂rot1 + δ̂rot2 + σφ n6),   nk ~ N(0, 1) independent.
/// Unlike the book, whose sample(b²) takes variances α1δrot1² + α2δtrans²,
/// MRPT scales standard deviations linearly; σxy, σφ are MRPT's
/// additional_std terms. Precondition (InvalidArgument): options.check().
Pose2 sample_thrun_motion(const Pose2& odometry_increment, const ThrunMotionOptions& options,
                          std::mt19937_64& rng);

/// One sample of Thrun's model from its six standard normal draws: the
/// increment (x, y meters; phi radians, not wrapped, in (−2π − ε, 2π + ε)).
struct ThrunMotionSample {
  double x = 0.0;    ///< meters
  double y = 0.0;    ///< meters
  double phi = 0.0;  ///< radians, not wrapped
};

/// sample_thrun_motion split in two for callers that draw many samples of
/// one increment (a particle filter's prediction) from their own random
/// streams: the constructor does the per-increment work (δrot1, δtrans,
/// δrot2 and the three standard deviations), sample() maps six independent
/// N(0, 1) draws n1..n6 (in the order of the formula above) to a sample.
/// Thread-safety: sample() is const and may run concurrently.
class ThrunMotionSampler {
 public:
  /// Precondition (InvalidArgument): options.check().
  ThrunMotionSampler(const Pose2& odometry_increment, const ThrunMotionOptions& options);
  /// The sample for the normal draws `n`.
  ThrunMotionSample sample(const std::array<double, 6>& n) const noexcept;

 private:
  double rot1_ = 0.0, trans_ = 0.0, rot2_ = 0.0;
  double s_rot1_ = 0.0, s_trans_ = 0.0, s_rot2_ = 0.0;
  double add_xy_ = 0.0, add_phi_ = 0.0;
};

/// options.particle_count samples of sample_thrun_motion with equal weights:
/// the sampled PDF MRPT stores in CPosePDFParticles.
Pose2Particles thrun_motion_particles(const Pose2& odometry_increment,
                                      const ThrunMotionOptions& options, std::mt19937_64& rng);

}  // namespace rove
