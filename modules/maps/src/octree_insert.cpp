// OccupancyOctree::insert_point_cloud: rays from a sensor origin into the
// tree, as OctoMap's insertPointCloud / insertPointCloudRays, in three steps:
//   1. rays: each point's end (cut by max_range) and end cell, checked;
//   2. updates. Each cell once per scan (OncePerScan, Discretized): when the
//      box of the rays' cells is small enough, the rays mark the cells they
//      cross in dense bitmaps over the box (octree_dense_cells.h; one bitmap
//      per thread, merged with an OR), the occupied ends are tagged, and the
//      cells are updated in tree order, below the root with one thread, per
//      subtree ("bucket") of a fixed grid in parallel with several. A larger
//      box, and EveryRay, take the sparse path: with one thread, the rays
//      are walked straight into a hashed cell set (octree_cell_set.h) or the
//      tree (EveryRay); with several, the cells each ray crosses are first
//      recorded as runs of unit steps (2 bits a step), cut where they cross
//      into another bucket, sorted by bucket (stably: cloud order is kept
//      within a bucket), then the buckets are updated in parallel;
//   3. the touched nodes are pruned or set to the maximum of their children,
//      per bucket in parallel, then above the buckets.
// A set of cells does not depend on the order it was marked in, buckets are
// disjoint subtrees and each keeps the cloud's order, so the tree does not
// depend on the thread count (a property the tests check).
#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <mutex>

#include <fmt/format.h>

#include "octree_cell_set.h"
#include "octree_dense_cells.h"
#include "octree_rays.h"
#include "octree_update.h"
#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/parallel.h"

namespace rove {

namespace detail {
namespace {

template <typename P>
struct Ray {
  P end[3];
  OctreeKey key;       // cell of `end`
  bool occupied;       // the end is a measured obstacle (not cut by max_range)
};

// A run of cells in one bucket: `key`, then `count` unit steps read from the
// chunk's step stream at `offset` (2 bits a step: the axis), each along
// −1 on the axes set in `negative`. Or an occupied end cell (count 0).
struct Event {
  std::uint32_t bucket;
  std::uint32_t chunk;
  std::uint32_t offset;
  std::uint32_t count;
  OctreeKey key;
  std::uint8_t hit;
  std::uint8_t negative;
};

struct Chunk {
  std::vector<Event> events;
  std::vector<std::uint64_t> steps;
  std::uint32_t used = 0;  // steps written
  void push_step(int axis) {
    if ((used & 31u) == 0) steps.push_back(0);
    steps.back() |= static_cast<std::uint64_t>(axis) << (2 * (used & 31u));
    ++used;
  }
  int step_at(std::uint32_t i) const { return static_cast<int>((steps[i >> 5] >> (2 * (i & 31u))) & 3u); }
};

// The grid of buckets: cells [lo, hi] on each axis, buckets 2^shift cells wide.
struct BucketGrid {
  int shift = 16;
  int lo[3] = {0, 0, 0};  // first bucket index per axis
  int n[3] = {1, 1, 1};
  std::uint32_t index(const OctreeKey& k) const noexcept {
    const int bx = (k.x >> shift) - lo[0], by = (k.y >> shift) - lo[1], bz = (k.z >> shift) - lo[2];
    return static_cast<std::uint32_t>((bx * n[1] + by) * n[2] + bz);
  }
  OctreeKey corner(std::uint32_t b) const noexcept {
    const int bz = static_cast<int>(b % static_cast<std::uint32_t>(n[2]));
    const int by = static_cast<int>((b / static_cast<std::uint32_t>(n[2])) % static_cast<std::uint32_t>(n[1]));
    const int bx = static_cast<int>(b / static_cast<std::uint32_t>(n[2] * n[1]));
    return {static_cast<std::uint16_t>((bx + lo[0]) << shift), static_cast<std::uint16_t>((by + lo[1]) << shift),
            static_cast<std::uint16_t>((bz + lo[2]) << shift)};
  }
  std::size_t size() const noexcept { return static_cast<std::size_t>(n[0]) * n[1] * n[2]; }
};

constexpr std::size_t kChunkRays = 2048;

// The dense path's memory: a bitmap (one per marking thread) may take up to
// 4 bytes per cell step the rays make (about what the sparse cell set
// takes), and at least 4 MiB.
constexpr std::size_t kDenseBytesPerStep = 4;
constexpr std::size_t kDenseMinBytes = std::size_t{4} << 20;
// Cells added around the box of the rays' end cells and origin: a ray's
// cells stay within its end cells' box up to rounding (a walk that leaves
// the box anyway sends the scan to the sparse path).
constexpr int kDenseMargin = 2;

template <typename P>
class CloudInsertion {
 public:
  CloudInsertion(OccupancyOctree& tree, std::span<const Eigen::Vector3f> points, const Eigen::Vector3d& origin,
                 const OctreeInsertOptions& options)
      : tree_(tree),
        store_(OctreeAccess::store(tree)),
        params_(OctreeAccess::params(tree)),
        options_(options),
        resolution_(tree.resolution()),
        inv_resolution_(1.0 / tree.resolution()) {
    result_.points = points.size();
    for (int i = 0; i < 3; ++i) origin_[i] = static_cast<P>(origin[i]);
    // The origin is checked as the cloud's points will be (same scalar).
    ROVE_CHECK_MSG(std::isfinite(origin.x()) && std::isfinite(origin.y()) && std::isfinite(origin.z()) &&
                       point_to_key(inv_resolution_, origin_, origin_key_),
                   "sensor origin ({}, {}, {}) is not finite or outside the octree (±{} m)", origin.x(),
                   origin.y(), origin.z(), kOctreeKeyOffset * resolution_);
    prepare(points);
  }

