#pragma once
/// \file
/// OccupancyOctree: a 3D occupancy map in an octree with OctoMap's semantics
/// (Hornung et al., "OctoMap: an efficient probabilistic 3D mapping framework
/// based on octrees", Autonomous Robots 2013): every node holds the log-odds
/// of its cell being occupied, updated with a hit/miss sensor model and
/// clamped; inner nodes hold the maximum of their children; 8 leaf children
/// with equal values are pruned into their parent. Keys, depths, child
/// order, defaults and files are OctoMap 1.9's (docs/octree.md).
///
/// Frames and units: points and the sensor origin are in the map frame,
/// meters; the tree covers [−32768, 32768) · resolution on each axis.
///
/// Storage: nodes live in blocks of 8 siblings (8 bytes a node: the float
/// log-odds and the index of the children's block), allocated from pooled
/// segments, so a tree costs about a third of OctoMap's memory.
///
/// Thread-safety: const member functions may run concurrently from several
/// threads while no non-const member runs (they read, cache nothing).
/// Insertion can use several threads itself (OctreeInsertOptions::
/// num_threads); its result does not depend on their number.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "rove/core/config_section.h"
#include "rove/maps/octree_key.h"
#include "rove/maps/point_cloud.h"

namespace rove {

namespace detail {
class OctreeStore;
struct OctreeAccess;
}

/// The sensor model and clamping, as probabilities (OctoMap's defaults).
/// They are kept as float log-odds, log(p / (1 − p)) rounded to float, as
/// OctoMap does.
struct OccupancyOctreeParams {
  double prob_hit = 0.7;              ///< p(occupied) of a cell a ray ends in
  double prob_miss = 0.4;             ///< p(occupied) of a cell a ray crosses
  double clamping_min = 0.1192;       ///< lower clamp of a cell's probability
  double clamping_max = 0.971;        ///< upper clamp of a cell's probability
  double occupancy_threshold = 0.5;   ///< occupied when p ≥ this
  /// Reads MRPT's keys `probHit`, `probMiss`, `clampingThresMin`,
  /// `clampingThresMax`, `occupancyThres` over the defaults; throws
  /// ConfigError naming the key unless check() passes.
  static OccupancyOctreeParams from_config(const ConfigSection& section);
  /// Throws InvalidArgument unless every probability is in (0, 1),
  /// prob_hit ≥ 0.5 ≥ prob_miss and clamping_min ≤ clamping_max.
  void check() const;
};

/// Which per-node channels a tree carries besides the log-odds (bit set).
enum class OctreeChannels : std::uint8_t {
  None = 0,        ///< occupancy only (OctoMap's OcTree)
  Color = 1,       ///< an RGB colour per node (OctoMap's ColorOcTree)
  Statistics = 2,  ///< hit and miss counts per leaf
};
/// Union of channel sets.
constexpr OctreeChannels operator|(OctreeChannels a, OctreeChannels b) noexcept {
  return static_cast<OctreeChannels>(static_cast<std::uint8_t>(a) | static_cast<std::uint8_t>(b));
}
/// True when `set` holds every channel of `c`.
constexpr bool has_channels(OctreeChannels set, OctreeChannels c) noexcept {
  return (static_cast<std::uint8_t>(set) & static_cast<std::uint8_t>(c)) == static_cast<std::uint8_t>(c);
}

/// How a point cloud updates the cells (OctoMap's three insertion calls).
enum class OctreeUpdateMode : std::uint8_t {
  /// Each cell is updated once per cloud: as occupied if some ray ends in
  /// it, else as free if some ray crosses it (OctoMap's insertPointCloud).
  OncePerScan = 0,
  /// As OncePerScan, after replacing the points by the centres of the
  /// distinct cells they fall in (insertPointCloud with discretize = true).
  Discretized = 1,
  /// Every ray updates the cells it crosses and its end cell, ray after ray
  /// in cloud order, repeats included (OctoMap's insertPointCloudRays; it
  /// ignores max_range, as OctoMap does).
  EveryRay = 2,
};

/// The floating-point arithmetic of ray traversal.
enum class OctreeRayArithmetic : std::uint8_t {
  /// Points, directions and distances in double.
  Double = 0,
  /// OctoMap 1.9's mix (float points and directions, double distances),
  /// which reproduces its cells exactly, ties included (octree_rays.h).
  OctoMap = 1,
};

/// Options of OccupancyOctree::insert_point_cloud.
struct OctreeInsertOptions {
  /// Rays longer than this (meters) are cut to it and their end is not
  /// marked occupied; < 0: no limit (OctoMap's maxrange).
  double max_range = -1.0;
  /// How cells are updated.
  OctreeUpdateMode mode = OctreeUpdateMode::OncePerScan;
  /// Leave inner nodes and pruning for later (OctoMap's lazy_eval): leaves
  /// are exact, inner values stale until update_inner_occupancy() / prune().
  bool lazy = false;
  /// Ray traversal arithmetic.
  OctreeRayArithmetic arithmetic = OctreeRayArithmetic::Double;
  /// Skip points that are not finite or fall outside the tree (counted in
  /// the result) instead of throwing InvalidArgument.
  bool skip_invalid_points = false;
  /// Threads (1–256; 0 = every hardware thread). The tree does not depend
  /// on the number.
  int num_threads = 1;
};

/// Why an insertion ended.
enum class OctreeInsertTermination : std::uint8_t {
  Inserted = 0,         ///< every point was used
  SkippedPoints = 1,    ///< some points were skipped (skip_invalid_points)
};

/// What insert_point_cloud did.
struct OctreeInsertResult {
  /// Whether every point was used.
  OctreeInsertTermination termination = OctreeInsertTermination::Inserted;
  /// One line saying what happened.
  std::string message;
  /// Points given.
  std::size_t points = 0;
  /// Points skipped: not finite or outside the tree.
  std::size_t skipped_points = 0;
  /// Cells updated as occupied / as free (after the mode's deduplication).
  std::size_t occupied_updates = 0;
  /// See occupied_updates.
  std::size_t free_updates = 0;
  /// True when every point was used.
  bool ok() const noexcept { return termination == OctreeInsertTermination::Inserted; }
};

/// Options of OccupancyOctree::cast_ray (OctoMap's castRay arguments).
struct OctreeRayCastOptions {
  /// Continue through unknown cells instead of stopping at the first one.
  bool ignore_unknown = false;
  /// Stop beyond this distance (meters, to the centre of the cell); ≤ 0:
  /// no limit.
  double max_range = -1.0;
  /// Ray traversal arithmetic.
  OctreeRayArithmetic arithmetic = OctreeRayArithmetic::Double;
};

/// Where a cast ray stopped.
enum class OctreeRayCastTermination : std::uint8_t {
  Hit = 0,        ///< in an occupied cell
  Unknown = 1,    ///< in an unknown cell (ignore_unknown off)
  MaxRange = 2,   ///< at the first cell beyond max_range
  EdgeOfMap = 3,  ///< at the edge of the tree
};

/// Result of OccupancyOctree::cast_ray.
struct OctreeRayCastResult {
  /// Where and why it stopped.
  OctreeRayCastTermination termination = OctreeRayCastTermination::Unknown;
  /// The finest cell it stopped in.
  OctreeKey key;
  /// That cell's centre, map frame, meters.
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
  /// True when the ray hit an occupied cell (OctoMap's return value).
  bool hit() const noexcept { return termination == OctreeRayCastTermination::Hit; }
};

/// Hit and miss counts of a leaf (OctreeChannels::Statistics): the updates
/// each finest cell under it received, saturating at 2^32 − 1.
struct OctreeLeafStatistics {
  std::uint32_t hits = 0;    ///< updates as occupied
  std::uint32_t misses = 0;  ///< updates as free
  /// Equality.
  friend bool operator==(const OctreeLeafStatistics&, const OctreeLeafStatistics&) = default;
};

/// A node found by a query.
struct OctreeNodeInfo {
  float log_odds = 0.0f;  ///< its log-odds
  int depth = 0;          ///< 0 = root, 16 = finest cell
  bool leaf = true;       ///< no children
};

/// A leaf: the cell `key` at `depth` (a pruned leaf at depth < 16 covers
/// 8^(16 − depth) finest cells).
struct OctreeLeaf {
  OctreeKey key;           ///< lower-corner key (octree_key_at_depth)
  int depth = kOctreeDepth;  ///< 1..16 (0 only for a childless root)
  float log_odds = 0.0f;   ///< its log-odds
};

/// How a colour measurement changes a leaf's colour (OctoMap's ColorOcTree
/// methods). A leaf whose colour is white (255, 255, 255) has none yet and
/// takes the measurement as it is.
enum class OctreeColorUpdate : std::uint8_t {
  Set = 0,        ///< replace (setNodeColor)
  Average = 1,    ///< (old + new) / 2 per channel, integer (averageNodeColor)
  Integrate = 2,  ///< old · p + new · (0.99 − p), p the leaf's occupancy
                  ///< probability, truncated (integrateNodeColor)
};

/// Changes recorded while change detection is on: the finest cells created
/// (`created`) or whose occupancy flipped, as OctoMap's changed-keys map.
struct OctreeChange {
  OctreeKey key;         ///< the cell
  bool created = false;  ///< new since the last reset (else: flipped)
};

/// A node as OctoMap's files list them, in depth-first pre-order.
struct OctreeNodeRecord {
  OctreeKey key;              ///< lower-corner key of the node
  int depth = 0;              ///< 0 = root
  float log_odds = 0.0f;      ///< its log-odds
  std::uint8_t child_mask = 0;  ///< bit i: child i exists
  Rgb8 color{255, 255, 255};  ///< its colour (white without the channel)
  OctreeLeafStatistics statistics;  ///< its counts (zero without the channel)
};

/// The octree (see the file comment).
class OccupancyOctree {
 public:
  /// An empty tree of finest cells `resolution` meters wide. Throws
  /// InvalidArgument unless octree_resolution_valid(resolution) and params
  /// pass their check.
  explicit OccupancyOctree(double resolution, OccupancyOctreeParams params = {},
                           OctreeChannels channels = OctreeChannels::None);
  ~OccupancyOctree();
  /// Deep copy.
  OccupancyOctree(const OccupancyOctree& other);
  /// Deep copy.
  OccupancyOctree& operator=(const OccupancyOctree& other);
  /// Move.
  OccupancyOctree(OccupancyOctree&&) noexcept;
  /// Move.
  OccupancyOctree& operator=(OccupancyOctree&&) noexcept;

