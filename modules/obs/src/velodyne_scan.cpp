#include "rove/obs/velodyne_scan.h"

#include <span>

#include "rove/core/check.h"
#include "rove/serialization/stl.h"
#include "rove/serialization/version.h"

namespace rove {
namespace {

// Block b starts at 100·b: header (2), azimuth (2), 32 returns of 3 bytes.
constexpr std::size_t kBlockBytes = 100;

std::uint16_t u16_at(const VelodynePacket& p, std::size_t i) {
  return static_cast<std::uint16_t>(p[i] | (p[i + 1] << 8));
}

}  // namespace

std::uint16_t velodyne_block_header(const VelodynePacket& p, std::size_t block) {
  ROVE_CHECK_LT(block, kVelodyneBlocksPerPacket);
  return u16_at(p, block * kBlockBytes);
}

std::uint16_t velodyne_block_azimuth(const VelodynePacket& p, std::size_t block) {
  ROVE_CHECK_LT(block, kVelodyneBlocksPerPacket);
  return u16_at(p, block * kBlockBytes + 2);
}

std::uint16_t velodyne_return_distance(const VelodynePacket& p, std::size_t block,
                                       std::size_t ret) {
  ROVE_CHECK_LT(block, kVelodyneBlocksPerPacket);
  ROVE_CHECK_LT(ret, kVelodyneReturnsPerBlock);
  return u16_at(p, block * kBlockBytes + 4 + 3 * ret);
}

std::uint8_t velodyne_return_intensity(const VelodynePacket& p, std::size_t block,
                                       std::size_t ret) {
  ROVE_CHECK_LT(block, kVelodyneBlocksPerPacket);
  ROVE_CHECK_LT(ret, kVelodyneReturnsPerBlock);
  return p[block * kBlockBytes + 4 + 3 * ret + 2];
}

std::uint32_t velodyne_gps_timestamp(const VelodynePacket& p) {
  constexpr std::size_t at = kVelodyneBlocksPerPacket * kBlockBytes;
  return static_cast<std::uint32_t>(p[at]) | (static_cast<std::uint32_t>(p[at + 1]) << 8) |
         (static_cast<std::uint32_t>(p[at + 2]) << 16) |
         (static_cast<std::uint32_t>(p[at + 3]) << 24);
}

void save(OutArchive& ar, const VelodynePointCloud& c) {
  write_version(ar, 1);
  save(ar, c.x);
  save(ar, c.y);
  save(ar, c.z);
  save(ar, c.intensity);
  ar.write_length(c.timestamp.size(), "timestamp");
  for (const Timestamp& t : c.timestamp) ar.write_scalar(t.ns);
  save(ar, c.azimuth);
  save(ar, c.laser_id);
  save(ar, c.points_for_laser_id);
}

void load(InArchive& ar, VelodynePointCloud& c) {
  read_version(ar, "VelodynePointCloud", 1);
  load(ar, c.x);
  load(ar, c.y);
  load(ar, c.z);
  load(ar, c.intensity);
  const std::uint32_t n = ar.read_length("timestamp", sizeof(std::int64_t));
  c.timestamp.assign(n, Timestamp{});
  for (Timestamp& t : c.timestamp) t.ns = ar.read_scalar<std::int64_t>("timestamp");
  load(ar, c.azimuth);
  load(ar, c.laser_id);
  load(ar, c.points_for_laser_id);
}

bool operator==(const VelodyneScan& a, const VelodyneScan& b) {
  return a.header_equals(b) && a.min_range_m == b.min_range_m && a.max_range_m == b.max_range_m &&
         a.packets == b.packets && a.calibration == b.calibration &&
         a.point_cloud == b.point_cloud && a.has_satellite_timestamp == b.has_satellite_timestamp;
}

void VelodyneScan::save_payload(OutArchive& ar) const {
  save_header(ar);
  ar.write_scalar(min_range_m);
  ar.write_scalar(max_range_m);
  ar.write_length(packets.size(), "packets");
  for (const VelodynePacket& p : packets) {
    ar.write_bytes(std::as_bytes(std::span<const std::uint8_t>(p.data(), p.size())));
  }
  ar.write_length(calibration.size(), "calibration");
  for (const VelodyneLaserCalibration& c : calibration) {
    for (double v : {c.azimuth_correction, c.vertical_correction, c.distance_correction,
                     c.vertical_offset_correction, c.horizontal_offset_correction,
                     c.sin_vert_correction, c.cos_vert_correction, c.sin_vert_offset_correction,
                     c.cos_vert_offset_correction}) {
      ar.write_scalar(v);
    }
  }
  save(ar, point_cloud);
  ar.write_scalar(has_satellite_timestamp);
}

void VelodyneScan::load_payload(InArchive& ar, std::uint8_t /*version 1*/) {
  load_header(ar);
  min_range_m = ar.read_scalar<double>("min_range");
  max_range_m = ar.read_scalar<double>("max_range");
  const std::uint32_t np = ar.read_length("packets", kVelodynePacketBytes);
  packets.assign(np, VelodynePacket{});
  for (VelodynePacket& p : packets) {
    ar.read_bytes(std::as_writable_bytes(std::span<std::uint8_t>(p.data(), p.size())), "packets");
  }
  const std::uint32_t nc = ar.read_length("calibration", 9 * sizeof(double));
  calibration.assign(nc, VelodyneLaserCalibration{});
  for (VelodyneLaserCalibration& c : calibration) {
    for (double* v : {&c.azimuth_correction, &c.vertical_correction, &c.distance_correction,
                      &c.vertical_offset_correction, &c.horizontal_offset_correction,
                      &c.sin_vert_correction, &c.cos_vert_correction,
                      &c.sin_vert_offset_correction, &c.cos_vert_offset_correction}) {
      *v = ar.read_scalar<double>("calibration");
    }
  }
  load(ar, point_cloud);
  has_satellite_timestamp = ar.read_scalar<bool>("has_satellite_timestamp");
}

}  // namespace rove
