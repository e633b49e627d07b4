#pragma once
/// \file
/// 2D lidar SLAM with loop closure, after Hess et al., "Real-Time Loop
/// Closure in 2D LIDAR SLAM" (ICRA 2016), with a point-based refinement:
///
///  - front-end: each scan's returns (scan_points_2d.h) are matched against
///    the older of the two active submaps, starting from the pose the
///    odometry (or constant velocity) predicts: when the predicted turn is
///    fast, an exhaustive search over rotations first
///    (correlative_search_2d); then least squares on the submap's grid with
///    the prediction as a prior (grid_scan_matcher.h); then point-to-line
///    ICP against the points of the submap's nodes, its correction kept
///    only along well-constrained directions (solution remapping: in a
///    corridor the prediction decides along the axis). The result is the
///    scan's pose in the local frame;
///  - motion filter: a scan that moved far enough from the last node (or
///    after enough time) becomes a node: it is inserted into both active
///    submaps (probability_grid.h); a submap that received
///    2 × scans_per_submap nodes is finished and a new one starts every
///    scans_per_submap nodes;
///  - loop closure: each sampled node is searched against the nearest
///    finished submaps within max_distance by branch-and-bound
///    (branch_and_bound_2d.h) in a window around the current estimate. The
///    best pose must score above min_score and clearly above the best pose
///    elsewhere in the window (a corridor, a row of identical rooms is
///    ambiguous); it is refined against the grid and checked by ICP against
///    the submap's points (whose pose becomes the constraint); and it must
///    imply the same correction of the front-end as another candidate of a
///    nearby node (one wrong match rarely has company). Then it is a
///    constraint;
///  - back-end: a pose graph (rove::graph) whose vertices are the nodes and
///    the submaps: the front-end's edges (consecutive nodes; node in submap,
///    softer) and the loop closures with a Huber kernel, optimized every
///    optimize_every_n_nodes nodes when loops were found, and at finish().
///    New nodes are placed in the world by the latest correction of the
///    local frame.
///
/// Final refinement (finish(), backend.scan_window > 0): the nodes are a
/// sample of the scans, and the scans between them only follow their
/// front-end poses. At the end every scan becomes a vertex of a second
/// graph, joined to the next scan by its front-end motion (the chain's
/// sigmas) and to each of the next scan_window scans by point-to-line ICP
/// of their returns (a pair whose ICP does not converge or leaves a
/// direction free adds nothing); the submaps and the accepted loop
/// closures keep their edges, attached to the scans that were nodes, and
/// the first node stays the anchor. One optimization of that graph gives
/// every scan's pose, and the nodes and submaps take theirs from it.
///
/// Otherwise every scan's pose in the world is its front-end pose moved by
/// the correction of the nodes around it (scan_pose).
///
/// Thread-safety: thread-compatible. Everything runs on the calling thread,
/// except the final refinement's alignments, on backend.num_threads threads
/// (the result does not depend on their number).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "rove/graph/optimizer.h"
#include "rove/graph/pose_graph.h"
#include "rove/math/se2.h"
#include "rove/obs/range_scan_2d.h"
#include "rove/obs/timestamp.h"
#include "rove/slam/branch_and_bound_2d.h"
#include "rove/slam/lidar_slam_options.h"
#include "rove/slam/probability_grid.h"
#include "rove/slam/scan_points_2d.h"