  // --- geometry ------------------------------------------------------
  /// Edge of a finest cell, meters.
  double resolution() const noexcept { return resolution_; }
  /// Edge of a node at `depth` (0 = root), meters.
  double node_size(int depth) const;
  /// The sensor model.
  const OccupancyOctreeParams& params() const noexcept { return params_; }
  /// The channels carried.
  OctreeChannels channels() const noexcept { return channels_; }
  /// The finest cell holding `p`, or nullopt if p is not finite or outside
  /// the tree (key = floor(p / resolution) + 32768, OctoMap's coordToKey).
  std::optional<OctreeKey> key_of(const Eigen::Vector3d& p) const noexcept;
  /// As key_of(); throws InvalidArgument naming p if there is none.
  OctreeKey key_checked(const Eigen::Vector3d& p) const;
  /// Centre of the node at `depth` containing `key` (OctoMap's keyToCoord).
  Eigen::Vector3d center_of(const OctreeKey& key, int depth = kOctreeDepth) const;

  // --- sensor model as stored -----------------------------------------
  /// log-odds of a hit, as stored (float).
  float hit_log_odds() const noexcept { return hit_; }
  /// log-odds of a miss.
  float miss_log_odds() const noexcept { return miss_; }
  /// Lower clamp, log-odds.
  float clamp_min_log_odds() const noexcept { return clamp_min_; }
  /// Upper clamp, log-odds.
  float clamp_max_log_odds() const noexcept { return clamp_max_; }
  /// Occupancy threshold, log-odds.
  float threshold_log_odds() const noexcept { return threshold_; }
  /// True when `log_odds` means occupied (≥ the threshold, as OctoMap).
  bool is_occupied(float log_odds) const noexcept { return log_odds >= threshold_; }

