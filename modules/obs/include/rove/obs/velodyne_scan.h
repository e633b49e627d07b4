#pragma once
/// \file
/// VelodyneScan: the raw UDP data packets of one Velodyne revolution with
/// the sensor's per-laser calibration (MRPT's CObservationVelodyneScan), and
/// the point cloud if one was decoded and stored with it.
///
/// Packet layout (Velodyne HDL-32E/VLP-16 manuals, 1206-byte data packet):
/// 12 blocks of {u16 header 0xEEFF/0xDDFF, u16 azimuth in 0.01°, 32 returns of
/// (u16 distance in 2 mm units, u8 intensity)}, then u32 GPS time (µs since
/// the top of the hour), u8 return mode (0x37 strongest, 0x38 last, 0x39
/// dual), u8 model (0x21 HDL-32E, 0x22 VLP-16). Multi-byte fields are
/// little-endian.

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "rove/obs/observation.h"
#include "rove/serialization/archive.h"

namespace rove {

/// Bytes of one Velodyne data packet.
inline constexpr std::size_t kVelodynePacketBytes = 1206;
/// Blocks per data packet.
inline constexpr std::size_t kVelodyneBlocksPerPacket = 12;
/// Laser returns per block.
inline constexpr std::size_t kVelodyneReturnsPerBlock = 32;

/// One raw data packet, as received.
using VelodynePacket = std::array<std::uint8_t, kVelodynePacketBytes>;

/// Header of block `block` (0xEEFF upper bank, 0xDDFF lower bank).
/// Precondition (InvalidArgument): block < 12.
std::uint16_t velodyne_block_header(const VelodynePacket& p, std::size_t block);
/// Azimuth of block `block`, hundredths of a degree (0..35999).
std::uint16_t velodyne_block_azimuth(const VelodynePacket& p, std::size_t block);
/// Distance of return `ret` of block `block`, in 2 mm units.
/// Preconditions: block < 12, ret < 32.
std::uint16_t velodyne_return_distance(const VelodynePacket& p, std::size_t block,
                                       std::size_t ret);
/// Intensity of return `ret` of block `block`.
std::uint8_t velodyne_return_intensity(const VelodynePacket& p, std::size_t block,
                                       std::size_t ret);
/// GPS time stamp of the packet, microseconds since the top of the hour.
std::uint32_t velodyne_gps_timestamp(const VelodynePacket& p);

/// Calibration of one laser (MRPT's VelodyneCalibration::PerLaserCalib), as
/// MRPT stores it: angles in degrees, distances in meters, the sine and
/// cosine of the vertical angle, and the vertical offset times them.
/// decode_velodyne_scan (velodyne_decode.h) uses it.
struct VelodyneLaserCalibration {
  double azimuth_correction = 0.0;            ///< degrees
  double vertical_correction = 0.0;           ///< degrees
  double distance_correction = 0.0;           ///< m
  double vertical_offset_correction = 0.0;    ///< m
  double horizontal_offset_correction = 0.0;  ///< m
  double sin_vert_correction = 0.0;           ///< sin(vertical_correction)
  double cos_vert_correction = 1.0;           ///< cos(vertical_correction)
  double sin_vert_offset_correction = 0.0;    ///< vertical offset · sin, by MRPT
  double cos_vert_offset_correction = 1.0;    ///< vertical offset · cos, by MRPT
  /// Exact equality.
  friend bool operator==(const VelodyneLaserCalibration&,
                         const VelodyneLaserCalibration&) = default;
};

/// A decoded point cloud in the sensor frame (meters), one entry per point;
/// the per-point vectors other than x, y, z, intensity are empty when not
/// generated.
struct VelodynePointCloud {
  std::vector<float> x;                  ///< m
  std::vector<float> y;                  ///< m
  std::vector<float> z;                  ///< m
  std::vector<std::uint8_t> intensity;   ///< 0..255
  std::vector<Timestamp> timestamp;      ///< per point
  std::vector<float> azimuth;            ///< rad, per point
  std::vector<std::int16_t> laser_id;    ///< ring number, per point
  /// For each laser id, the indices of its points.
  std::vector<std::vector<std::uint64_t>> points_for_laser_id;
  /// Exact equality.
  friend bool operator==(const VelodynePointCloud&, const VelodynePointCloud&) = default;
};

/// Writes a VelodynePointCloud (versioned record).
void save(OutArchive& ar, const VelodynePointCloud& c);
/// Reads a VelodynePointCloud written by save.
void load(InArchive& ar, VelodynePointCloud& c);

/// One revolution of raw Velodyne data.
class VelodyneScan final : public ObservationOf<VelodyneScan> {
 public:
  /// Stored class name: "VelodyneScan".
  static constexpr std::string_view kClassName = "VelodyneScan";

  /// Shortest valid range, meters.
  double min_range_m = 1.0;
  /// Longest valid range, meters.
  double max_range_m = 130.0;
  /// The data packets in arrival order.
  std::vector<VelodynePacket> packets;
  /// Calibration, one entry per laser (empty if not stored).
  std::vector<VelodyneLaserCalibration> calibration;
  /// The decoded points, if stored (all vectors empty otherwise).
  VelodynePointCloud point_cloud;
  /// True if `timestamp` comes from a GNSS clock.
  bool has_satellite_timestamp = false;

  /// No packets.
  VelodyneScan() = default;

  /// Exact equality of every field.
  friend bool operator==(const VelodyneScan& a, const VelodyneScan& b);

  /// The newest record version this build writes.
  std::uint8_t version() const override { return 1; }
  /// Writes the fields (Serializable contract).
  void save_payload(OutArchive& ar) const override;
  /// Reads fields written by save_payload; ParseError on malformed data.
  void load_payload(InArchive& ar, std::uint8_t version) override;
};

}  // namespace rove
