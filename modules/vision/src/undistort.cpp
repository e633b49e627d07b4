#include "rove/vision/undistort.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "rove/core/check.h"

namespace rove {
namespace {

double read_sample(const Image& image, std::size_t index) {
  switch (image.pixel_type) {
    case PixelType::U8: return image.data[index];
    case PixelType::U16: {
      std::uint16_t v = 0;
      std::memcpy(&v, image.data.data() + 2 * index, 2);
      return v;
    }
    case PixelType::F32: {
      float v = 0.0f;
      std::memcpy(&v, image.data.data() + 4 * index, 4);
      return v;
    }
  }
  return 0.0;
}

void write_sample(Image& image, std::size_t index, double value) {
  switch (image.pixel_type) {
    case PixelType::U8:
      image.data[index] = static_cast<std::uint8_t>(std::clamp(std::round(value), 0.0, 255.0));
      return;
    case PixelType::U16: {
      const auto v = static_cast<std::uint16_t>(std::clamp(std::round(value), 0.0, 65535.0));
      std::memcpy(image.data.data() + 2 * index, &v, 2);
      return;
    }
    case PixelType::F32: {
      const auto v = static_cast<float>(value);
      std::memcpy(image.data.data() + 4 * index, &v, 4);
      return;
    }
  }
}

}  // namespace

std::vector<Eigen::Vector2d> undistort_points(const PinholeCamera& camera,
                                              std::span<const Eigen::Vector2d> pixels) {
  camera.check();
  std::vector<Eigen::Vector2d> out;
  out.reserve(pixels.size());
  for (const Eigen::Vector2d& p : pixels) {
    const Eigen::Vector3d ray = camera.unproject(p.x(), p.y());
    out.emplace_back(camera.fx * ray.x() + camera.cx, camera.fy * ray.y() + camera.cy);
  }
  return out;
}

PinholeCamera undistorted_camera(const PinholeCamera& camera) {
  PinholeCamera ideal = camera;
  ideal.distortion = {};
  return ideal;
}

Image undistort_image(const Image& image, const PinholeCamera& camera) {
  image.check();
  camera.check();
  ROVE_CHECK_MSG(camera.width == 0 || (camera.width == image.width && camera.height == image.height),
                 "undistort_image: camera {}x{} does not match the image's {}x{}", camera.width,
                 camera.height, image.width, image.height);
  Image out = Image::zeros(image.width, image.height, image.channels, image.pixel_type);
  const std::size_t c = image.channels;
  const double w = image.width, h = image.height;
  for (std::uint32_t v = 0; v < image.height; ++v) {
    for (std::uint32_t u = 0; u < image.width; ++u) {
      const Eigen::Vector3d ray((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
      const Eigen::Vector2d src = camera.project(ray);
      // Bilinear weights of the four neighbours; outside the image: left 0.
      if (!(src.x() >= 0.0 && src.y() >= 0.0 && src.x() <= w - 1.0 && src.y() <= h - 1.0)) continue;
      const auto x0 = static_cast<std::size_t>(std::min(std::floor(src.x()), std::max(w - 2.0, 0.0)));
      const auto y0 = static_cast<std::size_t>(std::min(std::floor(src.y()), std::max(h - 2.0, 0.0)));
      const std::size_t x1 = std::min<std::size_t>(x0 + 1, image.width - 1);
      const std::size_t y1 = std::min<std::size_t>(y0 + 1, image.height - 1);
      const double fx = src.x() - static_cast<double>(x0), fy = src.y() - static_cast<double>(y0);
      const std::size_t out_index = (static_cast<std::size_t>(v) * image.width + u) * c;
      for (std::size_t k = 0; k < c; ++k) {
        const auto at = [&](std::size_t x, std::size_t y) {
          return read_sample(image, (y * image.width + x) * c + k);
        };
        const double value = (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) +
                             fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
        write_sample(out, out_index + k, value);
      }
    }
  }
  return out;
}

}  // namespace rove
