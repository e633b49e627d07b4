#pragma once
/// \file
/// ORB features (Rublee, Rabaud, Konolige, Bradski, "ORB: an efficient
/// alternative to SIFT or SURF", ICCV 2011): FAST corners on an image
/// pyramid, oriented by the intensity centroid, with 256-bit rotated BRIEF
/// descriptors. Extraction is OpenCV's cv::ORB.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rove/obs/image.h"

namespace rove {

/// A 256-bit binary descriptor.
using OrbDescriptor = std::array<std::uint8_t, 32>;

/// A detected keypoint.
struct Keypoint {
  /// Pixel position in the full-resolution image (column u, row v).
  double u = 0.0;
  double v = 0.0;
  /// Orientation, radians (OpenCV's angle converted).
  double angle = 0.0;
  /// Pyramid level it was found on (0 = full resolution).
  int octave = 0;
  /// Corner response (larger is stronger).
  double response = 0.0;
};

/// Keypoints with one descriptor each.
struct Features {
  std::vector<Keypoint> keypoints;        ///< the keypoints
  std::vector<OrbDescriptor> descriptors; ///< descriptors[i] describes keypoints[i]
};

/// Options of extract_orb (OpenCV's ORB parameters).
struct OrbOptions {
  /// Most features kept (best responses), ≥ 1. Default 1000.
  int max_features = 1000;
  /// Pyramid scale step, > 1. Default 1.2.
  double scale_factor = 1.2;
  /// Pyramid levels, ≥ 1. Default 8.
  int levels = 8;
  /// FAST threshold, intensity levels, ≥ 1. Default 20.
  int fast_threshold = 20;
  /// Border without features, pixels, ≥ 0. Default 31 (the patch size).
  int edge_threshold = 31;

  /// Throws InvalidArgument naming the first field out of range.
  void check() const;
};

/// ORB features of an 8-bit gray or RGB image (RGB is converted to gray
/// first). A textureless image gives no features, not an error.
/// Preconditions (InvalidArgument): image 8-bit with 1 or 3 channels and
/// passes check(), options valid.
Features extract_orb(const Image& image, const OrbOptions& options = {});

}  // namespace rove