  OctreeInsertResult run() {
    const int threads = resolve_thread_count(options_.num_threads, "OctreeInsertOptions::num_threads");
    if (rays_.empty()) {
      // Nothing to insert: the tree stays as it is (no root is created).
    } else if (every_ray() || !run_dense(threads)) {
      if (threads == 1 || !choose_grid()) {
        run_direct();
      } else {
        run_buckets(threads);
      }
    }
    if (result_.skipped_points > 0) {
      result_.termination = OctreeInsertTermination::SkippedPoints;
      result_.message = fmt::format("inserted {} of {} points ({} not finite or outside the octree)",
                                    result_.points - result_.skipped_points, result_.points,
                                    result_.skipped_points);
    } else {
      result_.message = fmt::format("inserted {} points", result_.points);
    }
    return result_;
  }

 private:
  bool every_ray() const noexcept { return options_.mode == OctreeUpdateMode::EveryRay; }

  [[noreturn]] void reject(std::size_t i, const Eigen::Vector3f& p) const {
    throw InvalidArgument(fmt::format(
        "octree insertion: point {} ({}, {}, {}) is not finite or outside the octree (±{} m at resolution {} m); "
        "set skip_invalid_points to skip such points",
        i, p.x(), p.y(), p.z(), kOctreeKeyOffset * resolution_, resolution_));
  }

