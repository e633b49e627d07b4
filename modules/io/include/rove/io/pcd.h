#pragma once
/// \file
/// PCD files (PCL's Point Cloud Data format, versions 0.5 to 0.7): reading
/// and writing rove::PointCloud in the three encodings `ascii`, `binary`
/// (one record per point, fields in header order) and `binary_compressed`
/// (LZF-compressed, fields stored one after another: all x, then all y, ...,
/// padding fields named `_` left out; preceded by two little-endian uint32:
/// compressed and uncompressed size).
///
/// Fields mapped to the cloud: x y z (required, count 1, any numeric type),
/// rgb or rgba (4 bytes, PCL's packed 0x00RRGGBB / 0xAARRGGBB, stored as F or
/// U; alpha is dropped) -> colors, intensity -> intensities, normal_x
/// normal_y normal_z (all three) -> normals. Every other field (curvature,
/// labels, descriptors, `_` padding) is skipped by its declared size.
/// NaN coordinates are kept (PCL's "not dense" clouds).
///
/// Malformed input raises rove::ParseError naming the file, the line (header
/// and ascii data) or byte offset (binary data) and the field. Sizes declared
/// in the header are checked against the bytes actually present before
/// anything is allocated from them.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rove/maps/point_cloud.h"

namespace rove {

/// Encoding of the point data.
enum class PcdFormat : std::uint8_t { Ascii, Binary, BinaryCompressed };

/// One column of a PCD file.
struct PcdField {
  std::string name;       ///< e.g. "x", "rgb", "_" for padding
  std::uint32_t size = 4; ///< bytes per element: 1, 2, 4 or 8
  char type = 'F';        ///< 'F' float, 'I' signed, 'U' unsigned
  std::uint32_t count = 1;///< elements per point
  friend bool operator==(const PcdField&, const PcdField&) = default;
};

/// The header of a PCD file.
struct PcdHeader {
  std::string version = "0.7";
  std::vector<PcdField> fields;
  std::uint32_t width = 0;   ///< points per row (organized) or the point count
  std::uint32_t height = 1;  ///< rows; 1 for an unorganized cloud
  /// Sensor pose: tx ty tz qw qx qy qz (PCL's sensor_origin_/orientation_).
  std::array<double, 7> viewpoint{0, 0, 0, 1, 0, 0, 0};
  std::uint64_t points = 0;  ///< width * height
  PcdFormat format = PcdFormat::Ascii;
};

/// Reads a PCD file. If `header` is not null it receives the file's header.
/// Throws IoError if the file cannot be read, ParseError if it is malformed.
PointCloud read_pcd(const std::string& path, PcdHeader* header = nullptr);
/// Reads PCD data held in memory; `source` names it in errors.
PointCloud read_pcd_from_memory(std::span<const std::uint8_t> data, std::string_view source,
                                PcdHeader* header = nullptr);

/// Options of write_pcd.
struct PcdWriteOptions {
  PcdFormat format = PcdFormat::BinaryCompressed;
  /// Write each channel the cloud has (colors as PCL's "rgb" F 4 packed
  /// 0x00RRGGBB, "intensity" F 4, "normal_x normal_y normal_z" F 4).
  bool write_colors = true;
  bool write_intensity = true;
  bool write_normals = true;
  /// Organized layout (width, height); 0 means width = size(), height = 1.
  /// If set, width * height must equal the cloud's size.
  std::uint32_t width = 0, height = 0;
};

/// Writes `cloud` as PCD. ascii writes the shortest text that reads back to
/// the same float, so every encoding round-trips exactly. Throws IoError if
/// the file cannot be written.
void write_pcd(const std::string& path, const PointCloud& cloud, const PcdWriteOptions& options = {});
/// As write_pcd, into memory.
std::vector<std::uint8_t> write_pcd_to_memory(const PointCloud& cloud, const PcdWriteOptions& options = {});

}  // namespace rove
