#include "octree_update.h"

#include <algorithm>
#include <bit>
#include <limits>

namespace rove::detail {

namespace {
constexpr Rgb8 kWhite{255, 255, 255};
bool is_white(const Rgb8& c) noexcept { return c.r == 255 && c.g == 255 && c.b == 255; }
std::uint32_t saturating_inc(std::uint32_t v) noexcept {
  return v == std::numeric_limits<std::uint32_t>::max() ? v : v + 1;
}
}  // namespace

UpdateParams OctreeAccess::params(const OccupancyOctree& t) noexcept {
  UpdateParams p;
  p.hit = t.hit_;
  p.miss = t.miss_;
  p.clamp_min = t.clamp_min_;
  p.clamp_max = t.clamp_max_;
  p.threshold = t.threshold_;
  p.colors = has_channels(t.channels_, OctreeChannels::Color);
  p.statistics = has_channels(t.channels_, OctreeChannels::Statistics);
  p.change_detection = t.change_detection_;
  return p;
}

SubtreeUpdater::SubtreeUpdater(OctreeStore& store, BlockAllocator& alloc, const UpdateParams& params,
                               std::uint32_t root, int root_depth, bool root_fresh)
    : store_(&store), alloc_(&alloc), params_(params), root_depth_(root_depth), root_fresh_(root_fresh) {
  path_[root_depth] = root;
}

bool SubtreeUpdater::aborts(UpdateKind kind, float log_odds, float value) const noexcept {
  // OctoMap's early abort: a cell already at the clamp the update pushes
  // towards is not touched. Per-leaf statistics count every measurement, so
  // they go down to the cell.
  if (params_.statistics) return false;
  switch (kind) {
    case UpdateKind::Delta:
      return (value >= 0.0f && log_odds >= params_.clamp_max) || (value <= 0.0f && log_odds <= params_.clamp_min);
    case UpdateKind::ScanMiss:
      return log_odds <= params_.clamp_min;
    case UpdateKind::Set:
    case UpdateKind::ScanHit:
      return false;
  }
  return false;
}

void SubtreeUpdater::new_children(std::uint32_t parent, bool expand) {
  const std::uint32_t b = alloc_->allocate();
  OctreeNode& p = store_->node(parent);
  if (expand) {
    for (std::uint32_t i = 0; i < 8; ++i) {
      store_->node(b * 8 + i) = OctreeNode{p.log_odds, kNoBlock};
      if (params_.colors) store_->color(b * 8 + i) = store_->color(parent);
      if (params_.statistics) store_->stats(b * 8 + i) = store_->stats(parent);
    }
    store_->exists(b) = 0xFF;
    node_delta += 8;
    changed = true;
  } else {
    store_->exists(b) = 0;
  }
  store_->dirty(b) = 0;
  p.children = b;
}

SubtreeUpdater::Reached SubtreeUpdater::descend(const OctreeKey& key, int target_depth, UpdateKind kind,
                                                float value, bool may_abort) {
  int d = root_depth_;
  if (valid_ >= 0) {
    const unsigned diff = static_cast<unsigned>((key.x ^ last_.x) | (key.y ^ last_.y) | (key.z ^ last_.z));
    const int common = diff == 0 ? kOctreeDepth : kOctreeDepth - std::bit_width(diff);
    d = std::max(root_depth_, std::min({common, valid_, target_depth}));
  }
  last_ = key;
  std::uint32_t n = path_[d];
  bool fresh = d == root_depth_ && root_fresh_;
  bool was_dirty = ((store_->dirty(n >> 3) >> (n & 7u)) & 1u) != 0;
  while (d < target_depth) {
    if (store_->node(n).children == kNoBlock) {
      if (!fresh) {
        if (may_abort && aborts(kind, store_->node(n).log_odds, value)) {
          valid_ = d;
          return {n, false, false, true};
        }
        new_children(n, true);  // a pruned leaf: expand it
      } else {
        new_children(n, false);
      }
      if (d == root_depth_) root_fresh_ = false;
    }
    const std::uint32_t block = store_->node(n).children;
    const unsigned slot = octree_child_index(key, d);
    const auto bit = static_cast<std::uint8_t>(1u << slot);
    const std::uint32_t child = block * 8 + slot;
    std::uint8_t& ex = store_->exists(block);
    fresh = (ex & bit) == 0;
    if (fresh) {
      store_->node(child) = OctreeNode{0.0f, kNoBlock};
      if (params_.colors) store_->color(child) = kWhite;
      if (params_.statistics) store_->stats(child) = OctreeLeafStatistics{};
      ex = static_cast<std::uint8_t>(ex | bit);
      ++node_delta;
      changed = true;
    }
    std::uint8_t& dm = store_->dirty(block);
    was_dirty = (dm & bit) != 0;
    dm = static_cast<std::uint8_t>(dm | bit);
    n = child;
    path_[++d] = n;
  }
  valid_ = d;
  return {n, fresh, was_dirty, false};
}

std::uint32_t SubtreeUpdater::reach(const OctreeKey& key, int depth, bool& fresh) {
  const Reached r = descend(key, depth, UpdateKind::Set, 0.0f, false);
  fresh = r.fresh;
  return r.id;
}

void SubtreeUpdater::apply(const OctreeKey& key, UpdateKind kind, float value) {
  const bool dedup = kind == UpdateKind::ScanHit || kind == UpdateKind::ScanMiss;
  const Reached r = descend(key, kOctreeDepth, kind, value, true);
  if (r.aborted || (dedup && r.was_dirty)) return;
  update_leaf(r.id, key, kind, value, r.fresh);
}

void SubtreeUpdater::update_leaf(std::uint32_t id, const OctreeKey& key, UpdateKind kind, float value,
                                 bool fresh) {
  OctreeNode& n = store_->node(id);
  const bool positive = kind == UpdateKind::ScanHit || (kind == UpdateKind::Delta && value > 0.0f);
  (positive ? hit_updates : miss_updates) += 1;
  if (!fresh && aborts(kind, n.log_odds, value)) return;
  const bool occupied_before = n.log_odds >= params_.threshold;
  float v = n.log_odds;
  switch (kind) {
    case UpdateKind::Set: v = value; break;
    case UpdateKind::Delta: v += value; break;
    case UpdateKind::ScanHit: v += params_.hit; break;
    case UpdateKind::ScanMiss: v += params_.miss; break;
  }
  if (kind != UpdateKind::Set) {
    // OctoMap's updateNodeLogOdds.
    if (v < params_.clamp_min) {
      v = params_.clamp_min;
    } else if (v > params_.clamp_max) {
      v = params_.clamp_max;
    }
  }
  changed = changed || v != n.log_odds || params_.statistics;
  n.log_odds = v;
  if (params_.statistics && kind != UpdateKind::Set) {
    OctreeLeafStatistics& s = store_->stats(id);
    if (positive) {
      s.hits = saturating_inc(s.hits);
    } else {
      s.misses = saturating_inc(s.misses);
    }
  }
  if (params_.change_detection) {
    if (fresh) {
      changes.push_back({key, true});
    } else if (occupied_before != (v >= params_.threshold)) {
      changes.push_back({key, false});
    }
  }
}

Rgb8 average_child_color(const OctreeStore& store, std::uint32_t block) {
  int r = 0, g = 0, b = 0, c = 0;
  const std::uint8_t mask = store.exists(block);
  for (std::uint32_t i = 0; i < 8; ++i) {
    if (((mask >> i) & 1u) == 0) continue;
    const Rgb8& col = store.color(block * 8 + i);
    if (is_white(col)) continue;
    r += col.r, g += col.g, b += col.b, ++c;
  }
  if (c == 0) return kWhite;
  return Rgb8{static_cast<std::uint8_t>(r / c), static_cast<std::uint8_t>(g / c),
              static_cast<std::uint8_t>(b / c)};
}

bool prune_node(OctreeStore& store, BlockAllocator& alloc, const UpdateParams& params, std::uint32_t id) {
  OctreeNode& n = store.node(id);
  const std::uint32_t block = n.children;
  if (block == kNoBlock || store.exists(block) != 0xFF) return false;
  const OctreeNode& first = store.node(block * 8);
  for (std::uint32_t i = 0; i < 8; ++i) {
    const OctreeNode& c = store.node(block * 8 + i);
    if (c.children != kNoBlock || !(c.log_odds == first.log_odds)) return false;
    if (params.statistics && !(store.stats(block * 8 + i) == store.stats(block * 8))) return false;
  }
  n.log_odds = first.log_odds;
  if (params.colors) {
    store.color(id) = store.color(block * 8);
    if (!is_white(store.color(id))) store.color(id) = average_child_color(store, block);
  }
  if (params.statistics) store.stats(id) = store.stats(block * 8);
  n.children = kNoBlock;
  alloc.free(block);
  return true;
}

bool refresh_node(OctreeStore& store, BlockAllocator& alloc, const UpdateParams& params, std::uint32_t id,
                  bool prune) {
  if (prune && prune_node(store, alloc, params, id)) return true;
  OctreeNode& n = store.node(id);
  const std::uint32_t block = n.children;
  if (block == kNoBlock) return false;
  const std::uint8_t mask = store.exists(block);
  float m = -std::numeric_limits<float>::max();
  for (std::uint32_t i = 0; i < 8; ++i) {
    if (((mask >> i) & 1u) != 0) m = std::max(m, store.node(block * 8 + i).log_odds);
  }
  n.log_odds = m;
  if (params.colors) store.color(id) = average_child_color(store, block);
  return false;
}

bool LeafFinder::find(const OctreeKey& key, std::uint32_t& id, int& depth) {
  if (!store_->root_exists()) return false;
  int d = 0;
  if (valid_ >= 0) {
    const unsigned diff = static_cast<unsigned>((key.x ^ last_.x) | (key.y ^ last_.y) | (key.z ^ last_.z));
    const int common = diff == 0 ? kOctreeDepth : kOctreeDepth - std::bit_width(diff);
    if (diff == 0 || common >= valid_) {
      // Same path down to where the last search ended.
      if (diff == 0 || store_->node(path_[valid_]).children == kNoBlock) {
        if (!found_) return false;
        id = path_[valid_];
        depth = valid_;
        last_ = key;
        return true;
      }
    }
    d = std::min(common, valid_);
  }
  last_ = key;
  std::uint32_t n = path_[d];
  while (d < kOctreeDepth) {
    const std::uint32_t block = store_->node(n).children;
    if (block == kNoBlock) break;
    const unsigned slot = octree_child_index(key, d);
    if (!store_->child_exists(block, slot)) {
      valid_ = d;
      found_ = false;
      return false;
    }
    n = block * 8 + slot;
    path_[++d] = n;
  }
  valid_ = d;
  found_ = true;
  id = n;
  depth = d;
  return true;
}

std::int64_t finalize_subtree(OctreeStore& store, BlockAllocator& alloc, const UpdateParams& params,
                              std::uint32_t id, int depth, bool lazy, int stop_depth) {
  const std::uint32_t block = store.node(id).children;
  if (block == kNoBlock) return 0;
  std::uint8_t& dm = store.dirty(block);
  const std::uint8_t marked = dm;
  dm = 0;
  std::int64_t delta = 0;
  if (depth + 1 < stop_depth && depth + 1 < kOctreeDepth) {
    for (std::uint32_t i = 0; i < 8; ++i) {
      if (((marked >> i) & 1u) != 0) {
        delta += finalize_subtree(store, alloc, params, block * 8 + i, depth + 1, lazy, stop_depth);
      }
    }
  }
  if (!lazy && refresh_node(store, alloc, params, id, true)) delta -= 8;
  return delta;
}

bool ensure_root(OctreeStore& store, std::size_t& num_nodes) {
  store.dirty(0) = static_cast<std::uint8_t>(store.dirty(0) | 1u);
  if (store.root_exists()) return false;
  store.exists(0) = 1;
  store.node(0) = OctreeNode{0.0f, kNoBlock};
  if (store.has_colors()) store.color(0) = kWhite;
  if (store.has_statistics()) store.stats(0) = OctreeLeafStatistics{};
  ++num_nodes;
  return true;
}

void merge_changes(std::unordered_map<OctreeKey, bool, OctreeKeyHash>& map,
                   const std::vector<ChangeEvent>& events) {
  for (const ChangeEvent& e : events) {
    if (e.created) {
      map.emplace(e.key, true);
      continue;
    }
    const auto it = map.find(e.key);
    if (it == map.end()) {
      map.emplace(e.key, false);
    } else if (!it->second) {
      map.erase(it);
    }
  }
}

}  // namespace rove::detail
