#include "rove/slam/lidar_slam.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "rove/core/check.h"
#include "rove/core/parallel.h"
#include "rove/core/timer.h"
#include "rove/registration/icp_target_2d.h"
#include "rove/slam/grid_scan_matcher.h"
#include "lidar_icp.h"

namespace rove {
namespace {

LidarSlamOptions checked(LidarSlamOptions o) {
  o.check();
  return o;
}

PoseGraph2D::Information information(double sigma_t, double sigma_r) {
  PoseGraph2D::Information info = PoseGraph2D::Information::Zero();
  info(0, 0) = info(1, 1) = 1.0 / (sigma_t * sigma_t);
  info(2, 2) = 1.0 / (sigma_r * sigma_r);
  return info;
}

// The pose b relative to a: a⁻¹·b.
SE2d between(const SE2d& a, const SE2d& b) { return a.inverse() * b; }

// The final refinement's scan-to-scan ICP: at most this many iterations
// (neighbouring scans start a few centimetres apart), and the scans whose
// targets are built at once (bounds the memory of the KD-trees).
constexpr int kWindowIcpIterations = 20;
constexpr std::size_t kWindowChunk = 512;
// A scan with fewer returns has no usable normals: its pairs fail.
constexpr std::size_t kWindowMinPoints = 3;

}  // namespace

std::string_view to_string(LoopClosureOutcome outcome) {
  switch (outcome) {
    case LoopClosureOutcome::Accepted: return "accepted";
    case LoopClosureOutcome::LowScore: return "low-score";
    case LoopClosureOutcome::IcpFailed: return "icp-failed";
    case LoopClosureOutcome::IcpDisagrees: return "icp-disagrees";
    case LoopClosureOutcome::Pending: return "pending";
    case LoopClosureOutcome::Inconsistent: return "inconsistent";
    case LoopClosureOutcome::Ambiguous: return "ambiguous";
  }
  return "unknown";
}

LidarSlam::LidarSlam(LidarSlamOptions options)
    : options_(checked(std::move(options))), inserter_(options_.submaps.odds) {}
LidarSlam::LidarSlam(LidarSlam&&) noexcept = default;
LidarSlam& LidarSlam::operator=(LidarSlam&&) noexcept = default;
LidarSlam::~LidarSlam() = default;

LidarSlamScanUpdate LidarSlam::add_scan(const RangeScan2D& scan, Timestamp time,
                                        const std::optional<SE2d>& odometry_increment) {
  return process(scan, nullptr, time, odometry_increment);
}

LidarSlamScanUpdate LidarSlam::add_scan(std::shared_ptr<const RangeScan2D> scan, Timestamp time,
                                        const std::optional<SE2d>& odometry_increment) {
  ROVE_CHECK_MSG(scan != nullptr, "add_scan needs a scan");
  const RangeScan2D& s = *scan;
  return process(s, std::move(scan), time, odometry_increment);
}

Timestamp LidarSlam::scan_time(std::size_t i) const {
  ROVE_CHECK_LT(i, scans_.size());
  return scans_[i].time;
}

SE2d LidarSlam::scan_local_pose(std::size_t i) const {
  ROVE_CHECK_LT(i, scans_.size());
  return scans_[i].T_local_robot;
}

SE2d LidarSlam::scan_pose(std::size_t i) const {
  ROVE_CHECK_LT(i, scans_.size());
  if (!refined_.empty()) return refined_[i];
  const ScanRecord& r = scans_[i];
  // Node 0 is the graph's anchor at its front-end pose: the scans before it
  // keep theirs.
  if (r.node < 0) return r.T_local_robot;
  const LidarSlamNode& a = nodes_[static_cast<std::size_t>(r.node)];
  const SE2d C_a = a.T_world_robot * a.T_local_robot.inverse();
  const auto next = static_cast<std::size_t>(r.node) + 1;
  if (a.scan == i || next >= nodes_.size()) return C_a * r.T_local_robot;
  // Between nodes a and b: the correction moves smoothly from a's to b's,
  // so that the scans of a loop-corrected stretch do not jump at b.
  const LidarSlamNode& b = nodes_[next];
  const SE2d C_b = b.T_world_robot * b.T_local_robot.inverse();
  double s = static_cast<double>(i - a.scan) / static_cast<double>(b.scan - a.scan);
  if (r.time.valid() && a.time.valid() && b.time.valid()) {
    const double span = b.time.to_seconds() - a.time.to_seconds();
    if (span > 0.0) s = std::clamp((r.time.to_seconds() - a.time.to_seconds()) / span, 0.0, 1.0);
  }
  return C_a * SE2d::exp(s * between(C_a, C_b).log()) * r.T_local_robot;
}

SE2d LidarSlam::predict(Timestamp time, const std::optional<SE2d>& odometry_increment) const {
  if (scans_.empty()) return SE2d();
  const ScanRecord& last = scans_.back();
  if (odometry_increment) return last.T_local_robot * *odometry_increment;
  if (scans_.size() < 2 || !time.valid()) return last.T_local_robot;
  const ScanRecord& prev = scans_[scans_.size() - 2];
  if (!prev.time.valid() || !last.time.valid()) return last.T_local_robot;
  const double dt_prev = last.time.to_seconds() - prev.time.to_seconds();
  const double dt = time.to_seconds() - last.time.to_seconds();
  if (!(dt_prev > 0.0) || !(dt >= 0.0) || dt > 10.0 * dt_prev) return last.T_local_robot;
  // Constant velocity: the last motion, scaled to this interval.
  const SE2d::Tangent xi = between(prev.T_local_robot, last.T_local_robot).log() * (dt / dt_prev);
  return last.T_local_robot * SE2d::exp(xi);
}

SE2d LidarSlam::match(const std::vector<Eigen::Vector2d>& points, const SE2d& predicted,
                      LidarSlamScanUpdate& up) {
  const LidarSubmap& s = submaps_[static_cast<std::size_t>(active_.front())];
  up.matched = true;
  ++stats_.matched;
  SE2d pose = predicted;
  const auto& f = options_.frontend;
  if (f.correlative_window.angular_window > 0.0 && !scans_.empty() &&
      std::abs(between(scans_.back().T_local_robot, predicted).angle()) >= f.correlative_min_turn) {
    // A fast turn: the prediction's heading may be off by more than the
    // matchers' basin (odometry and scans out of step).
    const std::vector<Eigen::Vector2d> few = adaptive_voxel_filter_2d(points, f.matching_filter);
    pose = s.T_local_submap *
           correlative_search_2d(s.grid, few, between(s.T_local_submap, predicted), f.correlative_window);
    ++stats_.correlative_searches;
  }
  if (options_.frontend.grid_match) {
    const std::vector<Eigen::Vector2d> matched =
        adaptive_voxel_filter_2d(points, options_.frontend.matching_filter);
    const GridScanMatchResult r = match_scan_to_grid(
        s.grid, matched, between(s.T_local_submap, pose), options_.frontend.matcher);
    up.match_converged = r.ok();
    if (!r.ok()) ++stats_.match_not_converged;
    pose = s.T_local_submap * r.T_grid_robot;
  }
  if (options_.frontend.icp_refine && !s.nodes.empty()) {
    // The target: the points of the matching submap's nodes, rebuilt every
    // icp_rebuild_every nodes (and when the matching submap changes).
    if (icp_target_submap_ != active_.front() ||
        s.nodes.size() >= icp_target_nodes_ + static_cast<std::size_t>(options_.frontend.icp_rebuild_every)) {
      icp_target_ = nodes_icp_target(s.nodes, nodes_, SE2d(), options_.submaps.resolution);
      icp_target_submap_ = active_.front();
      icp_target_nodes_ = s.nodes.size();
    }
    const LidarIcpResult icp = icp_align(*icp_target_, points, pose, options_.frontend.icp_gate,
                                         options_.frontend.icp_remap_threshold);
    if (icp.termination == RegistrationTermination::Converged) {
      pose = icp.T_target_robot;
      ++stats_.icp_refined;
      up.icp_refined = true;
    }
  }
  up.match_score = grid_match_score(s.grid, points, between(s.T_local_submap, pose));
  stats_.match_score_sum += up.match_score;
  return pose;
}

bool LidarSlam::motion_filter_passes(const SE2d& T_local_robot, Timestamp time) const {
  if (nodes_.empty()) return true;
  const LidarSlamNode& last = nodes_.back();
  const SE2d d = between(last.T_local_robot, T_local_robot);
  const auto& f = options_.frontend;
  if (d.translation().norm() >= f.motion_filter_distance) return true;
  if (std::abs(d.angle()) >= f.motion_filter_angle) return true;
  return time.valid() && last.time.valid() &&
         time.to_seconds() - last.time.to_seconds() >= f.motion_filter_time;
}

LidarSlamScanUpdate LidarSlam::process(const RangeScan2D& scan,
                                       std::shared_ptr<const RangeScan2D> keep, Timestamp time,
                                       const std::optional<SE2d>& odometry_increment) {
  ROVE_CHECK_MSG(!finished_, "add_scan after finish()");
  Stopwatch sw;
  ++stats_.scans;
  ScanPoints2D pts = scan_points_2d(scan, options_.frontend.scan);
  const std::optional<SE2d> odometry =
      options_.frontend.use_odometry ? odometry_increment : std::nullopt;
  LidarSlamScanUpdate up;
  SE2d pose = predict(time, odometry);
  up.has_points = !pts.points.empty();
  if (!up.has_points) {
    ++stats_.scans_without_points;
  } else if (!active_.empty()) {
    pose = match(pts.points, pose, up);
  }
  up.T_local_robot = pose;
  const std::ptrdiff_t last_node = static_cast<std::ptrdiff_t>(nodes_.size()) - 1;
  scans_.push_back({time, pose, last_node, {}});
  if (options_.backend.scan_window > 0) scans_.back().points = pts.points;
  stats_.frontend_seconds += sw.elapsed();
  if (up.has_points && motion_filter_passes(pose, time)) {
    add_node(scans_.size() - 1, time, pose, std::move(pts), std::move(keep), up);
  }
  return up;
}

void LidarSlam::add_node(std::size_t scan, Timestamp time, const SE2d& T_local_robot,
                         ScanPoints2D&& pts, std::shared_ptr<const RangeScan2D> keep,
                         LidarSlamScanUpdate& up) {
  const std::size_t id = nodes_.size();
  LidarSlamNode n;
  n.scan = scan;
  n.time = time;
  n.T_local_robot = T_local_robot;
  n.T_world_robot = world_from_local(T_local_robot);
  n.sensor_origin = pts.sensor_origin;
  n.points = std::move(pts.points);
  if (options_.loop_closure.enabled) {
    n.loop_points = adaptive_voxel_filter_2d(n.points, options_.loop_closure.filter);
  }
  n.observation = std::move(keep);
  nodes_.push_back(std::move(n));
  scans_[scan].node = static_cast<std::ptrdiff_t>(id);
  ++stats_.nodes;
  up.node_added = true;

  graph_.add_vertex(id, nodes_[id].T_world_robot, /*fixed=*/id == 0);
  const auto& b = options_.backend;
  if (id > 0) {
    graph_.add_edge(id - 1, id, between(nodes_[id - 1].T_local_robot, T_local_robot),
                    information(b.translation_sigma, b.rotation_sigma));
  }
  Stopwatch sw;
  insert_into_submaps(id);
  stats_.insertion_seconds += sw.elapsed();
  if (options_.loop_closure.enabled) search_loops(id, up);
  ++nodes_since_optimization_;
  if (loops_since_optimization_ > 0 &&
      nodes_since_optimization_ >= static_cast<std::size_t>(b.optimize_every_n_nodes)) {
    optimize();
    up.optimized = true;
  }
}

void LidarSlam::insert_into_submaps(std::size_t node) {
  LidarSlamNode& n = nodes_[node];
  const auto& o = options_.submaps;
  if (active_.empty() ||
      submaps_[static_cast<std::size_t>(active_.back())].nodes.size() >=
          static_cast<std::size_t>(o.scans_per_submap)) {
    LidarSubmap s(o.resolution);
    s.T_local_submap = SE2d(n.T_local_robot.translation().x(), n.T_local_robot.translation().y(), 0.0);
    s.T_world_submap = world_from_local(s.T_local_submap);
    const int index = static_cast<int>(submaps_.size());
    graph_.add_vertex(kLidarSubmapVertexBase + static_cast<VertexId>(index), s.T_world_submap);
    submaps_.push_back(std::move(s));
    sampler_counts_.push_back(0);
    active_.push_back(index);
    ++stats_.submaps;
    if (active_.size() > 2) {
      const int oldest = active_.front();
      active_.erase(active_.begin());
      finish_submap(oldest);
    }
  }
  const auto& b = options_.backend;
  std::vector<Eigen::Vector2d> hits(n.points.size());
  for (const int index : active_) {
    LidarSubmap& s = submaps_[static_cast<std::size_t>(index)];
    const SE2d T_submap_robot = between(s.T_local_submap, n.T_local_robot);
    for (std::size_t i = 0; i < n.points.size(); ++i) hits[i] = T_submap_robot * n.points[i];
    inserter_.insert(s.grid, T_submap_robot * n.sensor_origin, hits);
    s.nodes.push_back(node);
    n.submaps.push_back(index);
    graph_.add_edge(kLidarSubmapVertexBase + static_cast<VertexId>(index), node, T_submap_robot,
                    information(b.submap_translation_sigma, b.submap_rotation_sigma));
  }
}

void LidarSlam::finish_submap(int index) {
  LidarSubmap& s = submaps_[static_cast<std::size_t>(index)];
  s.finished = true;
  if (!options_.loop_closure.enabled) return;
  Stopwatch sw;
  s.max_grids = std::make_unique<PrecomputedGridStack>(s.grid, options_.loop_closure.depth);
  stats_.loop_seconds += sw.elapsed();
}

void LidarSlam::search_loops(std::size_t node, LidarSlamScanUpdate& up) {
  const LidarSlamNode& n = nodes_[node];
  const auto& o = options_.loop_closure;
  expire_pending(node);
  if (n.loop_points.empty() || n.submaps.empty()) return;
  // Finished submaps older than the one before the node's own: those
  // overlap the node's submaps in time and are tied to it by the front-end.
  const int newest_allowed = *std::min_element(n.submaps.begin(), n.submaps.end()) - 2;
  std::vector<std::pair<double, int>> near;
  for (int j = 0; j <= newest_allowed; ++j) {
    const LidarSubmap& s = submaps_[static_cast<std::size_t>(j)];
    if (!s.finished || !s.max_grids) continue;
    const double d = (s.T_world_submap.translation() - n.T_world_robot.translation()).norm();
    if (d <= o.max_distance) near.emplace_back(d, j);
  }
  std::sort(near.begin(), near.end());
  if (near.size() > static_cast<std::size_t>(o.max_submaps_per_node)) {
    near.resize(static_cast<std::size_t>(o.max_submaps_per_node));
  }
  for (const auto& [d, j] : near) {
    // A fixed-ratio sampler per submap: every 1/ratio-th node offered to it.
    std::size_t& count = sampler_counts_[static_cast<std::size_t>(j)];
    ++count;
    const double before = std::floor(static_cast<double>(count - 1) * o.sampling_ratio);
    const double after = std::floor(static_cast<double>(count) * o.sampling_ratio);
    if (after <= before) continue;
    Stopwatch sw;
    loops_.push_back(close_loop(node, j));
    ++stats_.loop_searches;
    ++up.loop_searches;
    switch (loops_.back().outcome) {
      case LoopClosureOutcome::Pending: {
        pending_.push_back(loops_.size() - 1);
        up.loops_accepted += confirm(loops_.size() - 1);
        break;
      }
      case LoopClosureOutcome::LowScore: ++stats_.loops_low_score; break;
      case LoopClosureOutcome::Ambiguous: ++stats_.loops_ambiguous; break;
      default: ++stats_.loops_icp_rejected; break;
    }
    stats_.loop_seconds += sw.elapsed();
  }
}

LidarLoopClosure LidarSlam::close_loop(std::size_t node, int submap) {
  const LidarSlamNode& n = nodes_[node];
  LidarSubmap& s = submaps_[static_cast<std::size_t>(submap)];
  const auto& o = options_.loop_closure;
  LidarLoopClosure lc;
  lc.node = node;
  lc.submap = submap;
  const SE2d initial = between(s.T_world_submap, n.T_world_robot);
  lc.T_submap_robot = initial;
  const BranchAndBoundSearch search(*s.max_grids, n.loop_points, initial, o.window);
  const BranchAndBoundResult b = search.search(o.min_score);
  if (!b.found) {
    lc.outcome = LoopClosureOutcome::LowScore;
    return lc;
  }
  lc.score = b.score;
  // How distinct the match is: the best score of the window more than
  // ambiguity_radius away from it (a corridor, a row of identical rooms).
  const BranchAndBoundResult second =
      search.search(lc.score - o.min_score_margin, b.T_grid_robot.translation(), o.ambiguity_radius);
  lc.second_score = second.found ? second.score : 0.0;
  if (lc.score - lc.second_score < o.min_score_margin) {
    lc.outcome = LoopClosureOutcome::Ambiguous;
    return lc;
  }
  const GridScanMatchResult r = match_scan_to_grid(s.grid, n.loop_points, b.T_grid_robot, o.refine);
  lc.T_submap_robot = r.T_grid_robot;
  lc.refined_score = r.score;
  if (o.verify_with_icp) {
    if (!s.icp_target) {
      s.icp_target =
          nodes_icp_target(s.nodes, nodes_, s.T_local_submap.inverse(), 0.5 * s.grid.resolution());
    }
    const LoopVerification v = verify_loop_with_icp(*s.icp_target, n.points, lc.T_submap_robot, o);
    lc.icp_goodness = v.goodness;
    lc.outcome = v.outcome;
    if (v.outcome != LoopClosureOutcome::Accepted) return lc;
    lc.T_submap_robot = v.T_submap_robot;  // ICP's pose: free of the grid's cell bias
  }
  const SE2d correction = between(initial, lc.T_submap_robot);
  lc.correction_translation = correction.translation().norm();
  lc.correction_rotation = std::abs(correction.angle());
  lc.outcome = LoopClosureOutcome::Pending;
  return lc;
}

SE2d LidarSlam::loop_implied_pose(const LidarLoopClosure& lc, std::size_t node) const {
  // The loop's correction of the local frame, K = (T_local_submap ·
  // T_submap_robot) · T_local_robot⁻¹, applied to `node`'s front-end pose.
  const SE2d& T_local_submap = submaps_[static_cast<std::size_t>(lc.submap)].T_local_submap;
  const SE2d K = T_local_submap * lc.T_submap_robot * nodes_[lc.node].T_local_robot.inverse();
  return K * nodes_[node].T_local_robot;
}

std::size_t LidarSlam::confirm(std::size_t index) {
  const auto& o = options_.loop_closure;
  const LidarLoopClosure& c = loops_[index];
  const SE2d mine = loop_implied_pose(c, c.node);
  std::vector<std::size_t> agreeing;
  for (std::size_t k = index; k-- > 0;) {
    const LidarLoopClosure& q = loops_[k];
    if (q.node + static_cast<std::size_t>(o.agreement_nodes) < c.node) break;
    if (q.outcome != LoopClosureOutcome::Pending && q.outcome != LoopClosureOutcome::Accepted) continue;
    if (std::abs(q.submap - c.submap) > 2) continue;
    const SE2d d = between(mine, loop_implied_pose(q, c.node));
    if (d.translation().norm() <= o.agreement_translation && std::abs(d.angle()) <= o.agreement_rotation) {
      agreeing.push_back(k);
    }
  }
  if (agreeing.size() + 1 < static_cast<std::size_t>(o.min_agreeing)) return 0;
  std::size_t added = 0;
  agreeing.push_back(index);
  for (const std::size_t k : agreeing) {
    if (loops_[k].outcome != LoopClosureOutcome::Pending) continue;
    accept_loop(k);
    ++added;
  }
  std::erase_if(pending_, [&](std::size_t k) { return loops_[k].outcome != LoopClosureOutcome::Pending; });
  return added;
}

void LidarSlam::accept_loop(std::size_t index) {
  const auto& o = options_.loop_closure;
  LidarLoopClosure& lc = loops_[index];
  PoseGraph2D::Edge e;
  e.from = kLidarSubmapVertexBase + static_cast<VertexId>(lc.submap);
  e.to = lc.node;
  e.measurement = lc.T_submap_robot;
  e.information = information(o.translation_sigma, o.rotation_sigma);
  e.kernel = RobustKernel(RobustKernelType::Huber, o.huber_delta);
  lc.edge = graph_.add_edge(e);
  lc.outcome = LoopClosureOutcome::Accepted;
  ++stats_.loops_accepted;
  ++loops_since_optimization_;
}

void LidarSlam::expire_pending(std::size_t node) {
  const auto n = static_cast<std::size_t>(options_.loop_closure.agreement_nodes);
  std::erase_if(pending_, [&](std::size_t k) {
    if (loops_[k].node + n >= node) return false;
    loops_[k].outcome = LoopClosureOutcome::Inconsistent;
    ++stats_.loops_inconsistent;
    return true;
  });
}

void LidarSlam::optimize() {
  Stopwatch sw;
  GraphOptimizerOptions go;
  go.max_iterations = options_.backend.max_iterations;
  GraphOptimizerResult r = rove::optimize(graph_, go);
  ++stats_.optimizations;
  if (!r.ok()) ++stats_.optimizations_not_converged;
  for (std::size_t i = 0; i < nodes_.size(); ++i) nodes_[i].T_world_robot = graph_.pose(i);
  for (std::size_t j = 0; j < submaps_.size(); ++j) {
    submaps_[j].T_world_submap = graph_.pose(kLidarSubmapVertexBase + static_cast<VertexId>(j));
  }
  if (!nodes_.empty()) {
    const LidarSlamNode& last = nodes_.back();
    T_world_local_ = last.T_world_robot * last.T_local_robot.inverse();
  }
  last_opt_ = std::move(r);
  nodes_since_optimization_ = 0;
  loops_since_optimization_ = 0;
  stats_.optimization_seconds += sw.elapsed();
}

GraphOptimizerResult LidarSlam::refine_scans() {
  Stopwatch sw;
  const auto& b = options_.backend;
  const std::size_t n = scans_.size();
  PoseGraph2D g;
  const std::size_t anchor = nodes_.front().scan;
  for (std::size_t i = 0; i < n; ++i) g.add_vertex(i, scan_pose(i), /*fixed=*/i == anchor);
  for (std::size_t j = 0; j < submaps_.size(); ++j) {
    const VertexId id = kLidarSubmapVertexBase + static_cast<VertexId>(j);
    g.add_vertex(id, graph_.pose(id));
  }
  // The front-end's motion between consecutive scans, as the chain of nodes.
  const PoseGraph2D::Information chain = information(b.translation_sigma, b.rotation_sigma);
  for (std::size_t i = 1; i < n; ++i) {
    g.add_edge(i - 1, i, between(scans_[i - 1].T_local_robot, scans_[i].T_local_robot), chain);
  }
  // The submaps' and loop closures' edges, on the scans that were nodes
  // (the node-to-node chain is replaced by the scans' chain above).
  const auto to_scan = [&](VertexId v) {
    return v >= kLidarSubmapVertexBase ? v : static_cast<VertexId>(nodes_[v].scan);
  };
  for (PoseGraph2D::Edge e : graph_.edges()) {
    if (e.from < kLidarSubmapVertexBase && e.to < kLidarSubmapVertexBase) continue;
    e.from = to_scan(e.from);
    e.to = to_scan(e.to);
    g.add_edge(e);
  }
  // Each scan aligned with the next scan_window ones, a chunk of scans at a
  // time: their targets built in parallel, then every pair's ICP in
  // parallel, then the edges added in order (the same graph for any number
  // of threads).
  const auto window = static_cast<std::size_t>(b.scan_window);
  const PoseGraph2D::Information window_info =
      information(b.scan_window_translation_sigma, b.scan_window_rotation_sigma);
  ThreadTeam team(resolve_thread_count(b.num_threads, "[backend] num_threads"));
  IcpTarget2DOptions target_options;
  target_options.normal_neighbors = 5;
  for (std::size_t begin = 0; begin < n; begin += kWindowChunk) {
    const std::size_t end = std::min(n, begin + kWindowChunk);
    std::vector<std::unique_ptr<IcpTarget2D>> targets(end - begin);
    parallel_for(end - begin, team, [&](std::size_t k) {
      const auto& pts = scans_[begin + k].points;
      if (pts.size() >= kWindowMinPoints) {
        targets[k] = std::make_unique<IcpTarget2D>(pts, target_options);
      }
    });
    struct Pair {
      std::size_t from = 0, to = 0;
    };
    std::vector<Pair> pairs;
    for (std::size_t i = begin; i < end; ++i) {
      if (scans_[i].points.empty()) continue;
      for (std::size_t j = i + 1; j < n && j <= i + window; ++j) {
        if (!scans_[j].points.empty()) pairs.push_back({i, j});
      }
    }
    std::vector<LidarIcpResult> results(pairs.size());
    std::vector<char> tried(pairs.size(), 0);
    parallel_for(pairs.size(), team, [&](std::size_t k) {
      const IcpTarget2D* target = targets[pairs[k].from - begin].get();
      if (target == nullptr) return;
      tried[k] = 1;
      results[k] = icp_align(*target, scans_[pairs[k].to].points,
                             between(g.pose(pairs[k].from), g.pose(pairs[k].to)),
                             b.scan_window_gate, /*remap_threshold=*/0.0, kWindowIcpIterations);
    });
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (tried[k] != 0 && results[k].termination == RegistrationTermination::Converged) {
        g.add_edge(pairs[k].from, pairs[k].to, results[k].T_target_robot, window_info);
        ++stats_.window_edges;
      } else {
        ++stats_.window_failed;
      }
    }
  }
  for (ScanRecord& r : scans_) std::vector<Eigen::Vector2d>().swap(r.points);

