#pragma once
// Updates of OccupancyOctree's cells (internal): OctoMap's updateNode,
// applied to many keys in a row, then finalized once.
//
// OctoMap updates one key at a time: it descends from the root, creating
// missing nodes (log-odds 0) and expanding pruned leaves (8 children with
// the leaf's value), updates the finest cell, and on the way back up prunes
// every node whose 8 children are equal leaves, or sets it to the maximum
// of its children. Pruning and expanding undo each other exactly, so the
// tree after a sequence of updates is the same when the pruning and the
// inner values are computed once at the end over the touched paths: that is
// what this engine does. A Cursor keeps the path of the last key, so the
// next key (a neighbour along a ray) descends only from their common
// ancestor. Touched nodes are marked in their block's dirty byte; a dirty
// finest cell is one already updated by the current scan, which is how a
// scan updates each cell once.
#include <cstdint>
#include <vector>

#include "octree_store.h"
#include "rove/maps/occupancy_octree.h"

namespace rove::detail {

// What the engine needs from the tree.
struct UpdateParams {
  float hit = 0.0f;
  float miss = 0.0f;
  float clamp_min = 0.0f;
  float clamp_max = 0.0f;
  float threshold = 0.0f;
  bool colors = false;
  bool statistics = false;
  bool change_detection = false;
};

struct OctreeAccess {
  static OctreeStore& store(OccupancyOctree& t) noexcept { return *t.store_; }
  static const OctreeStore& store(const OccupancyOctree& t) noexcept { return *t.store_; }
  static std::size_t& num_nodes(OccupancyOctree& t) noexcept { return t.num_nodes_; }
  static std::unordered_map<OctreeKey, bool, OctreeKeyHash>& changes(OccupancyOctree& t) noexcept {
    return t.changes_;
  }
  static UpdateParams params(const OccupancyOctree& t) noexcept;
};

// How one key is updated.
enum class UpdateKind : std::uint8_t {
  Delta,      // add `value` (OctoMap's updateNode, early abort at the clamp)
  Set,        // set to `value`, already clamped (setNodeValue)
  ScanHit,    // a scan's occupied cell: once per scan, never aborted early
  ScanMiss,   // a scan's free cell: once per scan (skipped if already updated)
};

// A change of a finest cell, for OctoMap's changed-keys map.
struct ChangeEvent {
  OctreeKey key;
  bool created;
};

// Applies updates below one node (the subtree's root, at `root_depth`),
// from one thread. Several updaters may run at once on disjoint subtrees
// with their own allocators.
class SubtreeUpdater {
 public:
  SubtreeUpdater(OctreeStore& store, BlockAllocator& alloc, const UpdateParams& params,
                 std::uint32_t root, int root_depth, bool root_fresh);

  void apply(const OctreeKey& key, UpdateKind kind, float value);
  // The node at `depth` on the path to `key`, created (or expanded into)
  // when missing and marked dirty; `fresh` tells whether it was created now.
  std::uint32_t reach(const OctreeKey& key, int depth, bool& fresh);

  std::int64_t node_delta = 0;      // nodes created minus nodes deleted
  std::size_t hit_updates = 0;      // occupied updates that reached their cell
  std::size_t miss_updates = 0;     // free updates that reached their cell
  std::vector<ChangeEvent> changes;  // when params.change_detection
  bool changed = false;              // some node was created, expanded or changed

 private:
  struct Reached {
    std::uint32_t id;
    bool fresh;
    bool was_dirty;
    bool aborted;
  };
  Reached descend(const OctreeKey& key, int target_depth, UpdateKind kind, float value, bool may_abort);
  bool aborts(UpdateKind kind, float log_odds, float value) const noexcept;
  void update_leaf(std::uint32_t id, const OctreeKey& key, UpdateKind kind, float value, bool fresh);
  void new_children(std::uint32_t parent, bool expand);

  OctreeStore* store_;
  BlockAllocator* alloc_;
  UpdateParams params_;
  int root_depth_;
  bool root_fresh_;
  int valid_ = -1;                // path_[root_depth_ .. valid_] holds the last key's path
  OctreeKey last_;
  std::uint32_t path_[kOctreeDepth + 1];
};

// Recomputes the touched nodes below `id` (at `depth`), children first:
// prunes a node whose 8 children are equal leaves, else sets it to the
// maximum of its children (and their mean colour); clears the dirty marks.
// With `lazy`, only clears the marks. Stops above `stop_depth` (the nodes
// there belong to other subtrees, finalized already). Freed blocks go to
// `alloc`; returns the change in the node count.
std::int64_t finalize_subtree(OctreeStore& store, BlockAllocator& alloc, const UpdateParams& params,
                              std::uint32_t id, int depth, bool lazy, int stop_depth = kOctreeDepth + 1);

// Prunes node `id` if its 8 children are leaves with equal log-odds (and
// statistics): it takes their value (OctoMap's pruneNode; ColorOcTree's
// colour rule) and its children's block is freed. Returns true if pruned.
bool prune_node(OctreeStore& store, BlockAllocator& alloc, const UpdateParams& params, std::uint32_t id);

// Recomputes node `id` from its children (maximum log-odds, mean colour),
// after trying to prune it when `prune`; returns true if it was pruned.
bool refresh_node(OctreeStore& store, BlockAllocator& alloc, const UpdateParams& params, std::uint32_t id,
                  bool prune);

// OctoMap's getAverageChildColor: the integer mean of the children's colours
// that are not white, white if none.
Rgb8 average_child_color(const OctreeStore& store, std::uint32_t block);

// Finds the deepest existing node on the path to a key, as OctoMap's
// search(key): the leaf the path ends in, or none when it ends at an inner
// node without the needed child. Keeps the last path, so neighbouring keys
// (a ray's cells) are found from their common ancestor.
class LeafFinder {
 public:
  explicit LeafFinder(const OctreeStore& store) : store_(&store) {}
  // Node id and its depth, or false.
  bool find(const OctreeKey& key, std::uint32_t& id, int& depth);

 private:
  const OctreeStore* store_;
  int valid_ = -1;
  OctreeKey last_;
  std::uint32_t path_[kOctreeDepth + 1] = {};
  bool found_ = false;  // whether the last search ended at a node
};

// Creates the root if the tree is empty (marked dirty, fresh) and returns
// whether it was created.
bool ensure_root(OctreeStore& store, std::size_t& num_nodes);

// Merges change events into the tree's map, in order, as OctoMap's
// updateNode records them.
void merge_changes(std::unordered_map<OctreeKey, bool, OctreeKeyHash>& map,
                   const std::vector<ChangeEvent>& events);

}  // namespace rove::detail
