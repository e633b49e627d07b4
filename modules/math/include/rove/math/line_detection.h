#pragma once
/// \file
/// Lines in 2D point sets (laser scans, projected clouds): least-squares
/// (PCA) line fit, the RANSAC problem for one line, and detection of several
/// lines by sequential RANSAC. Points are std::vector<Eigen::Vector2d> (or
/// any contiguous range of them, as std::span), in any one frame and in
/// meters; results are in the same frame.

#include <cmath>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/math/ransac.h"
#include "rove/math/sequential_detection.h"

namespace rove {

/// An infinite line {p : n·p + d = 0} with unit normal n. Canonical sign:
/// d ≤ 0 (n points from the origin towards the line); for a line through
/// the origin (d = 0) the largest-magnitude component of n is positive.
struct Line2 {
  /// Unit normal n.
  Eigen::Vector2d normal = Eigen::Vector2d::UnitY();
  /// Offset d (m): n·p + d = 0 on the line; −d ≥ 0 is the distance from the
  /// origin to the line.
  double offset = 0.0;

  /// Signed distance n·p + d (m) of a point; positive on the side n points to.
  double signed_distance(const Eigen::Vector2d& p) const { return normal.dot(p) + offset; }
  /// Unit direction along the line, n rotated by +90°.
  Eigen::Vector2d direction() const { return {-normal.y(), normal.x()}; }
};

/// Total-least-squares line of ≥ 2 points: through the centroid, along the
/// eigenvector of the largest eigenvalue of the scatter matrix. Returns
/// nullopt when fewer than 2 points are given or all coincide.
/// Precondition (InvalidArgument): all points finite.
std::optional<Line2> fit_line(std::span<const Eigen::Vector2d> points);

/// RansacProblem for one line: minimal sample of 2 points, distance
/// |n·p + d| (m), refit by fit_line() on the inliers.
struct LineRansacProblem {
  using Model = Line2;
  using Datum = Eigen::Vector2d;

  /// 2.
  std::size_t sample_size() const { return 2; }
  /// True if the 2 points coincide (up to a relative 1e-12).
  bool is_degenerate(std::span<const Datum> sample) const;
  /// Appends the line through the 2 points (none if they coincide).
  void fit(std::span<const Datum> sample, std::vector<Model>& models) const;
  /// Unsigned point-to-line distance (m).
  double distance(const Model& line, const Datum& p) const {
    return std::abs(line.signed_distance(p));
  }
  /// Replaces `line` by fit_line(inliers); false if that has no solution.
  bool refit(std::span<const Datum> inliers, Model& line) const;
};

/// Options of detect_lines(); ransac.distance_threshold is in meters.
using LineDetectionOptions = SequentialDetectionOptions;
/// Outcome of detect_lines(): lines (with their inlier indices) in the order
/// found, unassigned points, termination reason.
using LineDetectionResult = SequentialDetectionResult<Line2>;

/// Detects up to options.max_models lines by sequential RANSAC, as
/// detect_planes() does for planes.
/// Preconditions (InvalidArgument): every point finite (the message names
/// the first bad index), options valid, min_inliers ≥ 2.
LineDetectionResult detect_lines(std::span<const Eigen::Vector2d> points,
                                 const LineDetectionOptions& options = {});

}  // namespace rove
