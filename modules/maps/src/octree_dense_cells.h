#pragma once
// A dense set of finest cells over a box of keys (internal), to update each
// cell once per scan when the scan's rays fill a box compactly (a scan from
// one origin at a coarse resolution): one bit a cell, against the 2 bits in
// blocks of 128 bytes found through a hash table of CellSet
// (octree_cell_set.h), which stays for boxes too large to hold densely.
//
// The box is cut into blocks of 16 x 16 x 16 cells (the cells of a node at
// depth 12), stored in a dense 3D array; a block's 4,096 bits are in the
// octree's depth-first order (the Morton order of the cells). A cell's bit
// index is the sum of three table entries, one per axis, so marking a cell
// costs three loads, two additions and an OR, and needs no branch on the
// block the cell is in. Listing the cells in tree order sorts the non-empty
// blocks by their Morton code and reads each block's bits in order.
//
// A second, sparse layer tags cells (the occupied ends of rays): a tag page
// of 4,096 bits is allocated for a block when one of its cells is tagged.
// Sets over the same box (one per thread) are merged with an OR.
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "rove/maps/octree_key.h"

namespace rove::detail {

// The 16 low bits of v spread to every third bit, from bit 0.
inline std::uint64_t spread_bits3(std::uint64_t v) noexcept {
  v &= 0xFFFF;
  v = (v | (v << 16)) & 0x0000FF0000FFULL;
  v = (v | (v << 8)) & 0x00F00F00F00FULL;
  v = (v | (v << 4)) & 0x0C30C30C30C3ULL;
  v = (v | (v << 2)) & 0x249249249249ULL;
  return v;
}

// The Morton code of a finest cell: the bits of x, y and z interleaved, x
// lowest, so codes sort in the octree's depth-first order.
inline std::uint64_t morton_code(const OctreeKey& k) noexcept {
  return spread_bits3(k.x) | (spread_bits3(k.y) << 1) | (spread_bits3(k.z) << 2);
}

class DenseCellSet {
 public:
  static constexpr int kBlockShift = 4;                       // 16 cells a block per axis
  static constexpr int kBlockSide = 1 << kBlockShift;
  static constexpr std::size_t kBlockBits = std::size_t{1} << (3 * kBlockShift);
  static constexpr std::size_t kBlockWords = kBlockBits / 64;

  // Bytes of the bitmap over the box [lo, hi] (keys, inclusive).
  static std::size_t bytes_for(const OctreeKey& lo, const OctreeKey& hi) noexcept {
    std::size_t blocks = 1;
    for (int a = 0; a < 3; ++a) blocks *= static_cast<std::size_t>((hi[a] >> kBlockShift) - (lo[a] >> kBlockShift) + 1);
    return blocks * kBlockWords * sizeof(std::uint64_t);
  }

  // An empty set over the box [lo, hi]. Precondition: lo ≤ hi on each axis.
  DenseCellSet(const OctreeKey& lo, const OctreeKey& hi) {
    std::size_t blocks = 1;
    for (int a = 0; a < 3; ++a) {
      first_block_[a] = lo[a] >> kBlockShift;
      blocks_[a] = (hi[a] >> kBlockShift) - first_block_[a] + 1;
      base_[a] = first_block_[a] << kBlockShift;
      side_[a] = static_cast<unsigned>(blocks_[a]) << kBlockShift;
      blocks *= static_cast<std::size_t>(blocks_[a]);
    }
    // Block strides: x slowest, z fastest.
    const std::size_t stride[3] = {static_cast<std::size_t>(blocks_[1]) * static_cast<std::size_t>(blocks_[2]),
                                   static_cast<std::size_t>(blocks_[2]), 1};
    for (int a = 0; a < 3; ++a) {
      table_[a].resize(side_[a]);
      for (unsigned r = 0; r < side_[a]; ++r) {
        table_[a][r] = (r >> kBlockShift) * stride[a] * kBlockBits + (spread_bits3(r & (kBlockSide - 1)) << a);
      }
    }
    bits_.assign(blocks * kBlockWords, 0);
    tag_page_.assign(blocks, kNoPage);
  }

