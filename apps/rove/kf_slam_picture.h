#pragma once
/// \file
/// PNG picture of an EKF-SLAM run (`rove kf-slam`), seen from above: the
/// ground-truth path (gray) and landmarks (green crosses) when known, the
/// estimated path (blue), and every mapped landmark (red dot) inside its
/// position-uncertainty ellipse (the x-y marginal at `quantiles` standard
/// deviations, orange). A palette PNG.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/slam/kf_slam_run.h"

namespace rove::cli {

/// What a landmark picture shows (map frame, meters).
struct LandmarkPicture {
  /// One mapped landmark: its mean and x-y covariance (m²).
  struct Mark {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  };
  std::vector<Eigen::Vector2d> truth_path;      ///< gray
  std::vector<Eigen::Vector2d> path;            ///< blue
  std::vector<Eigen::Vector2d> true_landmarks;  ///< green crosses
  std::vector<Mark> landmarks;                  ///< red dots in orange ellipses
  std::vector<Eigen::Vector2d> samples;         ///< single purple pixels (particles, samples)
};

/// Writes `picture` to `path` atomically as a square palette PNG of
/// `size_px` pixels, ellipses at `quantiles` standard deviations. Throws
/// InvalidArgument if size_px is outside [64, 8192], IoError if the file
/// cannot be written.
void write_landmark_picture(const LandmarkPicture& picture, double quantiles,
                            const std::string& path, int size_px = 900);

/// Writes `path` atomically as a square picture of `size_px` pixels.
/// Throws InvalidArgument if size_px is outside [64, 8192], IoError if the
/// file cannot be written.
void write_kf_slam_picture(const KfSlamResult& result, double quantiles, const std::string& path,
                           int size_px = 900);

}  // namespace rove::cli
