#pragma once
// Conversions between rove's images and OpenCV's (internal to rove::vision).

#include <opencv2/core.hpp>

#include "rove/obs/image.h"

namespace rove::detail {

// A gray 8-bit cv::Mat of an 8-bit image (RGB converted with OpenCV's
// weights 0.299, 0.587, 0.114; gray images are copied). Precondition:
// 8-bit, 1 or 3 channels, check() passes.
cv::Mat to_gray_mat(const Image& image);

}  // namespace rove::detail