  // Marks and tags k; a key outside the box makes overflowed() true.
  void tag(const OctreeKey& k) {
    std::size_t bit = 0;
    if (!bit_of(k, bit)) return;
    bits_[bit >> 6] |= std::uint64_t{1} << (bit & 63u);
    const std::size_t block = bit / kBlockBits;
    if (tag_page_[block] == kNoPage) {
      tag_page_[block] = static_cast<std::uint32_t>(tags_.size() / kBlockWords);
      tags_.resize(tags_.size() + kBlockWords, 0);
    }
    tags_[std::size_t{tag_page_[block]} * kBlockWords + (bit % kBlockBits) / 64] |= std::uint64_t{1} << (bit & 63u);
  }

  // The walk_ray policy (octree_rays.h) that marks the cells a ray crosses.
  // A cell outside the box stops the walk and makes overflowed() true. It
  // keeps each axis's part of the current cell's bit index, so a step looks
  // up one table and checks one bound.
  class Marker {
   public:
    explicit Marker(DenseCellSet& set) noexcept
        : set_(&set),
          bits_(set.bits_.data()),
          t0_(set.table_[0].data()),
          t1_(set.table_[1].data()),
          t2_(set.table_[2].data()),
          side0_(set.side_[0]),
          side1_(set.side_[1]),
          side2_(set.side_[2]) {}
    bool start(const OctreeKey& k) noexcept {
      if (!set_->relative(k, r0_, r1_, r2_)) return false;
      a0_ = t0_[r0_], a1_ = t1_[r1_], a2_ = t2_[r2_];
      return true;
    }
    template <int Axis>
    [[gnu::always_inline]] bool advance(int step) noexcept {
      unsigned& r = Axis == 0 ? r0_ : (Axis == 1 ? r1_ : r2_);
      r += static_cast<unsigned>(step);
      if (r >= (Axis == 0 ? side0_ : (Axis == 1 ? side1_ : side2_))) [[unlikely]] {
        set_->overflowed_ = true;
        return false;
      }
      (Axis == 0 ? a0_ : (Axis == 1 ? a1_ : a2_)) = (Axis == 0 ? t0_ : (Axis == 1 ? t1_ : t2_))[r];
      return true;
    }
    bool at(const OctreeKey& k) const noexcept {
      unsigned r0 = 0, r1 = 0, r2 = 0;
      return set_->relative(k, r0, r1, r2) && r0 == r0_ && r1 == r1_ && r2 == r2_;
    }
    [[gnu::always_inline]] void visit(int) noexcept {
      const std::size_t bit = a0_ + a1_ + a2_;
      bits_[bit >> 6] |= std::uint64_t{1} << (bit & 63u);
    }

   private:
    DenseCellSet* set_;
    std::uint64_t* bits_;
    const std::size_t *t0_, *t1_, *t2_;
    unsigned side0_, side1_, side2_;
    unsigned r0_ = 0, r1_ = 0, r2_ = 0;
    std::size_t a0_ = 0, a1_ = 0, a2_ = 0;
  };

  // Whether some cell given to tag() or a Marker was outside the box.
  bool overflowed() const noexcept { return overflowed_; }
  // Words of the bitmap.
  std::size_t words() const noexcept { return bits_.size(); }
  // ORs the marks of `other` (a set over the same box) into this one, words
  // [begin, end) of the bitmap; tags are not merged.
  void merge_marks(const DenseCellSet& other, std::size_t begin, std::size_t end) noexcept {
    for (std::size_t i = begin; i < end; ++i) bits_[i] |= other.bits_[i];
    overflowed_ = overflowed_ || other.overflowed_;
  }

  // A non-empty block: its Morton code (the Morton code of its cells
  // without their 12 low bits) and its index.
  struct BlockRef {
    std::uint64_t code;
    std::uint32_t index;
  };
  // The non-empty blocks in tree order.
  std::vector<BlockRef> blocks_in_tree_order() const {
    std::vector<BlockRef> out;
    std::uint32_t b = 0;
    for (int bx = 0; bx < blocks_[0]; ++bx) {
      for (int by = 0; by < blocks_[1]; ++by) {
        for (int bz = 0; bz < blocks_[2]; ++bz, ++b) {
          const std::uint64_t* w = &bits_[std::size_t{b} * kBlockWords];
          if (std::all_of(w, w + kBlockWords, [](std::uint64_t x) { return x == 0; })) continue;
          const OctreeKey corner = block_corner(bx, by, bz);
          out.push_back({morton_code(corner) >> (3 * kBlockShift), b});
        }
      }
    }
    std::sort(out.begin(), out.end(), [](const BlockRef& a, const BlockRef& c) { return a.code < c.code; });
    return out;
  }

