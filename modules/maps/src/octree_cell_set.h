#pragma once
// A set of finest cells (internal), to update each cell once per scan:
// bitmaps of 8 x 8 x 8 cells (the cells of one node at depth 13) found
// through an open-addressing hash table on the block's coordinates. Each
// cell has a second bit, the tag (an occupied end of a ray). A ray visits
// about eight cells per block, so most queries hit the block of the
// previous one (kept in a Cursor) and cost a bit test.
//
// The cells are then listed in the octree's depth-first order (Morton order
// of the blocks, then of the cells in a block), so the tree is updated
// along a path that moves a level or two between consecutive cells.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <vector>

#include "rove/maps/octree_key.h"

namespace rove::detail {

class CellSet {
  static constexpr std::uint64_t kNone = ~std::uint64_t{0};
  static constexpr std::size_t kChunkBlocks = 1024;

 public:
  struct Block {
    std::uint64_t marked[8];
    std::uint64_t tagged[8];
  };
  // The block a caller's last query fell in. Valid until clear().
  struct Cursor {
    std::uint64_t id = kNone;
    Block* block = nullptr;
  };

  // Adds `k` (and tags it if `tag`); true if it was not in the set.
  [[gnu::always_inline]] bool insert(const OctreeKey& k, Cursor& c, bool tag = false) {
    const std::uint64_t id = block_of(k);
    if (id != c.id) [[unlikely]] {
      // A small direct-mapped cache of recent blocks before the table: rays
      // from one origin come back to the same blocks.
      Recent& r = recent_[(id * 0x9e3779b97f4a7c15ULL) >> 56];
      if (r.id != id) r = Recent{id, find_or_add(id)};
      c.block = r.block;
      c.id = id;
    }
    const unsigned bit = (k.x & 7u) | ((k.y & 7u) << 3) | ((k.z & 7u) << 6);
    const std::uint64_t mask = std::uint64_t{1} << (bit & 63u);
    if (tag) c.block->tagged[bit >> 6] |= mask;
    std::uint64_t& word = c.block->marked[bit >> 6];
    if ((word & mask) != 0) return false;
    word |= mask;
    return true;
  }
  bool insert(const OctreeKey& k, bool tag = false) { return insert(k, cursor_, tag); }

  // Calls fn(key, tagged) for every cell, in the octree's depth-first order.
  template <typename Fn>
  void for_each_in_tree_order(Fn&& fn) const {
    static const std::array<std::uint16_t, 512> kRank = bit_to_morton();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> order;  // (Morton code, block number)
    order.reserve(ids_.size());
    for (std::uint32_t b = 0; b < ids_.size(); ++b) order.emplace_back(morton_of_block(ids_[b]), b);
    std::sort(order.begin(), order.end());
    std::uint32_t cells[512];  // Morton rank << 16 | bit
    for (const auto& [code, b] : order) {
      const Block& blk = block(b);
      std::size_t n = 0;
      for (unsigned w = 0; w < 8; ++w) {
        for (std::uint64_t m = blk.marked[w]; m != 0; m &= m - 1) {
          const unsigned bit = 64 * w + static_cast<unsigned>(std::countr_zero(m));
          cells[n++] = (std::uint32_t{kRank[bit]} << 16) | bit;
        }
      }
      std::sort(cells, cells + n);
      const std::uint64_t id = ids_[b];
      const unsigned bx = static_cast<unsigned>(id & 0x1FFF) << 3, by = static_cast<unsigned>((id >> 13) & 0x1FFF) << 3,
                     bz = static_cast<unsigned>(id >> 26) << 3;
      for (std::size_t i = 0; i < n; ++i) {
        const unsigned bit = cells[i] & 0xFFFFu;
        const OctreeKey k{static_cast<std::uint16_t>(bx | (bit & 7u)), static_cast<std::uint16_t>(by | ((bit >> 3) & 7u)),
                          static_cast<std::uint16_t>(bz | (bit >> 6))};
        fn(k, ((blk.tagged[bit >> 6] >> (bit & 63u)) & 1u) != 0);
      }
    }
  }

