#include "rove/maps/occupancy_octree.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "octree_rays.h"
#include "octree_store.h"
#include "octree_update.h"
#include "rove/core/check.h"
#include "rove/core/error.h"

namespace rove {

using detail::kNoBlock;
using detail::OctreeAccess;
using detail::OctreeStore;

bool octree_resolution_valid(double resolution) noexcept {
  return std::isnormal(resolution) && resolution > 0.0 && std::isfinite(1.0 / resolution) &&
         std::isfinite(resolution * 2.0 * kOctreeKeyOffset);
}

float octree_log_odds(double probability) noexcept {
  return static_cast<float>(std::log(probability / (1.0 - probability)));
}

double octree_probability(double log_odds) noexcept { return 1.0 - (1.0 / (1.0 + std::exp(log_odds))); }

void OccupancyOctreeParams::check() const {
  for (const double p : {prob_hit, prob_miss, clamping_min, clamping_max, occupancy_threshold}) {
    ROVE_CHECK_MSG(p > 0.0 && p < 1.0, "octree probabilities must be in (0, 1), got {}", p);
  }
  ROVE_CHECK_MSG(prob_hit >= 0.5, "prob_hit must be >= 0.5 (a hit raises the occupancy), got {}", prob_hit);
  ROVE_CHECK_MSG(prob_miss <= 0.5, "prob_miss must be <= 0.5 (a miss lowers the occupancy), got {}", prob_miss);
  ROVE_CHECK_MSG(clamping_min <= clamping_max, "clamping_min ({}) must be <= clamping_max ({})", clamping_min,
                 clamping_max);
}

OccupancyOctreeParams OccupancyOctreeParams::from_config(const ConfigSection& s) {
  OccupancyOctreeParams p;
  p.occupancy_threshold = s.get_in_range("occupancyThres", p.occupancy_threshold, 1e-9, 1.0 - 1e-9);
  p.prob_hit = s.get_in_range("probHit", p.prob_hit, 0.5, 1.0 - 1e-9);
  p.prob_miss = s.get_in_range("probMiss", p.prob_miss, 1e-9, 0.5);
  p.clamping_min = s.get_in_range("clampingThresMin", p.clamping_min, 1e-9, 1.0 - 1e-9);
  p.clamping_max = s.get_in_range("clampingThresMax", p.clamping_max, 1e-9, 1.0 - 1e-9);
  if (p.clamping_min > p.clamping_max) {
    s.fail("clampingThresMin", fmt::format("{} is above clampingThresMax ({})", p.clamping_min, p.clamping_max));
  }
  return p;
}

OccupancyOctree::OccupancyOctree(double resolution, OccupancyOctreeParams params, OctreeChannels channels)
    : resolution_(resolution), inv_resolution_(1.0 / resolution), params_(params), channels_(channels) {
  ROVE_CHECK_MSG(octree_resolution_valid(resolution),
                 "octree resolution must be finite and > 0 (and neither it, its inverse nor the tree's extent "
                 "overflow), got {}",
                 resolution);
  params_.check();
  hit_ = octree_log_odds(params_.prob_hit);
  miss_ = octree_log_odds(params_.prob_miss);
  clamp_min_ = octree_log_odds(params_.clamping_min);
  clamp_max_ = octree_log_odds(params_.clamping_max);
  threshold_ = octree_log_odds(params_.occupancy_threshold);
  store_ = std::make_unique<OctreeStore>(has_channels(channels, OctreeChannels::Color),
                                         has_channels(channels, OctreeChannels::Statistics));
}

OccupancyOctree::~OccupancyOctree() = default;
OccupancyOctree::OccupancyOctree(OccupancyOctree&&) noexcept = default;
OccupancyOctree& OccupancyOctree::operator=(OccupancyOctree&&) noexcept = default;

OccupancyOctree::OccupancyOctree(const OccupancyOctree& o)
    : resolution_(o.resolution_),
      inv_resolution_(o.inv_resolution_),
      params_(o.params_),
      channels_(o.channels_),
      hit_(o.hit_),
      miss_(o.miss_),
      clamp_min_(o.clamp_min_),
      clamp_max_(o.clamp_max_),
      threshold_(o.threshold_),
      store_(std::make_unique<OctreeStore>(*o.store_)),
      num_nodes_(o.num_nodes_),
      change_detection_(o.change_detection_),
      changes_(o.changes_) {}

OccupancyOctree& OccupancyOctree::operator=(const OccupancyOctree& o) {
  if (this != &o) *this = OccupancyOctree(o);
  return *this;
}

double OccupancyOctree::node_size(int depth) const {
  ROVE_CHECK_MSG(depth >= 0 && depth <= kOctreeDepth, "depth {} is not in [0, 16]", depth);
  return resolution_ * static_cast<double>(1 << (kOctreeDepth - depth));
}

std::optional<OctreeKey> OccupancyOctree::key_of(const Eigen::Vector3d& p) const noexcept {
  OctreeKey k;
  const double c[3] = {p.x(), p.y(), p.z()};
  if (!detail::point_to_key(inv_resolution_, c, k)) return std::nullopt;
  return k;
}

OctreeKey OccupancyOctree::key_checked(const Eigen::Vector3d& p) const {
  const auto k = key_of(p);
  if (!k) {
    throw InvalidArgument(fmt::format("point ({}, {}, {}) is not finite or outside the octree (±{} m)", p.x(),
                                      p.y(), p.z(), kOctreeKeyOffset * resolution_));
  }
  return *k;
}

Eigen::Vector3d OccupancyOctree::center_of(const OctreeKey& key, int depth) const {
  ROVE_CHECK_MSG(depth >= 0 && depth <= kOctreeDepth, "depth {} is not in [0, 16]", depth);
  if (depth == 0) return Eigen::Vector3d::Zero();
  Eigen::Vector3d c;
  for (int a = 0; a < 3; ++a) {
    if (depth == kOctreeDepth) {
      c[a] = detail::key_to_coord(resolution_, key[a]);
    } else {
      // OctoMap's keyToCoord(key, depth).
      const double cells = static_cast<double>(1 << (kOctreeDepth - depth));
      c[a] = (std::floor((static_cast<double>(key[a]) - kOctreeKeyOffset) / cells) + 0.5) * node_size(depth);
    }
  }
  return c;
}

std::optional<OctreeNodeInfo> OccupancyOctree::search(const OctreeKey& key, int depth) const {
  ROVE_CHECK_MSG(depth >= 0 && depth <= kOctreeDepth, "depth {} is not in [0, 16]", depth);
  const OctreeStore& s = *store_;
  if (!s.root_exists()) return std::nullopt;
  std::uint32_t n = 0;
  int d = 0;
  for (; d < depth; ++d) {
    const std::uint32_t block = s.node(n).children;
    if (block == kNoBlock) break;
    const unsigned slot = octree_child_index(key, d);
    if (!s.child_exists(block, slot)) return std::nullopt;
    n = block * 8 + slot;
  }
  return OctreeNodeInfo{s.node(n).log_odds, d, s.node(n).children == kNoBlock};
}

std::optional<OctreeNodeInfo> OccupancyOctree::search(const Eigen::Vector3d& p) const {
  return search(key_checked(p));
}

namespace {
// The id of the deepest node on the path to key (OctoMap's search), or false.
bool find_node(const OctreeStore& s, const OctreeKey& key, std::uint32_t& id) {
  detail::LeafFinder f(s);
  int depth = 0;
  return f.find(key, id, depth);
}
}  // namespace

std::optional<Rgb8> OccupancyOctree::color_at(const OctreeKey& key) const {
  std::uint32_t id = 0;
  if (!store_->has_colors() || !find_node(*store_, key, id)) return std::nullopt;
  return store_->color(id);
}

std::optional<OctreeLeafStatistics> OccupancyOctree::statistics_at(const OctreeKey& key) const {
  std::uint32_t id = 0;
  if (!store_->has_statistics() || !find_node(*store_, key, id)) return std::nullopt;
  return store_->stats(id);
}

namespace {
void update_one(OccupancyOctree& tree, const OctreeKey& key, detail::UpdateKind kind, float value) {
  OctreeStore& s = OctreeAccess::store(tree);
  const detail::UpdateParams params = OctreeAccess::params(tree);
  std::size_t& num_nodes = OctreeAccess::num_nodes(tree);
  detail::BlockAllocator alloc(s, nullptr);
  const bool fresh = detail::ensure_root(s, num_nodes);
  detail::SubtreeUpdater up(s, alloc, params, 0, 0, fresh);
  up.apply(key, kind, value);
  // OctoMap touches nothing above a cell it leaves as it is.
  const std::int64_t pruned = detail::finalize_subtree(s, alloc, params, 0, 0, !up.changed);
  s.dirty(0) = 0;
  num_nodes = static_cast<std::size_t>(static_cast<std::int64_t>(num_nodes) + up.node_delta + pruned);
  if (params.change_detection) detail::merge_changes(OctreeAccess::changes(tree), up.changes);
}
}  // namespace

void OccupancyOctree::update_node(const OctreeKey& key, float log_odds_delta) {
  ROVE_CHECK_FINITE(log_odds_delta);
  update_one(*this, key, detail::UpdateKind::Delta, log_odds_delta);
}

void OccupancyOctree::update_node(const OctreeKey& key, bool occupied) {
  update_node(key, occupied ? hit_ : miss_);
}

void OccupancyOctree::set_node_value(const OctreeKey& key, float log_odds) {
  ROVE_CHECK_FINITE(log_odds);
  update_one(*this, key, detail::UpdateKind::Set, std::min(std::max(log_odds, clamp_min_), clamp_max_));
}

bool OccupancyOctree::update_color(const OctreeKey& key, Rgb8 color, OctreeColorUpdate how) {
  ROVE_CHECK_MSG(store_->has_colors(), "update_color needs an octree with the Color channel");
  OctreeStore& s = *store_;
  if (!s.root_exists()) return false;
  std::uint32_t path[kOctreeDepth + 1];
  path[0] = 0;
  int d = 0;
  for (; d < kOctreeDepth; ++d) {
    const std::uint32_t block = s.node(path[d]).children;
    if (block == kNoBlock) break;
    const unsigned slot = octree_child_index(key, d);
    if (!s.child_exists(block, slot)) return false;
    path[d + 1] = block * 8 + slot;
  }
  const std::uint32_t id = path[d];
  Rgb8& c = s.color(id);
  const bool set = !(c.r == 255 && c.g == 255 && c.b == 255);
  if (!set || how == OctreeColorUpdate::Set) {
    c = color;
  } else if (how == OctreeColorUpdate::Average) {
    c = Rgb8{static_cast<std::uint8_t>((c.r + color.r) / 2), static_cast<std::uint8_t>((c.g + color.g) / 2),
             static_cast<std::uint8_t>((c.b + color.b) / 2)};
  } else {
    // OctoMap's integrateNodeColor.
    const double p = octree_probability(s.node(id).log_odds);
    const auto mix = [p](std::uint8_t old_c, std::uint8_t new_c) {
      return static_cast<std::uint8_t>(static_cast<double>(old_c) * p + static_cast<double>(new_c) * (0.99 - p));
    };
    c = Rgb8{mix(c.r, color.r), mix(c.g, color.g), mix(c.b, color.b)};
  }
  for (int up = d - 1; up >= 0; --up) {
    s.color(path[up]) = detail::average_child_color(s, s.node(path[up]).children);
  }
  return true;
}

namespace {
// Calls fn(id, key, depth) for every node in depth-first pre-order.
template <typename Fn>
void walk(const OctreeStore& s, std::uint32_t id, const OctreeKey& key, int depth, Fn&& fn) {
  if (!fn(id, key, depth)) return;
  const std::uint32_t block = s.node(id).children;
  if (block == kNoBlock) return;
  const std::uint8_t mask = s.exists(block);
  const unsigned half = 1u << (kOctreeDepth - 1 - depth);
  for (unsigned i = 0; i < 8; ++i) {
    if (((mask >> i) & 1u) == 0) continue;
    OctreeKey k = key;
    if (i & 1u) k.x = static_cast<std::uint16_t>(k.x + half);
    if (i & 2u) k.y = static_cast<std::uint16_t>(k.y + half);
    if (i & 4u) k.z = static_cast<std::uint16_t>(k.z + half);
    walk(s, block * 8 + i, k, depth + 1, fn);
  }
}
}  // namespace

void OccupancyOctree::prune() {
  if (!store_->root_exists()) return;
  const detail::UpdateParams params = OctreeAccess::params(*this);
  detail::BlockAllocator alloc(*store_, nullptr);
  // OctoMap's order: the nodes of depth 15, then 14, ... 1 (never the root),
  // stopping at the first depth where nothing was pruned.
  for (int depth = kOctreeDepth - 1; depth > 0; --depth) {
    std::size_t pruned = 0;
    walk(*store_, 0, OctreeKey{}, 0, [&](std::uint32_t id, const OctreeKey&, int d) {
      if (d < depth) return true;
      if (detail::prune_node(*store_, alloc, params, id)) ++pruned;
      return false;
    });
    num_nodes_ -= 8 * pruned;
    if (pruned == 0) break;
  }
}

void OccupancyOctree::expand() {
  if (!store_->root_exists()) return;
  const detail::UpdateParams params = OctreeAccess::params(*this);
  detail::BlockAllocator alloc(*store_, nullptr);
  walk(*store_, 0, OctreeKey{}, 0, [&](std::uint32_t id, const OctreeKey&, int d) {
    if (d >= kOctreeDepth) return false;
    detail::OctreeNode& n = store_->node(id);
    if (n.children == kNoBlock) {
      const std::uint32_t b = alloc.allocate();
      for (std::uint32_t i = 0; i < 8; ++i) {
        store_->node(b * 8 + i) = detail::OctreeNode{n.log_odds, kNoBlock};
        if (params.colors) store_->color(b * 8 + i) = store_->color(id);
        if (params.statistics) store_->stats(b * 8 + i) = store_->stats(id);
      }
      store_->exists(b) = 0xFF;
      store_->dirty(b) = 0;
      store_->node(id).children = b;
      num_nodes_ += 8;
    }
    return true;
  });
}

namespace {
void refresh_recursive(OctreeStore& s, detail::BlockAllocator& alloc, const detail::UpdateParams& params,
                       std::uint32_t id) {
  const std::uint32_t block = s.node(id).children;
  if (block == kNoBlock) return;
  const std::uint8_t mask = s.exists(block);
  for (std::uint32_t i = 0; i < 8; ++i) {
    if (((mask >> i) & 1u) != 0) refresh_recursive(s, alloc, params, block * 8 + i);
  }
  detail::refresh_node(s, alloc, params, id, false);
}
}  // namespace

void OccupancyOctree::update_inner_occupancy() {
  if (!store_->root_exists()) return;
  detail::BlockAllocator alloc(*store_, nullptr);
  refresh_recursive(*store_, alloc, OctreeAccess::params(*this), 0);
}

void OccupancyOctree::to_max_likelihood() {
  if (!store_->root_exists()) return;
  walk(*store_, 0, OctreeKey{}, 0, [&](std::uint32_t id, const OctreeKey&, int) {
    detail::OctreeNode& n = store_->node(id);
    n.log_odds = is_occupied(n.log_odds) ? clamp_max_ : clamp_min_;
    return true;
  });
}

void OccupancyOctree::clear() {
  store_->reset();
  num_nodes_ = 0;
}

std::vector<OctreeChange> OccupancyOctree::changes() const {
  std::vector<OctreeChange> out;
  out.reserve(changes_.size());
  for (const auto& [k, created] : changes_) out.push_back({k, created});
  std::sort(out.begin(), out.end(), [](const OctreeChange& a, const OctreeChange& b) { return a.key < b.key; });
  return out;
}

void OccupancyOctree::reset_changes() { changes_.clear(); }

void OccupancyOctree::for_each_leaf(const std::function<void(const OctreeLeaf&)>& fn) const {
  if (!store_->root_exists()) return;
  walk(*store_, 0, OctreeKey{}, 0, [&](std::uint32_t id, const OctreeKey& k, int d) {
    const detail::OctreeNode& n = store_->node(id);
    if (n.children == kNoBlock) fn(OctreeLeaf{k, d, n.log_odds});
    return true;
  });
}

void OccupancyOctree::for_each_leaf_in_box(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                                           const std::function<void(const OctreeLeaf&)>& fn) const {
  ROVE_CHECK_FINITE(min);
  ROVE_CHECK_FINITE(max);
  if (!store_->root_exists() || (min.array() > max.array()).any()) return;
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const double l = std::floor(min[a] * inv_resolution_) + kOctreeKeyOffset;
    const double h = std::floor(max[a] * inv_resolution_) + kOctreeKeyOffset;
    if (h < 0.0 || l > 65535.0) return;
    lo[a] = static_cast<int>(std::max(l, 0.0));
    hi[a] = static_cast<int>(std::min(h, 65535.0));
  }
  walk(*store_, 0, OctreeKey{}, 0, [&](std::uint32_t id, const OctreeKey& k, int d) {
    const int size = 1 << (kOctreeDepth - d);
    for (int a = 0; a < 3; ++a) {
      if (k[a] > hi[a] || k[a] + size - 1 < lo[a]) return false;
    }
    const detail::OctreeNode& n = store_->node(id);
    if (n.children == kNoBlock) fn(OctreeLeaf{k, d, n.log_odds});
    return true;
  });
}

