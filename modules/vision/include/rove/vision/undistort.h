#pragma once
/// \file
/// Undistortion: pixels and images of a camera with Brown–Conrady
/// distortion mapped to the ideal pinhole camera with the same fx, fy, cx, cy
/// and no distortion.

#include <span>
#include <vector>

#include <Eigen/Core>

#include "rove/obs/image.h"
#include "rove/obs/pinhole_camera.h"

namespace rove {

/// The ideal (undistorted) pixel of each distorted pixel: with (a, b, 1) =
/// camera.unproject(u, v), (fx·a + cx, fy·b + cy). Throws NumericError where
/// the model cannot be inverted (see PinholeCamera::unproject).
/// Precondition (InvalidArgument): camera passes check(), pixels finite.
std::vector<Eigen::Vector2d> undistort_points(const PinholeCamera& camera,
                                              std::span<const Eigen::Vector2d> pixels);

/// The camera `camera` becomes after undistortion: same intrinsics, no
/// distortion.
PinholeCamera undistorted_camera(const PinholeCamera& camera);

/// The image the ideal camera would have taken: output pixel (u, v) samples
/// the input at camera.project(((u − cx)/fx, (v − cy)/fy, 1)) by bilinear
/// interpolation (the forward model, so no inversion is needed); pixels that
/// fall outside the input are 0. Any channel count; 8-bit, 16-bit or float
/// samples (integers rounded to nearest). Preconditions (InvalidArgument):
/// image.check() passes, camera passes check(), the camera's size is 0 or
/// the image's.
Image undistort_image(const Image& image, const PinholeCamera& camera);

}  // namespace rove