  // The points the rays go to: the cloud, or the centres of its distinct
  // cells (Discretized, in order of first appearance).
  struct Target {
    std::array<P, 3> p;
    std::size_t source;  // index in the cloud
  };
  std::vector<Target> targets(std::span<const Eigen::Vector3f> points) {
    std::vector<Target> out;
    out.reserve(points.size());
    if (options_.mode != OctreeUpdateMode::Discretized) {
      for (std::size_t i = 0; i < points.size(); ++i) {
        const auto& p = points[i];
        out.push_back({{static_cast<P>(p.x()), static_cast<P>(p.y()), static_cast<P>(p.z())}, i});
      }
      return out;
    }
    std::vector<std::pair<std::uint64_t, std::size_t>> keys;
    keys.reserve(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      const P q[3] = {static_cast<P>(points[i].x()), static_cast<P>(points[i].y()), static_cast<P>(points[i].z())};
      OctreeKey k;
      if (!point_to_key(inv_resolution_, q, k)) {
        if (!options_.skip_invalid_points) reject(i, points[i]);
        ++result_.skipped_points;
        continue;
      }
      keys.emplace_back(k.packed(), i);
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end(),
                           [](const auto& a, const auto& b) { return a.first == b.first; }),
               keys.end());
    std::sort(keys.begin(), keys.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    for (const auto& [packed, i] : keys) {
      const OctreeKey k = OctreeKey::unpack(packed);
      out.push_back({{static_cast<P>(key_to_coord(resolution_, k.x)), static_cast<P>(key_to_coord(resolution_, k.y)),
                      static_cast<P>(key_to_coord(resolution_, k.z))},
                     i});
    }
    return out;
  }

  void prepare(std::span<const Eigen::Vector3f> points) {
    const std::vector<Target> ts = targets(points);
    const bool cut = !every_ray() && options_.max_range >= 0.0;
    rays_.reserve(ts.size());
    for (std::size_t i = 0; i < ts.size(); ++i) {
      Ray<P> r{};
      const P* p = ts[i].p.data();
      P d[3] = {p[0] - origin_[0], p[1] - origin_[1], p[2] - origin_[2]};
      r.occupied = !cut || norm3(d) <= options_.max_range;
      if (r.occupied) {
        std::copy(p, p + 3, r.end);
      } else {
        // OctoMap: origin + direction · (float) maxrange.
        normalize3(d);
        const P range = static_cast<P>(options_.max_range);
        for (int k = 0; k < 3; ++k) r.end[k] = origin_[k] + d[k] * range;
      }
      const bool finite = std::isfinite(static_cast<double>(p[0])) && std::isfinite(static_cast<double>(p[1])) &&
                          std::isfinite(static_cast<double>(p[2]));
      if (!finite || !point_to_key(inv_resolution_, r.end, r.key)) {
        if (!options_.skip_invalid_points) reject(ts[i].source, points[ts[i].source]);
        ++result_.skipped_points;
        continue;
      }
      rays_.push_back(r);
    }
  }

  void finish(std::vector<BlockAllocator>& allocs, std::int64_t node_delta,
              const std::vector<const std::vector<ChangeEvent>*>& changes) {
    for (auto& a : allocs) a.release();
    std::size_t& n = OctreeAccess::num_nodes(tree_);
    n = static_cast<std::size_t>(static_cast<std::int64_t>(n) + node_delta);
    if (params_.change_detection) {
      for (const auto* c : changes) merge_changes(OctreeAccess::changes(tree_), *c);
    }
  }

  // Runs fill(updater) below the root, then finalizes the tree.
  template <typename Fill>
  void update_from_root(Fill&& fill) {
    std::vector<BlockAllocator> allocs;
    allocs.emplace_back(store_, nullptr);
    const bool fresh = ensure_root(store_, OctreeAccess::num_nodes(tree_));
    SubtreeUpdater up(store_, allocs[0], params_, 0, 0, fresh);
    fill(up);
    const std::int64_t pruned = finalize_subtree(store_, allocs[0], params_, 0, 0, options_.lazy);
    store_.dirty(0) = 0;
    result_.occupied_updates = up.hit_updates;
    result_.free_updates = up.miss_updates;
    finish(allocs, up.node_delta + pruned, {&up.changes});
  }