  // --- queries -------------------------------------------------------
  /// The deepest node on the path to `key` at `depth` or above that exists
  /// when the path ends in a leaf, nullopt when it ends at an inner node
  /// without the needed child or the tree is empty (OctoMap's search).
  std::optional<OctreeNodeInfo> search(const OctreeKey& key, int depth = kOctreeDepth) const;
  /// search() at the cell holding `p`; throws InvalidArgument if p is not
  /// finite or outside the tree.
  std::optional<OctreeNodeInfo> search(const Eigen::Vector3d& p) const;
  /// The colour of the leaf holding `key` (nullopt: unknown or no colour
  /// channel).
  std::optional<Rgb8> color_at(const OctreeKey& key) const;
  /// The statistics of the leaf holding `key` (nullopt: unknown or no
  /// statistics channel).
  std::optional<OctreeLeafStatistics> statistics_at(const OctreeKey& key) const;

  // --- updates (one cell) --------------------------------------------
  /// Adds `log_odds_delta` to the finest cell `key` (creating it and its
  /// path at 0, expanding a pruned ancestor), clamps, then updates the inner
  /// nodes and prunes on the path (OctoMap's updateNode). A cell already at
  /// the clamp the update pushes towards is left as it is.
  void update_node(const OctreeKey& key, float log_odds_delta);
  /// update_node() with the hit or miss log-odds.
  void update_node(const OctreeKey& key, bool occupied);
  /// Sets cell `key` to `log_odds` clamped to the clamping range
  /// (OctoMap's setNodeValue).
  void set_node_value(const OctreeKey& key, float log_odds);
  /// Changes the colour of the deepest existing node holding `key` (a
  /// pruned leaf, if that is where the path ends) and refreshes the colours
  /// of its ancestors. Returns false if that cell is unknown. Precondition:
  /// the tree has the Color channel.
  bool update_color(const OctreeKey& key, Rgb8 color, OctreeColorUpdate how);

