#pragma once
// A textured room rendered by a pinhole camera at known poses, for the RGB-D
// SLAM tests.

#include <cmath>
#include <cstdint>
#include <limits>
#include <variant>
#include <vector>

#include "rove/math/se3.h"
#include "rove/obs/pinhole_camera.h"
#include "rove/vision/rgbd_frame.h"

namespace rove::rgbd_test {

// The room (world = the first camera's optical frame: x right, y down, z
// forward): a wall at z = 3, a floor at y = 1, side walls at x = ±1.6 and a
// ceiling at y = −1.2. Each plane is tiled with 6 cm cells of random gray.
struct Plane {
  int axis;      // 0 x, 1 y, 2 z
  double value;  // plane: p[axis] = value
};
inline constexpr Plane kPlanes[] = {{2, 3.0}, {1, 1.0}, {0, -1.6}, {0, 1.6}, {1, -1.2}};

inline std::uint8_t texture(int plane, const Eigen::Vector3d& p) {
  const int a = kPlanes[plane].axis;
  const double u = p[(a + 1) % 3], v = p[(a + 2) % 3];
  const auto cu = static_cast<std::int64_t>(std::floor(u / 0.06));
  const auto cv = static_cast<std::int64_t>(std::floor(v / 0.06));
  std::uint64_t h = static_cast<std::uint64_t>(cu * 73856093) ^ static_cast<std::uint64_t>(cv * 19349663) ^
                    static_cast<std::uint64_t>(plane * 83492791);
  h ^= h >> 13;
  h *= 0x9E3779B97F4A7C15ull;
  h ^= h >> 29;
  return static_cast<std::uint8_t>(30 + h % 200);
}

inline PinholeCamera test_camera() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = 525.0;
  c.fy = 525.0;
  c.cx = 319.5;
  c.cy = 239.5;
  return c;
}

// Renders the room, row v seen from pose_of_row(v) (a rolling shutter when
// it changes; depth 5000 per meter).
template <class PoseOfRow>
RgbdFrame render_rows(const PinholeCamera& cam, PoseOfRow pose_of_row, bool textureless = false) {
  RgbdFrame f;
  f.color = Image::zeros(cam.width, cam.height, 3, PixelType::U8);
  f.depth = DepthImage::zeros_u16(cam.width, cam.height, 5000.0);
  auto& depth = std::get<std::vector<std::uint16_t>>(f.depth.values);
  for (std::uint32_t v = 0; v < cam.height; ++v) {
    const SE3d T_world_camera = pose_of_row(v);
    const Eigen::Matrix3d R = T_world_camera.rotation_matrix();
    const Eigen::Vector3d o = T_world_camera.translation();
    for (std::uint32_t u = 0; u < cam.width; ++u) {
      const Eigen::Vector3d ray_c = cam.unproject(u, v);
      const Eigen::Vector3d ray_w = R * ray_c;
      double best = std::numeric_limits<double>::infinity();
      int plane = -1;
      for (int k = 0; k < 5; ++k) {
        const double d = ray_w[kPlanes[k].axis];
        if (std::abs(d) < 1e-12) continue;
        const double s = (kPlanes[k].value - o[kPlanes[k].axis]) / d;
        if (s > 0.0 && s < best) {
          best = s;
          plane = k;
        }
      }
      if (plane < 0) continue;
      const std::size_t i = static_cast<std::size_t>(v) * cam.width + u;
      const std::uint8_t g = textureless ? 128 : texture(plane, o + best * ray_w);
      for (int ch = 0; ch < 3; ++ch) f.color.data[3 * i + static_cast<std::size_t>(ch)] = g;
      depth[i] = static_cast<std::uint16_t>(std::lround(best * ray_c.z() * 5000.0));  // z, not range
      ++f.valid_depth_pixels;
    }
  }
  return f;
}

// Renders the room seen from T_world_camera (depth 5000 per meter).
inline RgbdFrame render(const PinholeCamera& cam, const SE3d& T_world_camera, bool textureless = false) {
  return render_rows(cam, [&](std::uint32_t) { return T_world_camera; }, textureless);
}

// A path that pans, rolls and moves 20 cm, then comes back near the start.
// `i` may be fractional (between frames).
inline SE3d true_pose(double i, std::size_t n) {
  const double s = std::sin(2.0 * M_PI * i / static_cast<double>(n));
  const double c = 1.0 - std::cos(2.0 * M_PI * i / static_cast<double>(n));
  Eigen::Matrix<double, 6, 1> xi;
  xi << 0.10 * s, 0.03 * c, 0.08 * c, 0.05 * c, 0.25 * s, 0.06 * s;
  return SE3d::exp(xi);
}

}  // namespace rove::rgbd_test
