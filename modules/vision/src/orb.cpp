#include "rove/vision/orb.h"

#include <cstring>
#include <numbers>

#include <opencv2/features2d.hpp>

#include "cv_image.h"
#include "rove/core/check.h"

namespace rove {

void OrbOptions::check() const {
  ROVE_CHECK_GE(max_features, 1);
  ROVE_CHECK_GT(scale_factor, 1.0);
  ROVE_CHECK_GE(levels, 1);
  ROVE_CHECK_GE(fast_threshold, 1);
  ROVE_CHECK_GE(edge_threshold, 0);
}

Features extract_orb(const Image& image, const OrbOptions& options) {
  options.check();
  const cv::Mat gray = detail::to_gray_mat(image);
  cv::Ptr<cv::ORB> orb =
      cv::ORB::create(options.max_features, static_cast<float>(options.scale_factor), options.levels,
                      options.edge_threshold, 0, 2, cv::ORB::HARRIS_SCORE, 31,
                      options.fast_threshold);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  orb->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
  Features f;
  if (keypoints.empty()) return f;
  ROVE_CHECK_EQ(descriptors.cols, 32);
  ROVE_CHECK_EQ(static_cast<std::size_t>(descriptors.rows), keypoints.size());
  f.keypoints.reserve(keypoints.size());
  f.descriptors.resize(keypoints.size());
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const cv::KeyPoint& k = keypoints[i];
    f.keypoints.push_back({k.pt.x, k.pt.y, k.angle * std::numbers::pi / 180.0, k.octave,
                           k.response});
    std::memcpy(f.descriptors[i].data(), descriptors.ptr<std::uint8_t>(static_cast<int>(i)), 32);
  }
  return f;
}

}  // namespace rove