  // Runs fill(thread, i, updater) for the subtrees at `depth` whose nodes
  // contain corners[i], in parallel, then finalizes them and the nodes above them.
  template <typename Fill>
  void update_subtrees(ThreadTeam& team, const std::vector<OctreeKey>& corners, int depth, Fill&& fill) {
    const int threads = team.size();
    // The path from the root to each subtree's root node.
    std::mutex mutex;
    std::vector<BlockAllocator> allocs;
    for (int t = 0; t < threads; ++t) allocs.emplace_back(store_, &mutex);
    std::vector<std::uint32_t> roots(corners.size());
    std::vector<char> fresh(corners.size(), 0);
    std::int64_t node_delta = 0;
    {
      const bool root_fresh = ensure_root(store_, OctreeAccess::num_nodes(tree_));
      SubtreeUpdater top(store_, allocs[0], params_, 0, 0, root_fresh);
      for (std::size_t i = 0; i < corners.size(); ++i) {
        bool f = false;
        roots[i] = top.reach(corners[i], depth, f);
        fresh[i] = f ? 1 : 0;
      }
      node_delta += top.node_delta;
    }
    // The subtrees' updates, in parallel.
    std::vector<std::vector<ChangeEvent>> changes(corners.size());
    std::vector<std::int64_t> deltas(corners.size(), 0);
    std::vector<std::size_t> hits(corners.size(), 0), misses(corners.size(), 0);
    std::atomic<std::size_t> next_subtree{0};
    team.run([&](int t) {
      for (std::size_t i; (i = next_subtree.fetch_add(1)) < corners.size();) {
        SubtreeUpdater up(store_, allocs[static_cast<std::size_t>(t)], params_, roots[i], depth, fresh[i] != 0);
        fill(t, i, up);
        deltas[i] = up.node_delta;
        hits[i] = up.hit_updates;
        misses[i] = up.miss_updates;
        changes[i] = std::move(up.changes);
      }
    });
    // Finalize each subtree, then the nodes above them.
    std::atomic<std::size_t> next_final{0};
    team.run([&](int t) {
      for (std::size_t i; (i = next_final.fetch_add(1)) < corners.size();) {
        deltas[i] += finalize_subtree(store_, allocs[static_cast<std::size_t>(t)], params_, roots[i], depth,
                                      options_.lazy);
      }
    });
    node_delta += finalize_subtree(store_, allocs[0], params_, 0, 0, options_.lazy, depth);
    store_.dirty(0) = 0;
    std::vector<const std::vector<ChangeEvent>*> change_lists;
    for (std::size_t i = 0; i < corners.size(); ++i) {
      node_delta += deltas[i];
      result_.occupied_updates += hits[i];
      result_.free_updates += misses[i];
      change_lists.push_back(&changes[i]);
    }
    finish(allocs, node_delta, change_lists);
  }

  void run_direct() {
    update_from_root([&](SubtreeUpdater& up) {
      if (every_ray()) {
        for (const Ray<P>& r : rays_) {
          traverse_ray(origin_, r.end, origin_key_, r.key, resolution_,
                       [&](const OctreeKey& k, int) { up.apply(k, UpdateKind::Delta, params_.miss); });
          up.apply(r.key, UpdateKind::Delta, params_.hit);
        }
        return;
      }
      // The cells of the scan, each once (occupied ones tagged), then the
      // updates in the tree's order.
      CellSet cells;
      for (const Ray<P>& r : rays_) {
        if (r.occupied) cells.insert(r.key, true);
      }
      CellSet::Cursor cursor;
      for (const Ray<P>& r : rays_) {
        traverse_ray(origin_, r.end, origin_key_, r.key, resolution_,
                     [&](const OctreeKey& k, int) { cells.insert(k, cursor); });
      }
      cells.for_each_in_tree_order([&](const OctreeKey& k, bool occupied) {
        up.apply(k, occupied ? UpdateKind::ScanHit : UpdateKind::ScanMiss, 0.0f);
      });
    });
  }