  // --- clouds --------------------------------------------------------
  /// Inserts the rays from `origin` to each point (map frame, meters), see
  /// OctreeUpdateMode. Throws InvalidArgument if origin is not finite or
  /// outside the tree, or (unless options.skip_invalid_points) naming the
  /// first point that is not finite or outside the tree; a ray cut by
  /// max_range only needs its cut end inside.
  OctreeInsertResult insert_point_cloud(std::span<const Eigen::Vector3f> points,
                                        const Eigen::Vector3d& origin,
                                        const OctreeInsertOptions& options = {});
  /// As above, then updates the colour of the cell each point falls in with
  /// its colour, in point order (MRPT's CColouredOctoMap). Precondition:
  /// the Color channel and one colour per point.
  OctreeInsertResult insert_point_cloud(std::span<const Eigen::Vector3f> points,
                                        std::span<const Rgb8> colors, const Eigen::Vector3d& origin,
                                        const OctreeInsertOptions& options = {},
                                        OctreeColorUpdate how = OctreeColorUpdate::Integrate);
  /// The cells a ray from `origin` to `end` crosses, `origin`'s first,
  /// `end`'s excluded (OctoMap's computeRayKeys; empty when both are in one
  /// cell). Throws InvalidArgument if either is not finite or outside.
  std::vector<OctreeKey> ray_keys(const Eigen::Vector3d& origin, const Eigen::Vector3d& end,
                                  OctreeRayArithmetic arithmetic = OctreeRayArithmetic::Double) const;
  /// Follows a ray from `origin` along `direction` until an occupied cell
  /// (OctoMap's castRay). Throws InvalidArgument if origin is not finite or
  /// outside the tree, or direction is zero or not finite.
  OctreeRayCastResult cast_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                               const OctreeRayCastOptions& options = {}) const;