  void clear() {
    ids_.clear();
    recent_.fill(Recent{});
    std::fill(table_.begin(), table_.end(), Slot{});
    cursor_ = Cursor{};
  }

 private:
  struct Slot {
    std::uint64_t id = kNone;
    std::uint32_t number = 0;
  };

  static std::uint64_t block_of(const OctreeKey& k) noexcept {
    return std::uint64_t{static_cast<std::uint32_t>(k.x >> 3)} |
           (std::uint64_t{static_cast<std::uint32_t>(k.y >> 3)} << 13) |
           (std::uint64_t{static_cast<std::uint32_t>(k.z >> 3)} << 26);
  }
  // Interleaves x, y, z bits (x lowest): the octree's child order.
  static std::uint64_t morton_of_block(std::uint64_t id) noexcept {
    std::uint64_t m = 0;
    for (unsigned i = 0; i < 13; ++i) {
      m |= ((id >> i) & 1u) << (3 * i);
      m |= ((id >> (13 + i)) & 1u) << (3 * i + 1);
      m |= ((id >> (26 + i)) & 1u) << (3 * i + 2);
    }
    return m;
  }
  // The Morton rank of each cell of a block (bit index x | y << 3 | z << 6).
  static std::array<std::uint16_t, 512> bit_to_morton() {
    std::array<std::uint16_t, 512> t{};
    for (unsigned bit = 0; bit < 512; ++bit) {
      const unsigned x = bit & 7u, y = (bit >> 3) & 7u, z = bit >> 6;
      unsigned m = 0;
      for (unsigned i = 0; i < 3; ++i) {
        m |= ((x >> i) & 1u) << (3 * i);
        m |= ((y >> i) & 1u) << (3 * i + 1);
        m |= ((z >> i) & 1u) << (3 * i + 2);
      }
      t[bit] = static_cast<std::uint16_t>(m);
    }
    return t;
  }
  std::size_t home(std::uint64_t id) const noexcept {
    return static_cast<std::size_t>((id * 0x9e3779b97f4a7c15ULL) >> 20) & (table_.size() - 1);
  }
  Block& block(std::uint32_t number) const noexcept { return chunks_[number / kChunkBlocks][number % kChunkBlocks]; }
  [[gnu::noinline]] Block* find_or_add(std::uint64_t id) {
    if (2 * (ids_.size() + 1) > table_.size()) grow();
    for (std::size_t i = home(id);; i = (i + 1) & (table_.size() - 1)) {
      Slot& s = table_[i];
      if (s.id == id) return &block(s.number);
      if (s.id == kNone) {
        s.id = id;
        s.number = static_cast<std::uint32_t>(ids_.size());
        if (s.number / kChunkBlocks == chunks_.size()) chunks_.push_back(std::make_unique<Block[]>(kChunkBlocks));
        ids_.push_back(id);
        Block& b = block(s.number);
        b = Block{};
        return &b;
      }
    }
  }
  void grow() {
    std::vector<Slot> old = std::move(table_);
    table_.assign(old.empty() ? 1024 : 2 * old.size(), Slot{});
    for (const Slot& s : old) {
      if (s.id == kNone) continue;
      std::size_t i = home(s.id);
      while (table_[i].id != kNone) i = (i + 1) & (table_.size() - 1);
      table_[i] = s;
    }
  }

  std::vector<std::unique_ptr<Block[]>> chunks_;  // blocks never move: cursors keep pointers
  std::vector<std::uint64_t> ids_;               // block number -> block coordinates
  std::vector<Slot> table_;
  Cursor cursor_;
  struct Recent {
    std::uint64_t id = kNone;
    Block* block = nullptr;
  };
  std::array<Recent, 256> recent_{};
};

}  // namespace rove::detail