namespace rove {

class IcpTarget2D;

/// Graph vertex ids of the submaps start here (nodes are 0, 1, ...).
inline constexpr VertexId kLidarSubmapVertexBase = 1000000000;

/// A scan kept as a node of the map.
struct LidarSlamNode {
  /// Index of the scan among those given to add_scan.
  std::size_t scan = 0;
  /// The scan's time.
  Timestamp time;
  /// Front-end pose T_local_robot.
  SE2d T_local_robot;
  /// Pose in the world T_world_robot (optimized, or placed by the latest
  /// correction of the local frame).
  SE2d T_world_robot;
  /// The sensor's position on the robot, meters.
  Eigen::Vector2d sensor_origin = Eigen::Vector2d::Zero();
  /// Returns in the robot frame (voxel-filtered), meters.
  std::vector<Eigen::Vector2d> points;
  /// The returns searched for loop closures (adaptive voxel filter).
  std::vector<Eigen::Vector2d> loop_points;
  /// The submaps the node was inserted into.
  std::vector<int> submaps;
  /// The scan itself, when given to add_scan as a shared pointer.
  std::shared_ptr<const RangeScan2D> observation;
};

/// A local map.
struct LidarSubmap {
  /// Frame of the grid in the local frame (the first node's position, no
  /// rotation).
  SE2d T_local_submap;
  /// The grid's frame in the world (optimized).
  SE2d T_world_submap;
  /// The grid, in the submap's frame.
  ProbabilityGrid grid;
  /// Nodes inserted, in order.
  std::vector<std::size_t> nodes;
  /// True once it receives no more nodes.
  bool finished = false;
  /// Max grids for loop closure (built when finished, when enabled).
  std::unique_ptr<PrecomputedGridStack> max_grids;
  /// Points of its nodes in its frame for ICP verification (built on first use).
  std::shared_ptr<const IcpTarget2D> icp_target;

  explicit LidarSubmap(double resolution) : grid(resolution) {}
};

/// Why a loop-closure candidate was not made a constraint.
enum class LoopClosureOutcome {
  Accepted,        ///< added to the graph
  LowScore,        ///< no pose in the window scored above min_score
  IcpFailed,       ///< ICP verification did not converge or paired too few points
  IcpDisagrees,    ///< ICP converged away from the refined pose
  Pending,         ///< verified, waiting for agreeing candidates (during a run only)
  Inconsistent,    ///< verified, but fewer than min_agreeing candidates agreed with it
  Ambiguous,       ///< another pose of the window scores almost as well (a corridor)
};

/// "accepted", "low-score", "icp-failed", "icp-disagrees", "pending",
/// "inconsistent", "ambiguous".
std::string_view to_string(LoopClosureOutcome outcome);

/// One loop-closure search of a node against a submap.
struct LidarLoopClosure {
  std::size_t node = 0;   ///< node index
  int submap = 0;         ///< submap index
  /// Branch-and-bound score (mean probability), 0 when nothing was found.
  double score = 0.0;
  /// Score after refinement.
  double refined_score = 0.0;
  /// Best score of the window farther than ambiguity_radius from the match
  /// (0 when none comes within min_score_margin of it).
  double second_score = 0.0;
  /// The constraint T_submap_robot (refined; the search's start when none).
  SE2d T_submap_robot;
  /// Distance between the refined pose and the search's start (current
  /// estimate), meters and radians.
  double correction_translation = 0.0;
  double correction_rotation = 0.0;
  /// ICP goodness when verified (0 otherwise).
  double icp_goodness = 0.0;
  /// What became of it.
  LoopClosureOutcome outcome = LoopClosureOutcome::LowScore;
  /// Edge index in graph() when accepted.
  std::optional<std::size_t> edge;
};

/// What add_scan did with one scan.
struct LidarSlamScanUpdate {
  /// True if the scan had returns in range (otherwise it was only timed).
  bool has_points = false;
  /// True if it was matched against a submap (false for the first scan).
  bool matched = false;
  /// How well the final pose fits the matched submap: the mean probability
  /// of its cells under the scan's points; 0 if not matched.
  double match_score = 0.0;
  /// True if the grid matcher ran and converged.
  bool match_converged = false;
  /// True if ICP refined the pose (converged).
  bool icp_refined = false;
  /// True if the scan became a node.
  bool node_added = false;
  /// Loop closures searched / accepted with this scan.
  std::size_t loop_searches = 0;
  std::size_t loops_accepted = 0;
  /// True if the graph was optimized after this scan.
  bool optimized = false;
  /// The front-end pose T_local_robot.
  SE2d T_local_robot;
};

/// Counters and timings of a run.
struct LidarSlamStats {
  std::size_t scans = 0;                ///< add_scan calls
  std::size_t scans_without_points = 0; ///< scans with no return in range
  std::size_t matched = 0;              ///< scans matched against a submap
  std::size_t match_not_converged = 0;  ///< grid matches that hit max_iterations
  std::size_t icp_refined = 0;          ///< matches refined by ICP (converged)
  std::size_t correlative_searches = 0; ///< fast turns searched by correlative matching
  double match_score_sum = 0.0;         ///< sum of the matched scans' scores
  std::size_t nodes = 0;                ///< scans kept as nodes
  std::size_t submaps = 0;              ///< submaps started
  std::size_t loop_searches = 0;        ///< loop-closure searches run
  std::size_t loops_low_score = 0;      ///< searches without a pose above min_score
  std::size_t loops_icp_rejected = 0;   ///< candidates ICP did not confirm
  std::size_t loops_inconsistent = 0;   ///< verified candidates no other agreed with
  std::size_t loops_ambiguous = 0;      ///< candidates with a rival pose as good
  std::size_t loops_accepted = 0;       ///< constraints added
  std::size_t optimizations = 0;        ///< graph optimizations run
  std::size_t optimizations_not_converged = 0;  ///< of which did not converge
  double frontend_seconds = 0.0;        ///< preprocessing and matching
  double insertion_seconds = 0.0;       ///< inserting nodes into submaps
  double loop_seconds = 0.0;            ///< loop-closure search (incl. max grids)
  double optimization_seconds = 0.0;    ///< graph optimization
  std::size_t window_edges = 0;         ///< final refinement: scan pairs ICP aligned
  std::size_t window_failed = 0;        ///< final refinement: scan pairs it could not
  double refinement_seconds = 0.0;      ///< final refinement (alignments and optimization)
};

/// The lidar SLAM system. See the file comment.
class LidarSlam {
 public:
  /// Preconditions (InvalidArgument): options.check() passes.
  explicit LidarSlam(LidarSlamOptions options);
  LidarSlam(LidarSlam&&) noexcept;
  LidarSlam& operator=(LidarSlam&&) noexcept;
  ~LidarSlam();

