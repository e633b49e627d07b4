#include "octree_store.h"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>

#include "rove/core/error.h"

namespace rove::detail {

OctreeStore::OctreeStore(bool colors, bool statistics)
    : colors_(colors),
      statistics_(statistics),
      table_(std::make_unique_for_overwrite<Segment*[]>(kMaxSegments)) {
  reset();
}

OctreeStore::OctreeStore(const OctreeStore& other)
    : colors_(other.colors_),
      statistics_(other.statistics_),
      table_(std::make_unique_for_overwrite<Segment*[]>(kMaxSegments)),
      fresh_(other.fresh_),
      free_(other.free_) {
  try {
    for (std::size_t s = 0; s < other.segments_; ++s) {
      add_segment();
      const Segment& from = *other.table_[s];
      Segment& to = *table_[s];
      // Only blocks handed out hold defined values.
      const std::size_t first = s * kSegmentBlocks;
      const std::size_t used = fresh_ > first ? std::min<std::size_t>(fresh_ - first, kSegmentBlocks) : 0;
      std::memcpy(to.nodes.get(), from.nodes.get(), used * 8 * sizeof(OctreeNode));
      std::memcpy(to.exists.get(), from.exists.get(), used);
      std::memcpy(to.dirty.get(), from.dirty.get(), used);
      if (colors_) std::copy_n(from.colors.get(), used * 8, to.colors.get());
      if (statistics_) std::copy_n(from.stats.get(), used * 8, to.stats.get());
    }
  } catch (...) {
    drop_segments();
    throw;
  }
}

OctreeStore::~OctreeStore() { drop_segments(); }

void OctreeStore::drop_segments() noexcept {
  for (std::size_t s = 0; s < segments_; ++s) delete table_[s];
  segments_ = 0;
}

std::size_t OctreeStore::segment_bytes() const noexcept {
  std::size_t per_block = 8 * sizeof(OctreeNode) + 2;
  if (colors_) per_block += 8 * sizeof(Rgb8);
  if (statistics_) per_block += 8 * sizeof(OctreeLeafStatistics);
  return per_block * kSegmentBlocks;
}

std::size_t OctreeStore::bytes() const noexcept {
  return segments_ * (segment_bytes() + sizeof(Segment) + sizeof(Segment*)) +
         free_.capacity() * sizeof(std::uint32_t);
}

void OctreeStore::add_segment() {
  if (segments_ == kMaxSegments) {
    throw ResourceError(fmt::format("octree: more than {} node blocks", kMaxBlocks));
  }
  auto s = std::make_unique<Segment>();
  // Not value-initialized: pages are only touched as blocks are handed out.
  s->nodes = std::make_unique_for_overwrite<OctreeNode[]>(kSegmentBlocks * 8);
  s->exists = std::make_unique_for_overwrite<std::uint8_t[]>(kSegmentBlocks);
  s->dirty = std::make_unique_for_overwrite<std::uint8_t[]>(kSegmentBlocks);
  if (colors_) s->colors = std::make_unique_for_overwrite<Rgb8[]>(kSegmentBlocks * 8);
  if (statistics_) s->stats = std::make_unique_for_overwrite<OctreeLeafStatistics[]>(kSegmentBlocks * 8);
  table_[segments_] = s.release();
  ++segments_;
}

void OctreeStore::take_blocks(std::size_t n, std::vector<std::uint32_t>& out) {
  while (n > 0 && !free_.empty()) {
    out.push_back(free_.back());
    free_.pop_back();
    --n;
  }
  if (n == 0) return;
  for (std::size_t i = 0; i < n; ++i) {
    if ((fresh_ >> kSegmentShift) >= segments_) add_segment();
    out.push_back(fresh_++);
  }
}

void OctreeStore::give_back(const std::vector<std::uint32_t>& blocks) {
  free_.insert(free_.end(), blocks.begin(), blocks.end());
}

void OctreeStore::reset() {
  drop_segments();
  free_.clear();
  free_.shrink_to_fit();
  fresh_ = 1;
  add_segment();
  exists(0) = 0;
  dirty(0) = 0;
  node(0) = OctreeNode{0.0f, kNoBlock};
  if (colors_) color(0) = Rgb8{255, 255, 255};
  if (statistics_) stats(0) = OctreeLeafStatistics{};
}

std::uint32_t BlockAllocator::allocate() {
  if (!freed_.empty()) {
    const std::uint32_t b = freed_.back();
    freed_.pop_back();
    return b;
  }
  if (ready_.empty()) {
    constexpr std::size_t kChunk = 64;
    if (mutex_ != nullptr) {
      std::lock_guard lock(*mutex_);
      store_->take_blocks(kChunk, ready_);
    } else {
      store_->take_blocks(kChunk, ready_);
    }
    std::reverse(ready_.begin(), ready_.end());  // hand out in increasing order
  }
  const std::uint32_t b = ready_.back();
  ready_.pop_back();
  return b;
}

void BlockAllocator::release() {
  if (store_ == nullptr || (ready_.empty() && freed_.empty())) return;
  if (mutex_ != nullptr) {
    std::lock_guard lock(*mutex_);
    store_->give_back(ready_);
    store_->give_back(freed_);
  } else {
    store_->give_back(ready_);
    store_->give_back(freed_);
  }
  ready_.clear();
  freed_.clear();
}

}  // namespace rove::detail