  // The box of the origin's and the rays' end cells, `margin` cells wider
  // on each side (within the tree), and the cell steps of the rays if each
  // walked straight to its end cell.
  void ray_box(int margin, OctreeKey& lo, OctreeKey& hi, std::size_t& steps) const {
    int l[3], h[3];
    for (int a = 0; a < 3; ++a) l[a] = h[a] = origin_key_[a];
    steps = 0;
    for (const Ray<P>& r : rays_) {
      for (int a = 0; a < 3; ++a) {
        l[a] = std::min<int>(l[a], r.key[a]), h[a] = std::max<int>(h[a], r.key[a]);
        steps += static_cast<std::size_t>(std::abs(r.key[a] - origin_key_[a]));
      }
    }
    for (int a = 0; a < 3; ++a) {
      lo[a] = static_cast<std::uint16_t>(std::max(0, l[a] - margin));
      hi[a] = static_cast<std::uint16_t>(std::min(0xFFFF, h[a] + margin));
    }
  }

  // The bucket size (log2 of cells per axis) for the box [lo, hi]: about 4
  // to 8 buckets along its longest axis, at least 2^min_shift cells.
  static int bucket_shift(const OctreeKey& lo, const OctreeKey& hi, int min_shift) {
    int extent = 0;
    for (int a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a] + 1);
    return std::max(min_shift, static_cast<int>(std::bit_width(static_cast<unsigned>(extent))) - 3);
  }

  // Picks the bucket grid from the cells the rays can reach; false when a
  // single bucket would hold them all.
  bool choose_grid() {
    OctreeKey lo, hi;
    std::size_t steps = 0;
    ray_box(1, lo, hi, steps);
    grid_.shift = bucket_shift(lo, hi, 4);
    if (grid_.shift >= kOctreeDepth || rays_.size() < 2 * kChunkRays) return false;
    for (int a = 0; a < 3; ++a) {
      grid_.lo[a] = lo[a] >> grid_.shift;
      grid_.n[a] = (hi[a] >> grid_.shift) - grid_.lo[a] + 1;
    }
    return true;
  }

  // Each cell once per scan through dense bitmaps (see the file comment);
  // false, with the tree untouched, when the box of the rays is too large
  // for them or some ray left it.
  bool run_dense(int threads) {
    OctreeKey lo, hi;
    std::size_t steps = 0;
    ray_box(kDenseMargin, lo, hi, steps);
    const std::size_t bytes = DenseCellSet::bytes_for(lo, hi);
    const std::size_t budget = std::max(kDenseMinBytes, kDenseBytesPerStep * steps);
    if (bytes > budget) return false;
    const std::size_t chunks = (rays_.size() + kChunkRays - 1) / kChunkRays;
    const int markers = static_cast<int>(std::min({static_cast<std::size_t>(threads), budget / bytes, chunks}));
    std::vector<DenseCellSet> sets;
    sets.reserve(static_cast<std::size_t>(markers));
    for (int m = 0; m < markers; ++m) sets.emplace_back(lo, hi);
    for (const Ray<P>& r : rays_) {
      if (r.occupied) sets[0].tag(r.key);
    }
    ThreadTeam team(threads);
    std::atomic<std::size_t> next_chunk{0};
    team.run([&](int t) {
      if (t >= markers) return;
      DenseCellSet::Marker marker(sets[static_cast<std::size_t>(t)]);
      for (std::size_t c; (c = next_chunk.fetch_add(1)) < chunks;) {
        const std::size_t end = std::min(rays_.size(), (c + 1) * kChunkRays);
        for (std::size_t i = c * kChunkRays; i < end; ++i) {
          walk_ray(origin_, rays_[i].end, origin_key_, rays_[i].key, resolution_, marker);
        }
      }
    });
    if (std::any_of(sets.begin(), sets.end(), [](const DenseCellSet& d) { return d.overflowed(); })) return false;
    if (markers > 1) {
      const std::size_t words = sets[0].words();
      team.run([&](int t) {
        const std::size_t n = static_cast<std::size_t>(threads), i = static_cast<std::size_t>(t);
        for (std::size_t m = 1; m < sets.size(); ++m) sets[0].merge_marks(sets[m], words * i / n, words * (i + 1) / n);
      });
      sets.erase(sets.begin() + 1, sets.end());
    }
    const DenseCellSet& cells = sets[0];
    const std::vector<DenseCellSet::BlockRef> blocks = cells.blocks_in_tree_order();
    const auto update_blocks = [&](SubtreeUpdater& up, std::size_t begin, std::size_t end) {
      for (std::size_t b = begin; b < end; ++b) {
        cells.for_each_in_block(blocks[b].index, [&](const OctreeKey& k, bool occupied) {
          up.apply(k, occupied ? UpdateKind::ScanHit : UpdateKind::ScanMiss, 0.0f);
        });
      }
    };
    const int shift = bucket_shift(lo, hi, DenseCellSet::kBlockShift);
    if (threads == 1 || shift >= kOctreeDepth) {
      update_from_root([&](SubtreeUpdater& up) { update_blocks(up, 0, blocks.size()); });
      return true;
    }
    // Buckets: runs of blocks in one subtree of 2^shift cells a side (their
    // Morton codes agree above the bucket's bits).
    const int code_shift = 3 * (shift - DenseCellSet::kBlockShift);
    std::vector<std::size_t> starts;
    std::vector<OctreeKey> corners;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      if (b == 0 || (blocks[b].code >> code_shift) != (blocks[b - 1].code >> code_shift)) {
        starts.push_back(b);
        corners.push_back(octree_key_at_depth(cells.block_corner(blocks[b].index), kOctreeDepth - shift));
      }
    }
    starts.push_back(blocks.size());
    update_subtrees(team, corners, kOctreeDepth - shift,
                    [&](int, std::size_t i, SubtreeUpdater& up) { update_blocks(up, starts[i], starts[i + 1]); });
    return true;
  }

