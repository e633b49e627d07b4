#pragma once
/// \file
/// Weighted means of poses and the differences used to form covariances
/// around them, shared by PoseParticles and PoseSOG.
///  - Pose2: weighted mean of (x, y); phi by the weighted circular mean
///    atan2(Σ wᵢ sin φᵢ, Σ wᵢ cos φᵢ) (MRPT's SE_average<2>).
///  - Pose3: weighted mean of the translations; rotation by the weighted
///    chordal L2 mean, the projection of Σ wᵢ Rᵢ onto SO(3) with an SVD
///    (Hartley, Trumpf, Dai, Li, "Rotation averaging", IJCV 2013, §5.3;
///    MRPT's SO_average<3>).

#include <concepts>
#include <span>

#include <Eigen/Core>

#include "rove/poses/pose2.h"
#include "rove/poses/pose3.h"

namespace rove {

/// The pose types the sample-based PDFs support.
template <typename P>
concept PdfPose = std::same_as<P, Pose2> || std::same_as<P, Pose3>;

/// Weighted mean of poses (see the file comment for the rotation part).
/// Preconditions: same sizes, at least one pose, weights finite, ≥ 0 and not
/// all zero. Throws NumericError when the rotation mean is undetermined (the
/// sines and cosines cancel, or Σ wᵢ Rᵢ has rank < 2).
Pose2 weighted_mean(std::span<const Pose2> poses, std::span<const double> weights);
/// Weighted mean of 3D poses: translation mean and chordal rotation mean.
Pose3 weighted_mean(std::span<const Pose3> poses, std::span<const double> weights);

/// p − mean as (dx, dy, wrap(dphi)).
Eigen::Vector3d pose_difference(const Pose2& p, const Pose2& mean);
/// p − mean as (dx, dy, dz, wrap(dyaw), wrap(dpitch), wrap(droll)) on the
/// yaw-pitch-roll parameters.
Eigen::Matrix<double, 6, 1> pose_difference(const Pose3& p, const Pose3& mean);

}  // namespace rove
