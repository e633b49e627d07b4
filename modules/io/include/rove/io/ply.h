#pragma once
/// \file
/// PLY files (Stanford polygon format) as point clouds: reading and writing
/// the `vertex` element in `ascii`, `binary_little_endian` and
/// `binary_big_endian`.
///
/// Vertex properties mapped to the cloud: x y z (required, any numeric
/// type), red green blue (integer types taken as 0..255 and clamped; float
/// types as 0..1 scaled by 255) -> colors, intensity or scalar_intensity ->
/// intensities, nx ny nz (or normal_x normal_y normal_z) -> normals. Other
/// vertex properties, list properties and every other element (faces, edges,
/// ...) are read past by their declared types and ignored.
///
/// Malformed input raises rove::ParseError naming the file, the line (header
/// and ascii data) or byte offset (binary data) and the element/property.
/// Declared counts are checked against the bytes present before anything is
/// allocated from them.

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "rove/maps/point_cloud.h"

namespace rove {

/// Encoding of a PLY file.
enum class PlyFormat : std::uint8_t { Ascii, BinaryLittleEndian, BinaryBigEndian };

/// Reads the vertices of a PLY file. Throws IoError if the file cannot be
/// read, ParseError if it is malformed.
PointCloud read_ply(const std::string& path);
/// Reads PLY data held in memory; `source` names it in errors.
PointCloud read_ply_from_memory(std::span<const std::uint8_t> data, std::string_view source);

/// Options of write_ply.
struct PlyWriteOptions {
  PlyFormat format = PlyFormat::BinaryLittleEndian;
  bool write_colors = true;     ///< uchar red green blue, if the cloud has colors
  bool write_intensity = true;  ///< float intensity, if the cloud has it
  bool write_normals = true;    ///< float nx ny nz, if the cloud has normals
};

/// Writes `cloud` as a PLY vertex element (float x y z ...). ascii writes the
/// shortest text that reads back to the same float: every encoding
/// round-trips exactly. Throws IoError if the file cannot be written.
void write_ply(const std::string& path, const PointCloud& cloud, const PlyWriteOptions& options = {});
/// As write_ply, into memory.
std::vector<std::uint8_t> write_ply_to_memory(const PointCloud& cloud, const PlyWriteOptions& options = {});

}  // namespace rove
