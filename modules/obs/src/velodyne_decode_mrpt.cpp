#include "velodyne_decode_mrpt.h"

#include <array>
#include <cmath>
#include <numbers>

namespace rove::detail {

namespace {

struct SinCos {
  std::array<float, 36000> s, c;
};

// MRPT's table: angle i is −π + i · 2π / 35999; a hundredth-degree azimuth
// a is looked up at (a + 18000) mod 36000.
const SinCos& mrpt_table() {
  static const SinCos t = [] {
    SinCos v;
    for (int i = 0; i < 36000; ++i) {
      const double a = -std::numbers::pi + i * (2.0 * std::numbers::pi / 35999.0);
      v.s[static_cast<std::size_t>(i)] = static_cast<float>(std::sin(a));
      v.c[static_cast<std::size_t>(i)] = static_cast<float>(std::cos(a));
    }
    return v;
  }();
  return t;
}

}  // namespace

int mrpt_velodyne_azimuth(std::size_t lasers, int block, int pair, int laser, std::uint16_t azimuth, int step) {
  double t = 0.0, t0 = 0.0, t1 = 1.0;  // µs: this laser, its block, the next block
  if (lasers == 16) {
    t = static_cast<double>(static_cast<float>(pair) * 110.592f + static_cast<float>(laser) * 2.304f);
    t0 = static_cast<double>(static_cast<float>(pair) * 110.592f);
    t1 = static_cast<double>(static_cast<float>(pair + 1) * 110.592f);
  } else {
    t = block * 46.08 + laser * 1.152;
    t0 = block * 46.08;
    t1 = (block + 1) * 46.08;
  }
  const long adjustment = std::lrint(step * ((t - t0) / (t1 - t0)));  // half to even
  const float corrected = static_cast<float>(azimuth) + static_cast<float>(adjustment);
  return static_cast<int>(std::round(corrected)) % 36000;
}

bool mrpt_velodyne_point(std::uint16_t raw_distance, const VelodyneLaserCalibration& c, int azimuth,
                         float min_range, float max_range, float xyz[3]) {
  const float distance = static_cast<float>(raw_distance * 0.002f + c.distance_correction);
  if (distance < min_range || distance > max_range) return false;
  const float cos_v = static_cast<float>(c.cos_vert_correction), sin_v = static_cast<float>(c.sin_vert_correction);
  const float h = static_cast<float>(c.horizontal_offset_correction), v = static_cast<float>(c.vertical_offset_correction);
  float r = distance * cos_v;
  if (v != 0.0f) r += v * sin_v;
  const auto i = static_cast<std::size_t>((azimuth + 18000) % 36000);
  const float ca = mrpt_table().c[i], sa = mrpt_table().s[i];
  xyz[0] = r * ca + h * sa;
  xyz[1] = -(r * sa - h * ca);
  xyz[2] = distance * sin_v + v;
  return true;
}

}  // namespace rove::detail