std::vector<OctreeLeaf> OccupancyOctree::leaves() const {
  std::vector<OctreeLeaf> out;
  for_each_leaf([&](const OctreeLeaf& l) { out.push_back(l); });
  return out;
}

std::size_t OccupancyOctree::num_leaves() const {
  std::size_t n = 0;
  for_each_leaf([&](const OctreeLeaf&) { ++n; });
  return n;
}

void OccupancyOctree::for_each_node(const std::function<void(const OctreeNodeRecord&)>& fn) const {
  if (!store_->root_exists()) return;
  walk(*store_, 0, OctreeKey{}, 0, [&](std::uint32_t id, const OctreeKey& k, int d) {
    const detail::OctreeNode& n = store_->node(id);
    OctreeNodeRecord r;
    r.key = k;
    r.depth = d;
    r.log_odds = n.log_odds;
    r.child_mask = n.children == kNoBlock ? 0 : store_->exists(n.children);
    if (store_->has_colors()) r.color = store_->color(id);
    if (store_->has_statistics()) r.statistics = store_->stats(id);
    fn(r);
    return true;
  });
}

namespace {
struct PreorderBuilder {
  OctreeStore& s;
  detail::BlockAllocator& alloc;
  std::span<const OctreeNodeRecord> nodes;
  std::size_t next = 0;