  /// Processes one scan taken at `time` (an invalid time, or one before
  /// the previous scan's, disables the time-based rules for it).
  /// `odometry_increment`: the robot's motion since the previous scan given
  /// to add_scan as odometry measured it, T_previous_robot (meters,
  /// radians), if known; without it the pose is predicted at constant
  /// velocity. Preconditions (InvalidArgument): scan.check() passes;
  /// finish() was not called.
  LidarSlamScanUpdate add_scan(const RangeScan2D& scan, Timestamp time,
                               const std::optional<SE2d>& odometry_increment = std::nullopt);
  /// As above, keeping `scan` with the node it may become (for rebuilding
  /// the map from the scans). Precondition: scan != nullptr.
  LidarSlamScanUpdate add_scan(std::shared_ptr<const RangeScan2D> scan, Timestamp time,
                               const std::optional<SE2d>& odometry_increment = std::nullopt);
  /// Ends the run: the last optimization (when any loop closure was found
  /// since the previous one), then the final refinement over every scan
  /// (backend.scan_window > 0, when there is a node; see the file comment),
  /// and the final poses. Returns the result of the last optimization run
  /// here (std::nullopt when none was). Idempotent: a second call returns
  /// std::nullopt.
  std::optional<GraphOptimizerResult> finish();