  Stopwatch so;
  GraphOptimizerOptions go;
  go.max_iterations = b.max_iterations;
  go.num_threads = b.num_threads;
  GraphOptimizerResult result = rove::optimize(g, go);
  ++stats_.optimizations;
  if (!result.ok()) ++stats_.optimizations_not_converged;
  stats_.optimization_seconds += so.elapsed();

  refined_.resize(n);
  for (std::size_t i = 0; i < n; ++i) refined_[i] = g.pose(i);
  for (std::size_t k = 0; k < nodes_.size(); ++k) {
    nodes_[k].T_world_robot = refined_[nodes_[k].scan];
    graph_.set_pose(k, nodes_[k].T_world_robot);
  }
  for (std::size_t j = 0; j < submaps_.size(); ++j) {
    const VertexId id = kLidarSubmapVertexBase + static_cast<VertexId>(j);
    submaps_[j].T_world_submap = g.pose(id);
    graph_.set_pose(id, submaps_[j].T_world_submap);
  }
  const LidarSlamNode& last = nodes_.back();
  T_world_local_ = last.T_world_robot * last.T_local_robot.inverse();
  stats_.refinement_seconds += sw.elapsed();
  return result;
}

std::optional<GraphOptimizerResult> LidarSlam::finish() {
  if (finished_) return std::nullopt;
  finished_ = true;
  expire_pending(std::numeric_limits<std::size_t>::max() / 2);
  bool ran = false;
  if (loops_since_optimization_ > 0) {
    optimize();
    ran = true;
  }
  if (options_.backend.scan_window > 0 && !nodes_.empty()) {
    last_opt_ = refine_scans();
    ran = true;
  }
  return ran ? last_opt_ : std::nullopt;
}

}  // namespace rove