  void build(std::uint32_t id, int depth) {
    ROVE_CHECK_MSG(next < nodes.size(), "the node list ends early: its child masks imply more than {} nodes",
                   nodes.size());
    const OctreeNodeRecord& r = nodes[next++];
    detail::OctreeNode& n = s.node(id);
    n = detail::OctreeNode{r.log_odds, kNoBlock};
    if (s.has_colors()) s.color(id) = r.color;
    if (s.has_statistics()) s.stats(id) = r.statistics;
    if (r.child_mask == 0) {
      ROVE_CHECK_MSG(std::isfinite(r.log_odds), "leaf {} has a log-odds that is not finite", next - 1);
      return;
    }
    ROVE_CHECK_MSG(depth < kOctreeDepth, "node {} has children below depth 16", next - 1);
    const std::uint32_t b = alloc.allocate();
    s.exists(b) = r.child_mask;
    s.dirty(b) = 0;
    s.node(id).children = b;
    for (unsigned i = 0; i < 8; ++i) {
      if (((r.child_mask >> i) & 1u) != 0) build(b * 8 + i, depth + 1);
    }
    if (std::isnan(r.log_odds)) {
      float m = -std::numeric_limits<float>::max();
      for (unsigned i = 0; i < 8; ++i) {
        if (((r.child_mask >> i) & 1u) != 0) m = std::max(m, s.node(b * 8 + i).log_odds);
      }
      s.node(id).log_odds = m;
    }
  }
};
}  // namespace

