#include "cv_image.h"

#include <opencv2/imgproc.hpp>

#include "rove/core/check.h"

namespace rove::detail {

cv::Mat to_gray_mat(const Image& image) {
  image.check();
  ROVE_CHECK_MSG(image.pixel_type == PixelType::U8 && (image.channels == 1 || image.channels == 3),
                 "expected an 8-bit gray or RGB image, got {} channels of type {}", image.channels,
                 static_cast<int>(image.pixel_type));
  const int rows = static_cast<int>(image.height), cols = static_cast<int>(image.width);
  // OpenCV only reads through this header: the const_cast never writes.
  cv::Mat view(rows, cols, image.channels == 1 ? CV_8UC1 : CV_8UC3,
               const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat gray;
  if (image.channels == 1) {
    gray = view.clone();
  } else {
    cv::cvtColor(view, gray, cv::COLOR_RGB2GRAY);
  }
  return gray;
}

}  // namespace rove::detail