  void record_chunk(std::size_t c, Chunk& out) const {
    const std::size_t begin = c * kChunkRays, end = std::min(rays_.size(), begin + kChunkRays);
    const int shift = grid_.shift;
    for (std::size_t i = begin; i < end; ++i) {
      const Ray<P>& r = rays_[i];
      const auto hit_event = [&] {
        if (r.occupied || every_ray()) out.events.push_back({grid_.index(r.key), static_cast<std::uint32_t>(c), 0, 0, r.key, 1, 0});
      };
      if (!every_ray()) hit_event();
      std::uint8_t negative = 0;
      for (int a = 0; a < 3; ++a) negative |= r.end[a] < origin_[a] ? static_cast<std::uint8_t>(1u << a) : 0;
      std::size_t run = 0;
      traverse_ray(origin_, r.end, origin_key_, r.key, resolution_, [&](const OctreeKey& k, int axis) {
        if (axis >= 0 && (k[axis] >> shift) == (out.events[run].key[axis] >> shift)) {
          out.push_step(axis);
          ++out.events[run].count;
          return;
        }
        run = out.events.size();
        out.events.push_back({grid_.index(k), static_cast<std::uint32_t>(c), out.used, 0, k, 0, negative});
      });
      if (every_ray()) hit_event();
    }
  }

  void run_buckets(int threads) {
    ThreadTeam team(threads);
    // Step 2a: record the runs of every chunk of rays.
    const std::size_t chunks = (rays_.size() + kChunkRays - 1) / kChunkRays;
    std::vector<Chunk> recorded(chunks);
    std::atomic<std::size_t> next_chunk{0};
    team.run([&](int) {
      for (std::size_t c; (c = next_chunk.fetch_add(1)) < chunks;) record_chunk(c, recorded[c]);
    });
    // Sort the events by bucket, stably (counting sort).
    std::vector<std::uint32_t> start(grid_.size() + 1, 0);
    for (const Chunk& ch : recorded) {
      for (const Event& e : ch.events) ++start[e.bucket + 1];
    }
    for (std::size_t b = 0; b < grid_.size(); ++b) start[b + 1] += start[b];
    std::vector<Event> events(start.back());
    {
      std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
      for (Chunk& ch : recorded) {
        for (const Event& e : ch.events) events[next[e.bucket]++] = e;
        std::vector<Event>().swap(ch.events);
      }
    }
    std::vector<std::uint32_t> buckets;
    for (std::uint32_t b = 0; b < grid_.size(); ++b) {
      if (start[b + 1] > start[b]) buckets.push_back(b);
    }
    // Steps 2b and 3: the buckets, in parallel.
    std::vector<OctreeKey> corners;
    for (const std::uint32_t b : buckets) corners.push_back(grid_.corner(b));
    std::vector<CellSet> cells(static_cast<std::size_t>(threads));
    update_subtrees(team, corners, kOctreeDepth - grid_.shift, [&](int t, std::size_t i, SubtreeUpdater& up) {
      update_bucket(up, events, start[buckets[i]], start[buckets[i] + 1], recorded, cells[static_cast<std::size_t>(t)]);
    });
  }