  // --- whole tree ----------------------------------------------------
  /// Prunes every node whose 8 children are leaves with equal values
  /// (and equal statistics), bottom-up (OctoMap's prune).
  void prune();
  /// Expands every pruned leaf down to depth 16 (OctoMap's expand).
  void expand();
  /// Recomputes every inner node (maximum of the children's log-odds, mean
  /// of their colours) (OctoMap's updateInnerOccupancy).
  void update_inner_occupancy();
  /// Sets every node to the clamp of its side of the threshold
  /// (OctoMap's toMaxLikelihood).
  void to_max_likelihood();
  /// Removes every node (keeps resolution, parameters, channels).
  void clear();

  /// Turns recording of changed cells on or off (OctoMap's
  /// enableChangeDetection); turning it off keeps what was recorded.
  void enable_change_detection(bool on) noexcept { change_detection_ = on; }
  /// Whether changes are recorded.
  bool change_detection() const noexcept { return change_detection_; }
  /// The changes recorded, sorted by key.
  std::vector<OctreeChange> changes() const;
  /// Forgets the recorded changes.
  void reset_changes();

  // --- iteration and statistics --------------------------------------
  /// Calls fn for every leaf (pruned leaves once, at their depth), in
  /// depth-first child order.
  void for_each_leaf(const std::function<void(const OctreeLeaf&)>& fn) const;
  /// Calls fn for every leaf that intersects the box [min, max] (meters).
  void for_each_leaf_in_box(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                            const std::function<void(const OctreeLeaf&)>& fn) const;
  /// All leaves, in for_each_leaf order.
  std::vector<OctreeLeaf> leaves() const;
  /// Calls fn for every node in depth-first pre-order (children 0..7), the
  /// root first (what OctoMap's files store).
  void for_each_node(const std::function<void(const OctreeNodeRecord&)>& fn) const;
  /// Replaces the content by `nodes`, given in depth-first pre-order as
  /// for_each_node lists them (keys and depths are implied and ignored). An
  /// inner node whose log_odds is NaN gets the maximum of its children's.
  /// Throws InvalidArgument if the list is not one tree of at most 17
  /// levels, holds fewer or more nodes than the masks imply, or a leaf's
  /// log-odds is not finite.
  void assign_preorder(std::span<const OctreeNodeRecord> nodes);
  /// Nodes, inner and leaves (OctoMap's size()).
  std::size_t num_nodes() const noexcept { return num_nodes_; }
  /// Leaves.
  std::size_t num_leaves() const;
  /// True when the tree has no node.
  bool empty() const noexcept { return num_nodes_ == 0; }
  /// Bytes held by the node storage, including pooled free blocks.
  std::size_t memory_usage() const noexcept;
  /// Box covering every leaf (OctoMap's getMetricMin/Max); empty box
  /// (min > max) for an empty tree.
  void metric_bounds(Eigen::Vector3d& min, Eigen::Vector3d& max) const;

 private:
  friend struct detail::OctreeAccess;
  double resolution_;
  double inv_resolution_;
  OccupancyOctreeParams params_;
  OctreeChannels channels_;
  float hit_, miss_, clamp_min_, clamp_max_, threshold_;
  std::unique_ptr<detail::OctreeStore> store_;
  std::size_t num_nodes_ = 0;
  bool change_detection_ = false;
  std::unordered_map<OctreeKey, bool, OctreeKeyHash> changes_;  // key -> created
};

/// True when `resolution` (meters) can make a tree: a normal, finite number
/// > 0 whose inverse and the tree's extent (2^16 · resolution) are finite.
bool octree_resolution_valid(double resolution) noexcept;
/// log(p / (1 − p)) rounded to float (OctoMap's logodds).
float octree_log_odds(double probability) noexcept;
/// 1 − 1 / (1 + exp(log_odds)) (OctoMap's probability).
double octree_probability(double log_odds) noexcept;

}  // namespace rove
