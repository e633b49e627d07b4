#pragma once
/// \file
/// OctoMap's files, byte-compatible with OctoMap 1.9:
///  - `.bt` (binary): a text header (`# Octomap OcTree binary file`, `id`,
///    `size` = nodes, `res` = resolution printed as `%g`, `data`) then, in
///    depth-first pre-order, one record per inner node: 2 bits per child
///    (children 0..3 in the first byte, 4..7 in the second, child i at bits
///    2i, 2i+1): 00 unknown, 10 free leaf, 01 occupied leaf, 11 inner node.
///    Leaves read back at the clamping bounds (clamping_min for free,
///    clamping_max for occupied), inner nodes as the maximum of their
///    children, the root at clamping_max (as OctoMap reads it). OctoMap's
///    older headerless format (int32 3, f64 resolution, u32 size) is read
///    too.
///  - `.ot` (full): the same header with `# Octomap OcTree file`, then every
///    node in pre-order: f32 log-odds, for `ColorOcTree` three colour bytes
///    (r, g, b), and a byte whose bit i says child i exists.
/// Both are little-endian. The sensor model is not stored: readers take it
/// as a parameter (OctoMap's defaults by default).
///
/// Malformed input (a wrong first line, a header without `id`, `res` or
/// `data`, a resolution ≤ 0, a tree deeper than 16 levels, a node count
/// other than `size`, truncated data, bytes after the tree, a non-finite
/// log-odds, an `.ot` tree type other than OcTree and ColorOcTree) is a
/// ParseError naming the source, the byte offset and the field.

#include <cstdint>
#include <string>
#include <string_view>

#include "rove/maps/occupancy_octree.h"

namespace rove {

/// The two formats.
enum class OctreeFileFormat : std::uint8_t {
  Binary = 0,  ///< `.bt`
  Full = 1,    ///< `.ot`
};

/// What a `.bt` holds.
enum class OctreeBinaryContent : std::uint8_t {
  /// The tree as it is (OctoMap's writeBinaryConst).
  AsIs = 0,
  /// The tree converted to its maximum-likelihood map and pruned first, on
  /// a copy: the smallest file (OctoMap's writeBinary).
  MaxLikelihood = 1,
};

/// The header of an OctoMap file.
struct OctreeFileHeader {
  OctreeFileFormat format = OctreeFileFormat::Binary;  ///< from the first line
  std::string id;                  ///< tree type, e.g. "OcTree", "ColorOcTree"
  std::uint64_t size = 0;          ///< nodes
  double resolution = 0.0;         ///< meters
  std::size_t data_offset = 0;     ///< where the nodes start
  bool legacy = false;             ///< OctoMap's headerless `.bt`
};

/// Reads the header of `bytes` (`source` names them in errors).
OctreeFileHeader parse_octree_header(std::string_view bytes, const std::string& source);

/// Parses a `.bt` or `.ot` file held in `bytes` (told apart by the first
/// line). A ColorOcTree file gives a tree with the Color channel (from a
/// `.bt`, which stores no colours, every node white), so that it writes
/// back as it was read.
OccupancyOctree parse_octree(std::string_view bytes, const std::string& source,
                             const OccupancyOctreeParams& params = {});

/// Reads a `.bt` or `.ot` file. Throws IoError if it cannot be read,
/// ResourceError if its header asks for more memory than the budget.
OccupancyOctree read_octree(const std::string& path, const OccupancyOctreeParams& params = {});

/// The `.bt` bytes of `tree` (id "ColorOcTree" for a tree with colours, as
/// OctoMap's ColorOcTree writes it, else "OcTree").
std::string octree_binary_bytes(const OccupancyOctree& tree,
                                OctreeBinaryContent content = OctreeBinaryContent::AsIs);

/// The `.ot` bytes of `tree` (ColorOcTree when it has colours).
std::string octree_full_bytes(const OccupancyOctree& tree);

/// Writes `tree` to `path` atomically (rove/core/files.h) in `format`.
void write_octree(const std::string& path, const OccupancyOctree& tree, OctreeFileFormat format,
                  OctreeBinaryContent content = OctreeBinaryContent::AsIs);

}  // namespace rove
