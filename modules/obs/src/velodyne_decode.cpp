#include "rove/obs/velodyne_decode.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "rove/core/check.h"
#include "velodyne_decode_mrpt.h"

namespace rove {

namespace {

constexpr std::uint16_t kUpperBank = 0xEEFF;
constexpr std::uint8_t kDualReturn = 0x39;
constexpr std::size_t kModeByte = 1204;

// The packet's azimuth step (hundredths of a degree) between consecutive
// blocks, or pairs of blocks in dual mode: the element `rank` of the sorted
// differences (MRPT takes the 7th smallest; the median is rank n / 2).
int azimuth_step(const VelodynePacket& p, bool dual, bool mrpt) {
  const std::size_t stride = dual ? 2 : 1, n = kVelodyneBlocksPerPacket - stride;
  std::array<int, kVelodyneBlocksPerPacket> d{};
  for (std::size_t i = 0; i < n; ++i) {
    d[i] = (36000 + velodyne_block_azimuth(p, i + stride) - velodyne_block_azimuth(p, i)) % 36000;
  }
  const std::size_t rank = mrpt ? kVelodyneBlocksPerPacket / 2 : n / 2;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(rank), d.begin() + static_cast<std::ptrdiff_t>(n));
  return d[rank];
}

// Firing time of a return within its block as a fraction of the block:
// VLP-16 (16 lasers): firing sequence `firing` (0, 1) of 55.296 µs, lasers
// 2.304 µs apart, 110.592 µs a block; HDL-32E: lasers 1.152 µs apart,
// 46.08 µs a block (the manuals' timing tables).
double firing_fraction(std::size_t lasers, int firing, int laser) {
  if (lasers == 16) return (firing * 55.296 + laser * 2.304) / 110.592;
  return laser * 1.152 / 46.08;
}

// The point of one return in double (VelodyneDecoding::Full); false when
// its distance is outside [min_range, max_range].
bool full_point(std::uint16_t raw, const VelodyneLaserCalibration& c, double azimuth_rad, double min_range,
                double max_range, float xyz[3]) {
  const double d = raw * 0.002 + c.distance_correction;
  if (d < min_range || d > max_range) return false;
  const double v = c.vertical_offset_correction, h = c.horizontal_offset_correction;
  const double r = d * c.cos_vert_correction + v * c.sin_vert_correction;
  const double ca = std::cos(azimuth_rad), sa = std::sin(azimuth_rad);
  xyz[0] = static_cast<float>(r * ca + h * sa);
  xyz[1] = static_cast<float>(-(r * sa - h * ca));
  xyz[2] = static_cast<float>(d * c.sin_vert_correction + v);
  return true;
}

struct Decoder {
  const VelodyneScan& scan;
  const VelodyneDecodeOptions& options;
  VelodyneDecodeResult& out;
  std::size_t lasers;
  double min_range, max_range;

  void push(const float xyz[3], std::uint8_t intensity, double azimuth_rad, int laser) {
    VelodynePointCloud& c = out.cloud;
    c.x.push_back(xyz[0]);
    c.y.push_back(xyz[1]);
    c.z.push_back(xyz[2]);
    c.intensity.push_back(intensity);
    c.azimuth.push_back(static_cast<float>(azimuth_rad));
    c.laser_id.push_back(static_cast<std::int16_t>(laser));
  }

  void block(const VelodynePacket& p, int b, bool dual, int step) {
    const bool mrpt = options.decoding == VelodyneDecoding::Mrpt;
    const bool second = dual && (b & 1) != 0, last = dual && (b & 1) == 0;
    const std::uint16_t azimuth = velodyne_block_azimuth(p, static_cast<std::size_t>(b));
    const int returns = mrpt ? 16 : static_cast<int>(kVelodyneReturnsPerBlock);
    for (int k = 0; k < returns; ++k) {
      const auto kk = static_cast<std::size_t>(k), bb = static_cast<std::size_t>(b);
      const std::uint16_t raw = velodyne_return_distance(p, bb, kk);
      if (raw == 0) continue;
      ++out.returns;
      if (second && (raw == velodyne_return_distance(p, bb - 1, kk) || !options.keep_strongest)) continue;
      if (last && !options.keep_last) continue;
      const int laser = k % static_cast<int>(lasers), firing = k / static_cast<int>(lasers);
      const VelodyneLaserCalibration& cal = scan.calibration[static_cast<std::size_t>(laser)];
      float xyz[3];
      double alpha = 0.0;
      if (mrpt) {
        const int a = detail::mrpt_velodyne_azimuth(lasers, b, dual ? b / 2 : b, laser, azimuth, step);
        if (!detail::mrpt_velodyne_point(raw, cal, a, static_cast<float>(min_range), static_cast<float>(max_range),
                                         xyz)) {
          continue;
        }
        alpha = a * (std::numbers::pi / 18000.0);
      } else {
        const double a = azimuth + step * firing_fraction(lasers, firing, laser);
        alpha = std::fmod(a, 36000.0) * (std::numbers::pi / 18000.0);
        if (!full_point(raw, cal, alpha, min_range, max_range, xyz)) continue;
      }
      push(xyz, velodyne_return_intensity(p, bb, kk), alpha, laser);
    }
  }

  void run() {
    const bool mrpt = options.decoding == VelodyneDecoding::Mrpt;
    for (const VelodynePacket& p : scan.packets) {
      const bool dual = p[kModeByte] == kDualReturn;
      const int step = azimuth_step(p, dual, mrpt);
      for (int b = 0; b < static_cast<int>(kVelodyneBlocksPerPacket); ++b) {
        if (velodyne_block_header(p, static_cast<std::size_t>(b)) != kUpperBank) {
          ++out.skipped_blocks;
          continue;
        }
        block(p, b, dual, step);
      }
    }
  }
};

}  // namespace

VelodyneDecodeResult decode_velodyne_scan(const VelodyneScan& scan, const VelodyneDecodeOptions& options) {
  ROVE_CHECK_MSG(options.min_range_m >= 0.0 && options.max_range_m >= 0.0,
                 "Velodyne decoding: ranges must be >= 0, got min {} m, max {} m", options.min_range_m,
                 options.max_range_m);
  VelodyneDecodeResult r;
  const std::size_t lasers = scan.calibration.size();
  if (scan.packets.empty()) {
    r.message = "no packets";
    return r;
  }
  if (lasers == 0) {
    r.termination = VelodyneDecodeTermination::NoCalibration;
    r.message = fmt::format(
        "the scan holds {} raw packets but no per-laser calibration (MRPT's VelodyneCalibration, from the sensor's "
        "calibration file, e.g. VLP16.xml or HDL32.xml), which decoding needs",
        scan.packets.size());
    return r;
  }
  if (lasers != 16 && lasers != 32) {
    r.termination = VelodyneDecodeTermination::UnsupportedCalibration;
    r.message = fmt::format("a calibration of {} lasers: rove decodes the VLP-16 (16) and the HDL-32E (32)", lasers);
    return r;
  }
  Decoder d{scan, options, r, lasers, std::max(options.min_range_m, scan.min_range_m),
            std::min(options.max_range_m, scan.max_range_m)};
  d.run();
  r.message = fmt::format("{} points from {} returns of {} packets{}", r.cloud.x.size(), r.returns,
                          scan.packets.size(),
                          r.skipped_blocks > 0 ? fmt::format(" ({} blocks skipped: not upper bank)", r.skipped_blocks)
                                               : std::string());
  return r;
}

}  // namespace rove