  /// Scans given so far.
  std::size_t num_scans() const noexcept { return scans_.size(); }
  /// Time of scan i. Precondition: i < num_scans().
  Timestamp scan_time(std::size_t i) const;
  /// World pose T_world_robot of scan i. After the final refinement, its
  /// vertex's optimized pose. Before it (or without it): a node's is its
  /// optimized pose; a scan between two nodes takes its front-end pose
  /// through the correction C = T_world_robot · T_local_robot⁻¹ of those
  /// nodes, interpolated on SE(2) by the scan's time between theirs (by its
  /// index when times are missing); after the last node, that node's
  /// correction; before the first node, its front-end pose.
  /// Precondition: i < num_scans().
  SE2d scan_pose(std::size_t i) const;
  /// Front-end pose T_local_robot of scan i.
  SE2d scan_local_pose(std::size_t i) const;
  /// The nodes, in order.
  const std::vector<LidarSlamNode>& nodes() const noexcept { return nodes_; }
  /// The submaps, in order.
  const std::vector<LidarSubmap>& submaps() const noexcept { return submaps_; }
  /// Every loop-closure search, in order.
  const std::vector<LidarLoopClosure>& loop_closures() const noexcept { return loops_; }
  /// The pose graph (nodes 0.., submaps kLidarSubmapVertexBase + index).
  const PoseGraph2D& graph() const noexcept { return graph_; }
  /// The result of the last optimization, if any ran.
  const std::optional<GraphOptimizerResult>& last_optimization() const noexcept { return last_opt_; }
  /// Counters and timings.
  const LidarSlamStats& stats() const noexcept { return stats_; }
  /// The options.
  const LidarSlamOptions& options() const noexcept { return options_; }

 private:
  struct ScanRecord {
    Timestamp time;
    SE2d T_local_robot;
    std::ptrdiff_t node = -1;  // last node at or before the scan
    std::vector<Eigen::Vector2d> points;  // returns in the robot frame, until the refinement
  };

  LidarSlamScanUpdate process(const RangeScan2D& scan, std::shared_ptr<const RangeScan2D> keep,
                              Timestamp time, const std::optional<SE2d>& odometry_increment);
  SE2d predict(Timestamp time, const std::optional<SE2d>& odometry_increment) const;
  SE2d match(const std::vector<Eigen::Vector2d>& points, const SE2d& predicted,
             LidarSlamScanUpdate& up);
  bool motion_filter_passes(const SE2d& T_local_robot, Timestamp time) const;
  void add_node(std::size_t scan, Timestamp time, const SE2d& T_local_robot, ScanPoints2D&& pts,
                std::shared_ptr<const RangeScan2D> keep, LidarSlamScanUpdate& up);
  void insert_into_submaps(std::size_t node);
  void finish_submap(int submap);
  void search_loops(std::size_t node, LidarSlamScanUpdate& up);
  LidarLoopClosure close_loop(std::size_t node, int submap);
  SE2d loop_implied_pose(const LidarLoopClosure& lc, std::size_t node) const;
  std::size_t confirm(std::size_t index);
  void accept_loop(std::size_t index);
  void expire_pending(std::size_t node);
  void optimize();
  GraphOptimizerResult refine_scans();
  SE2d world_from_local(const SE2d& T_local) const { return T_world_local_ * T_local; }

  LidarSlamOptions options_;
  GridScanInserter inserter_;
  std::vector<ScanRecord> scans_;
  std::vector<LidarSlamNode> nodes_;
  std::vector<LidarSubmap> submaps_;
  std::vector<int> active_;  // indices of the active submaps, oldest first
  std::vector<std::size_t> sampler_counts_;  // per submap: nodes offered for loop search
  std::vector<LidarLoopClosure> loops_;
  std::vector<std::size_t> pending_;  // loops_ waiting for agreeing candidates
  PoseGraph2D graph_;
  SE2d T_world_local_;
  std::size_t nodes_since_optimization_ = 0;
  std::size_t loops_since_optimization_ = 0;
  std::optional<GraphOptimizerResult> last_opt_;
  std::vector<SE2d> refined_;  // every scan's pose after the final refinement
  std::shared_ptr<const IcpTarget2D> icp_target_;  // the front-end's ICP target
  int icp_target_submap_ = -1;                     // the submap it was built from
  std::size_t icp_target_nodes_ = 0;               // that submap's nodes then
  bool finished_ = false;
  LidarSlamStats stats_;
};

}  // namespace rove
