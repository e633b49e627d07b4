#pragma once
// Node storage of OccupancyOctree (internal).
//
// Nodes live in blocks of 8 siblings; a node is addressed by its id
// block * 8 + slot. Block 0 holds the root in slot 0 (its other slots are
// unused), so the root's id is 0. A node is 8 bytes: the float log-odds and
// the index of its children's block (kNoBlock for a leaf). Each block has
// two flag bytes: which of its 8 slots exist, and which were touched by the
// insertion running now ("dirty"; always clear between calls). Optional
// per-node channels (colour, statistics) are parallel arrays indexed by id.
//
// Blocks come from segments of kSegmentBlocks, allocated on demand and
// never moved, so node references stay valid while the tree grows. The
// table of segments has room for every segment from the start (1 MB of
// address space, touched only as segments are added), so it never moves
// either and threads may read it while another adds a segment. Freed
// blocks go to a free list. BlockAllocator hands out blocks to one thread:
// several allocators can work at once on disjoint subtrees, taking chunks of
// blocks from the store under a mutex.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "rove/maps/occupancy_octree.h"

namespace rove::detail {

inline constexpr std::uint32_t kNoBlock = 0xFFFFFFFFu;

struct OctreeNode {
  float log_odds;
  std::uint32_t children;  // block index, or kNoBlock
};

class OctreeStore {
 public:
  static constexpr unsigned kSegmentShift = 12;  // 4096 blocks = 32768 nodes a segment
  static constexpr std::uint32_t kSegmentBlocks = 1u << kSegmentShift;
  static constexpr std::uint32_t kMaxBlocks = 1u << 29;  // ids fit 32 bits

  OctreeStore(bool colors, bool statistics);
  OctreeStore(const OctreeStore& other);
  OctreeStore& operator=(const OctreeStore&) = delete;
  ~OctreeStore();

  bool has_colors() const noexcept { return colors_; }
  bool has_statistics() const noexcept { return statistics_; }

  OctreeNode& node(std::uint32_t id) noexcept { return seg(id >> 3).nodes[id & kIdMask]; }
  const OctreeNode& node(std::uint32_t id) const noexcept { return seg(id >> 3).nodes[id & kIdMask]; }
  std::uint8_t& exists(std::uint32_t block) noexcept { return seg(block).exists[block & kBlockMask]; }
  std::uint8_t exists(std::uint32_t block) const noexcept { return seg(block).exists[block & kBlockMask]; }
  std::uint8_t& dirty(std::uint32_t block) noexcept { return seg(block).dirty[block & kBlockMask]; }
  Rgb8& color(std::uint32_t id) noexcept { return seg(id >> 3).colors[id & kIdMask]; }
  const Rgb8& color(std::uint32_t id) const noexcept { return seg(id >> 3).colors[id & kIdMask]; }
  OctreeLeafStatistics& stats(std::uint32_t id) noexcept { return seg(id >> 3).stats[id & kIdMask]; }
  const OctreeLeafStatistics& stats(std::uint32_t id) const noexcept {
    return seg(id >> 3).stats[id & kIdMask];
  }

  bool root_exists() const noexcept { return (exists(0) & 1u) != 0; }
  bool child_exists(std::uint32_t block, unsigned slot) const noexcept {
    return ((exists(block) >> slot) & 1u) != 0;
  }

  // Blocks handed out so far minus those freed.
  std::size_t blocks_in_use() const noexcept { return fresh_ - free_.size(); }
  // Bytes of every segment allocated.
  std::size_t bytes() const noexcept;

  // Under the caller's mutex when several allocators run: up to `n` blocks,
  // appended to `out` (free ones first, then fresh ones).
  void take_blocks(std::size_t n, std::vector<std::uint32_t>& out);
  // Returns blocks to the free list (serial).
  void give_back(const std::vector<std::uint32_t>& blocks);
  // Drops everything but the root block, which becomes empty.
  void reset();

 private:
  static constexpr std::uint32_t kBlockMask = kSegmentBlocks - 1;
  static constexpr std::uint32_t kIdMask = kSegmentBlocks * 8 - 1;
  static constexpr std::size_t kMaxSegments = kMaxBlocks >> kSegmentShift;
  struct Segment {
    std::unique_ptr<OctreeNode[]> nodes;
    std::unique_ptr<std::uint8_t[]> exists;
    std::unique_ptr<std::uint8_t[]> dirty;
    std::unique_ptr<Rgb8[]> colors;
    std::unique_ptr<OctreeLeafStatistics[]> stats;
  };
  Segment& seg(std::uint32_t block) const noexcept { return *table_[block >> kSegmentShift]; }
  void add_segment();
  void drop_segments() noexcept;
  std::size_t segment_bytes() const noexcept;

  bool colors_;
  bool statistics_;
  std::unique_ptr<Segment*[]> table_;  // kMaxSegments entries, the first segments_ set
  std::size_t segments_ = 0;
  std::uint32_t fresh_ = 1;  // next block never handed out (block 0: the root's)
  std::vector<std::uint32_t> free_;
};

// Hands out blocks to one thread (see the file comment). `mutex` may be null
// when no other allocator runs.
class BlockAllocator {
 public:
  BlockAllocator(OctreeStore& store, std::mutex* mutex) : store_(&store), mutex_(mutex) {}
  ~BlockAllocator() { release(); }
  BlockAllocator(const BlockAllocator&) = delete;
  BlockAllocator& operator=(const BlockAllocator&) = delete;
  BlockAllocator(BlockAllocator&& o) noexcept
      : store_(o.store_), mutex_(o.mutex_), ready_(std::move(o.ready_)), freed_(std::move(o.freed_)) {}

  std::uint32_t allocate();
  void free(std::uint32_t block) { freed_.push_back(block); }
  // Returns unused and freed blocks to the store (under the mutex).
  void release();

 private:
  OctreeStore* store_;
  std::mutex* mutex_;
  std::vector<std::uint32_t> ready_;
  std::vector<std::uint32_t> freed_;
};

}  // namespace rove::detail