  void update_bucket(SubtreeUpdater& up, const std::vector<Event>& events, std::uint32_t begin, std::uint32_t end,
                     const std::vector<Chunk>& recorded, CellSet& cells) const {
    const auto walk = [&](const Event& e, const auto& visit) {
      OctreeKey k = e.key;
      visit(k);
      const Chunk& ch = recorded[e.chunk];
      for (std::uint32_t s = 0; s < e.count; ++s) {
        const int axis = ch.step_at(e.offset + s);
        k[axis] = static_cast<std::uint16_t>(((e.negative >> axis) & 1u) != 0 ? k[axis] - 1 : k[axis] + 1);
        visit(k);
      }
    };
    if (every_ray()) {
      for (std::uint32_t i = begin; i < end; ++i) {
        const Event& e = events[i];
        if (e.hit) {
          up.apply(e.key, UpdateKind::Delta, params_.hit);
        } else {
          walk(e, [&](const OctreeKey& k) { up.apply(k, UpdateKind::Delta, params_.miss); });
        }
      }
      return;
    }
    cells.clear();
    CellSet::Cursor cursor;
    for (std::uint32_t i = begin; i < end; ++i) {
      if (events[i].hit) {
        cells.insert(events[i].key, cursor, true);
      } else {
        walk(events[i], [&](const OctreeKey& k) { cells.insert(k, cursor); });
      }
    }
    cells.for_each_in_tree_order([&](const OctreeKey& k, bool occupied) {
      up.apply(k, occupied ? UpdateKind::ScanHit : UpdateKind::ScanMiss, 0.0f);
    });
  }

  OccupancyOctree& tree_;
  OctreeStore& store_;
  UpdateParams params_;
  OctreeInsertOptions options_;
  double resolution_;
  double inv_resolution_;
  P origin_[3];
  OctreeKey origin_key_;
  std::vector<Ray<P>> rays_;
  BucketGrid grid_;
  OctreeInsertResult result_;
};

}  // namespace
}  // namespace detail

OctreeInsertResult OccupancyOctree::insert_point_cloud(std::span<const Eigen::Vector3f> points,
                                                       const Eigen::Vector3d& origin,
                                                       const OctreeInsertOptions& options) {
  ROVE_CHECK_MSG(std::isfinite(options.max_range), "max_range must be finite (< 0 for no limit)");
  if (options.arithmetic == OctreeRayArithmetic::OctoMap) {
    return detail::CloudInsertion<float>(*this, points, origin, options).run();
  }
  return detail::CloudInsertion<double>(*this, points, origin, options).run();
}

OctreeInsertResult OccupancyOctree::insert_point_cloud(std::span<const Eigen::Vector3f> points,
                                                       std::span<const Rgb8> colors, const Eigen::Vector3d& origin,
                                                       const OctreeInsertOptions& options, OctreeColorUpdate how) {
  ROVE_CHECK_MSG(has_channels(channels_, OctreeChannels::Color),
                 "a coloured cloud needs an octree with the Color channel");
  ROVE_CHECK_EQ(colors.size(), points.size());
  OctreeInsertResult r = insert_point_cloud(points, origin, options);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto k = key_of(points[i].cast<double>());
    if (k) update_color(*k, colors[i], how);
  }
  return r;
}

}  // namespace rove
