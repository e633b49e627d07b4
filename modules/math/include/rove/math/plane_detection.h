#pragma once
/// \file
/// Planes in 3D point clouds: least-squares (PCA) plane fit, the RANSAC
/// problem for one plane, and detection of several planes by sequential
/// RANSAC. Points are std::vector<Eigen::Vector3d> (or any contiguous range
/// of them, as std::span), in any one frame and in meters; results are in
/// the same frame.

#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/math/ransac.h"
#include "rove/math/sequential_detection.h"

namespace rove {

/// A plane {p : n·p + d = 0} with unit normal n. Canonical sign: d ≤ 0
/// (n points from the origin towards the plane); for a plane through the
/// origin (d = 0) the largest-magnitude component of n is positive.
struct Plane3 {
  /// Unit normal n.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  /// Offset d (m): n·p + d = 0 on the plane; −d ≥ 0 is the distance from
  /// the origin to the plane.
  double offset = 0.0;

  /// Signed distance n·p + d (m) of a point; positive on the side n points to.
  double signed_distance(const Eigen::Vector3d& p) const { return normal.dot(p) + offset; }
};

/// Total-least-squares plane of ≥ 3 points: through the centroid, normal
/// along the eigenvector of the smallest eigenvalue of the scatter matrix.
/// Returns nullopt when fewer than 3 points are given or the points do not
/// span a plane (all coincident or collinear, up to a relative 1e-10 on the
/// scatter eigenvalues). Precondition (InvalidArgument): all points finite.
std::optional<Plane3> fit_plane(std::span<const Eigen::Vector3d> points);

/// RansacProblem for one plane: minimal sample of 3 points, distance
/// |n·p + d| (m), refit by fit_plane() on the inliers.
struct PlaneRansacProblem {
  using Model = Plane3;
  using Datum = Eigen::Vector3d;

  /// A sample is degenerate when the sine of the angle at its first point is
  /// below this (nearly collinear or repeated points). Default 1e-6.
  double min_sine = 1e-6;

  /// 3.
  std::size_t sample_size() const { return 3; }
  /// True if the 3 points are (nearly) collinear or coincident.
  bool is_degenerate(std::span<const Datum> sample) const;
  /// Appends the plane through the 3 points (none if degenerate).
  void fit(std::span<const Datum> sample, std::vector<Model>& models) const;
  /// Unsigned point-to-plane distance (m).
  double distance(const Model& plane, const Datum& p) const {
    return std::abs(plane.signed_distance(p));
  }
  /// Replaces `plane` by fit_plane(inliers); false if that has no solution.
  bool refit(std::span<const Datum> inliers, Model& plane) const;
};

/// Options of detect_planes(); ransac.distance_threshold is in meters.
using PlaneDetectionOptions = SequentialDetectionOptions;
/// Outcome of detect_planes(): planes (with their inlier indices) in the
/// order found, unassigned points, termination reason.
using PlaneDetectionResult = SequentialDetectionResult<Plane3>;

/// Detects up to options.max_models planes by sequential RANSAC: find the
/// plane with most inliers, refit it by PCA on them, remove them, repeat
/// until fewer than options.min_inliers points remain, the best plane has
/// fewer inliers than that, or max_models planes are found.
/// Preconditions (InvalidArgument): every point finite (the message names
/// the first bad index), options valid, min_inliers ≥ 3.
PlaneDetectionResult detect_planes(std::span<const Eigen::Vector3d> points,
                                   const PlaneDetectionOptions& options = {});

}  // namespace rove
