#pragma once
/// \file
/// OctreeKey: the integer address of a cell of an OccupancyOctree, as
/// OctoMap's OcTreeKey. The tree has 16 levels below its root; a key holds,
/// per axis, the index of a finest cell counted from the tree's lower edge:
/// key = floor(coordinate / resolution) + 32768, so the tree spans
/// [−32768, 32768) · resolution meters on each axis, centred on the origin.
/// The same key addresses the node that contains the cell at any coarser
/// depth (its low bits are ignored there).

#include <compare>
#include <cstdint>
#include <functional>

namespace rove {

/// Levels below the root: a leaf at depth 16 is a finest cell.
inline constexpr int kOctreeDepth = 16;
/// Key of the cell whose lower corner is the origin (OctoMap's tree_max_val).
inline constexpr int kOctreeKeyOffset = 32768;

/// Integer coordinates of a finest cell (see the file comment).
struct OctreeKey {
  std::uint16_t x = 0;  ///< cell index along x
  std::uint16_t y = 0;  ///< cell index along y
  std::uint16_t z = 0;  ///< cell index along z
  /// Component `axis` (0 = x, 1 = y, 2 = z). Precondition: axis in [0, 3).
  std::uint16_t operator[](int axis) const noexcept { return axis == 0 ? x : (axis == 1 ? y : z); }
  /// Mutable component `axis`.
  std::uint16_t& operator[](int axis) noexcept { return axis == 0 ? x : (axis == 1 ? y : z); }
  /// Lexicographic (x, y, z) order and equality.
  friend auto operator<=>(const OctreeKey&, const OctreeKey&) = default;
  /// The key packed into 48 bits: x | y << 16 | z << 32.
  std::uint64_t packed() const noexcept {
    return std::uint64_t{x} | (std::uint64_t{y} << 16) | (std::uint64_t{z} << 32);
  }
  /// Inverse of packed().
  static OctreeKey unpack(std::uint64_t p) noexcept {
    return {static_cast<std::uint16_t>(p & 0xFFFF), static_cast<std::uint16_t>((p >> 16) & 0xFFFF),
            static_cast<std::uint16_t>((p >> 32) & 0xFFFF)};
  }
};

/// Which of the 8 children of a node at depth `depth` (0 = root) contains
/// `key`: bit 0 from x, bit 1 from y, bit 2 from z (OctoMap's order).
/// Precondition: depth in [0, 16).
inline unsigned octree_child_index(const OctreeKey& key, int depth) noexcept {
  const int bit = kOctreeDepth - 1 - depth;
  return ((key.x >> bit) & 1u) | (((key.y >> bit) & 1u) << 1) | (((key.z >> bit) & 1u) << 2);
}

/// `key` with the bits below depth `depth` cleared: the lower-corner key of
/// the node at that depth that contains it. Precondition: depth in [0, 16].
inline OctreeKey octree_key_at_depth(const OctreeKey& key, int depth) noexcept {
  const unsigned shift = static_cast<unsigned>(kOctreeDepth - depth);
  const unsigned mask = shift >= 16 ? 0u : (0xFFFFu << shift) & 0xFFFFu;
  return {static_cast<std::uint16_t>(key.x & mask), static_cast<std::uint16_t>(key.y & mask),
          static_cast<std::uint16_t>(key.z & mask)};
}

/// Hash of a key (for unordered containers).
struct OctreeKeyHash {
  /// The hash.
  std::size_t operator()(const OctreeKey& k) const noexcept {
    return std::hash<std::uint64_t>{}(k.packed() * 0x9e3779b97f4a7c15ULL);
  }
};

}  // namespace rove