void OccupancyOctree::assign_preorder(std::span<const OctreeNodeRecord> nodes) {
  store_->reset();
  num_nodes_ = 0;
  if (nodes.empty()) return;
  try {
    detail::BlockAllocator alloc(*store_, nullptr);
    store_->exists(0) = 1;
    PreorderBuilder b{*store_, alloc, nodes};
    b.build(0, 0);
    ROVE_CHECK_MSG(b.next == nodes.size(), "the node list holds {} nodes after the tree's {}", nodes.size() - b.next,
                   b.next);
  } catch (...) {
    store_->reset();
    throw;
  }
  num_nodes_ = nodes.size();
}

std::size_t OccupancyOctree::memory_usage() const noexcept { return sizeof(*this) + store_->bytes(); }

void OccupancyOctree::metric_bounds(Eigen::Vector3d& min, Eigen::Vector3d& max) const {
  min = Eigen::Vector3d::Constant(1.0);
  max = Eigen::Vector3d::Constant(-1.0);
  bool first = true;
  for_each_leaf([&](const OctreeLeaf& l) {
    const double size = node_size(l.depth);
    for (int a = 0; a < 3; ++a) {
      const double lo = (static_cast<double>(l.key[a]) - kOctreeKeyOffset) * resolution_;
      min[a] = first ? lo : std::min(min[a], lo);
      max[a] = first ? lo + size : std::max(max[a], lo + size);
    }
    first = false;
  });
}

}  // namespace rove