  // The key of the first cell of block `index`.
  OctreeKey block_corner(std::uint32_t index) const noexcept {
    const auto nz = static_cast<std::uint32_t>(blocks_[2]), ny = static_cast<std::uint32_t>(blocks_[1]);
    return block_corner(static_cast<int>(index / (nz * ny)), static_cast<int>((index / nz) % ny),
                        static_cast<int>(index % nz));
  }

  // Calls fn(key, tagged) for every marked cell of block `index`, in tree order.
  template <typename Fn>
  void for_each_in_block(std::uint32_t index, Fn&& fn) const {
    static const std::array<std::uint16_t, kBlockBits> kCell = cell_of_rank();
    const OctreeKey corner = block_corner(index);
    const std::uint64_t* w = &bits_[std::size_t{index} * kBlockWords];
    const std::uint64_t* t = tag_page_[index] == kNoPage ? nullptr : &tags_[std::size_t{tag_page_[index]} * kBlockWords];
    for (std::size_t i = 0; i < kBlockWords; ++i) {
      for (std::uint64_t m = w[i]; m != 0; m &= m - 1) {
        const unsigned bit = static_cast<unsigned>(std::countr_zero(m));
        const unsigned c = kCell[64 * i + bit];
        fn(OctreeKey{static_cast<std::uint16_t>(corner.x | (c & 15u)),
                     static_cast<std::uint16_t>(corner.y | ((c >> 4) & 15u)),
                     static_cast<std::uint16_t>(corner.z | (c >> 8))},
           t != nullptr && ((t[i] >> bit) & 1u) != 0);
      }
    }
  }

 private:
  static constexpr std::uint32_t kNoPage = 0xFFFFFFFFu;

  // k's offsets from the box's first cell; false (and overflowed()) outside.
  bool relative(const OctreeKey& k, unsigned& r0, unsigned& r1, unsigned& r2) noexcept {
    r0 = static_cast<unsigned>(k.x - base_[0]), r1 = static_cast<unsigned>(k.y - base_[1]),
    r2 = static_cast<unsigned>(k.z - base_[2]);
    if (r0 < side_[0] && r1 < side_[1] && r2 < side_[2]) return true;
    overflowed_ = true;
    return false;
  }
  bool relative(const OctreeKey& k, unsigned& r0, unsigned& r1, unsigned& r2) const noexcept {
    r0 = static_cast<unsigned>(k.x - base_[0]), r1 = static_cast<unsigned>(k.y - base_[1]),
    r2 = static_cast<unsigned>(k.z - base_[2]);
    return r0 < side_[0] && r1 < side_[1] && r2 < side_[2];
  }
  bool bit_of(const OctreeKey& k, std::size_t& bit) noexcept {
    unsigned r0 = 0, r1 = 0, r2 = 0;
    if (!relative(k, r0, r1, r2)) return false;
    bit = table_[0][r0] + table_[1][r1] + table_[2][r2];
    return true;
  }

  OctreeKey block_corner(int bx, int by, int bz) const noexcept {
    return {static_cast<std::uint16_t>((first_block_[0] + bx) << kBlockShift),
            static_cast<std::uint16_t>((first_block_[1] + by) << kBlockShift),
            static_cast<std::uint16_t>((first_block_[2] + bz) << kBlockShift)};
  }
  // x | y << 4 | z << 8 of the cell at each Morton rank of a block.
  static std::array<std::uint16_t, kBlockBits> cell_of_rank() {
    std::array<std::uint16_t, kBlockBits> t{};
    for (unsigned r = 0; r < kBlockBits; ++r) {
      unsigned c[3] = {0, 0, 0};
      for (int i = 0; i < kBlockShift; ++i) {
        for (int a = 0; a < 3; ++a) c[a] |= ((r >> (3 * i + a)) & 1u) << i;
      }
      t[r] = static_cast<std::uint16_t>(c[0] | (c[1] << 4) | (c[2] << 8));
    }
    return t;
  }

  int first_block_[3];   // block index of the box's first block, per axis
  int blocks_[3];        // blocks per axis
  int base_[3];          // key of the box's first cell, per axis
  unsigned side_[3];     // cells per axis
  std::vector<std::size_t> table_[3];  // per axis: cell offset -> part of the bit index
  std::vector<std::uint64_t> bits_;
  std::vector<std::uint32_t> tag_page_;  // per block: its tag page, or kNoPage
  std::vector<std::uint64_t> tags_;
  bool overflowed_ = false;
};

}  // namespace rove::detail
