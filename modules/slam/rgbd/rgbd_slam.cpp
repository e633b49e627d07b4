#include "rove/slam/rgbd_slam.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <limits>
#include <random>
#include <utility>

#include "rgbd_tracking.h"
#include "rove/core/check.h"
#include "rove/core/timer.h"
#include "rove/maps/voxel_grid.h"
#include "rove/registration/icp_3d.h"
#include "rove/vision/place_recognition.h"

namespace rove {
namespace {

constexpr std::size_t kNoKeyframe = std::numeric_limits<std::size_t>::max();
// Consecutive lost frames after which a frame with enough points starts a
// new keyframe joined to the last one by the prediction only.
constexpr std::size_t kLostBeforeRestart = 3;
// Standard deviations of such a prediction edge (m, rad).
constexpr double kWeakSigmaTranslation = 0.05;
constexpr double kWeakSigmaRotation = 0.05;
// Loop candidates are searched over a larger radius: the graph's relative
// pose has drifted more than one frame's prediction.
constexpr double kLoopRadiusFactor = 2.0;

using Mat6 = Eigen::Matrix<double, 6, 6>;

struct KeyframeData {
  std::size_t frame = 0;
  double time = 0.0;
  detail::FrameFeatures features;
  PointCloud cloud;  // camera frame, map_stride, voxel filtered
};

struct FrameRecord {
  double time = 0.0;
  std::size_t keyframe = kNoKeyframe;
  SE3d T_keyframe_frame;
  RgbdFrameStatus status = RgbdFrameStatus::Lost;
};

// The previous frame, kept while it is tracked and not a keyframe: it may
// become one when the next frame cannot be tracked against the keyframe.
struct PreviousFrame {
  std::size_t index = 0;
  double time = 0.0;
  detail::FrameFeatures features;
  RgbdFrame frame;
  SE3d T_keyframe_frame;
  Mat6 covariance = Mat6::Zero();  // of T_keyframe_frame, right tangent
  std::vector<DescriptorMatch> inliers;  // PnP's: keyframe feature -> this frame's
};

// Features of two keyframes that PnP paired: one 3D point seen by both.
struct FeaturePair {
  std::uint32_t keyframe_a, feature_a, keyframe_b, feature_b;
};

// A pose estimate of `cur` against a reference frame.
struct Attempt {
  PnpResult pnp;
  std::vector<DescriptorMatch> used;  // the matches pnp was solved on
  std::size_t matches = 0;
  bool good = false;
  bool guided = false;
};

}  // namespace

struct RgbdSlam::Impl {
  PinholeCamera camera;
  RgbdSlamOptions opt;
  PnpOptions pnp_track, pnp_loop;
  std::vector<KeyframeData> keyframes;
  std::vector<FrameRecord> frames;
  PoseGraph3D graph;
  std::vector<RgbdLoopCheck> loops;
  std::optional<GraphOptimizerResult> last_opt;
  RgbdSlamStats stats;
  std::mt19937_64 rng;
  std::optional<PreviousFrame> previous;
  SE3d T_world_last;   // pose given to the last processed frame
  SE3d velocity;       // T_prev_cur of the last two tracked frames
  double velocity_dt = 0.0;  // seconds between those frames
  Eigen::Vector3d predicted_omega = Eigen::Vector3d::Zero();  // rad/s, the frame's features were corrected with
  double tracking_sq_sum = 0.0;  // Σ squared reprojection errors of the tracking's PnP inliers
  std::size_t tracking_inliers = 0;
  std::size_t consecutive_lost = 0;
  bool loop_added_since_optimization = false;
  std::vector<std::unique_ptr<PreparedCloud3D>> icp_clouds;  // per keyframe, when first needed
  // Bundle adjustment's inputs (options.bundle_adjustment): the pairs PnP
  // found between keyframes, and the relative poses measured otherwise.
  std::vector<FeaturePair> feature_pairs;
  std::vector<BaRelativePose> ba_relatives;
  std::optional<BundleAdjustmentResult> last_ba;
  BinaryPlaceIndex places;  // the keyframes' descriptors (options.appearance_loops)

  // The inlier pairs of a PnP between keyframes `ref` and `cur`.
  void record_pairs(std::size_t ref, std::size_t cur, const std::vector<DescriptorMatch>& inliers) {
    if (!opt.bundle_adjustment) return;
    for (const DescriptorMatch& m : inliers) {
      feature_pairs.push_back({static_cast<std::uint32_t>(ref), m.query, static_cast<std::uint32_t>(cur), m.train});
    }
  }

  void record_pairs(std::size_t ref, std::size_t cur, const Attempt& a) {
    if (!opt.bundle_adjustment) return;
    record_pairs(ref, cur, detail::pnp_inlier_matches(keyframes[ref].features, a.used, a.pnp));
  }

  // A relative pose for the bundle adjustment, its covariance (right
  // tangent) floored as the graph's edges are.
  void record_relative(std::size_t from, std::size_t to, const SE3d& T_from_to, const Mat6& covariance) {
    if (!opt.bundle_adjustment) return;
    const Eigen::LDLT<Mat6> ldlt(
        detail::floored_covariance(covariance, opt.edge_min_sigma_translation, opt.edge_min_sigma_rotation));
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return;
    Mat6 info = ldlt.solve(Mat6::Identity());
    info = 0.5 * (info + info.transpose());
    ba_relatives.push_back({from, to, T_from_to, info});
  }

  const PreparedCloud3D& icp_cloud(std::size_t k) {
    if (icp_clouds.size() <= k) icp_clouds.resize(k + 1);
    if (!icp_clouds[k]) {
      PrepareOptions po;
      po.covariances = true;
      icp_clouds[k] = std::make_unique<PreparedCloud3D>(PreparedCloud3D::from_cloud(
          voxel_downsample(keyframes[k].cloud, static_cast<float>(opt.icp_voxel)), po));
    }
    return *icp_clouds[k];
  }

  // The relative pose of keyframes `from` and `to` measured by GICP of their
  // clouds from the PnP estimate `guess`; added as an edge when it passes
  // the checks of RgbdSlamOptions::icp_voxel.
  void add_icp_edge(std::size_t from, std::size_t to, const SE3d& guess) {
    if (opt.icp_voxel <= 0.0) return;
    Stopwatch sw;
    Icp3dOptions io;
    io.method = Icp3dMethod::Gicp;
    io.max_correspondence_distance = opt.icp_max_distance;
    io.max_iterations = 30;
    const PreparedCloud3D& target = icp_cloud(from);
    const PreparedCloud3D& source = icp_cloud(to);
    const bool usable = target.size() >= io.min_correspondences && source.size() >= io.min_correspondences;
    const Icp3dResult r = usable ? icp_3d(target, source, guess, io) : Icp3dResult{};
    if (usable && r.ok() && r.goodness >= opt.icp_min_pairing && r.covariance.allFinite() &&
        motion_norm(guess.inverse() * r.T_target_source) <= opt.icp_max_correction) {
      add_edge(from, to, r.T_target_source, measured_information(r.covariance));
      record_relative(from, to, r.T_target_source, r.covariance);
      ++stats.icp_edges;
    } else {
      ++stats.icp_refused;
    }
    stats.icp_seconds += sw.elapsed();
  }

  Impl(const PinholeCamera& c, const RgbdSlamOptions& o) : camera(c), opt(o), rng(o.seed) {
    camera.check();
    opt.check();
    pnp_track = opt.pnp;
    pnp_track.min_inliers = opt.min_inliers;
    pnp_track.seed = opt.seed;
    pnp_loop = pnp_track;
    pnp_loop.min_inliers = opt.loop_min_inliers;
  }

  bool acceptable(const PnpResult& p, std::size_t min_inliers, double max_norm) const {
    return p.ok() && p.inliers.size() >= min_inliers &&
           (max_norm <= 0.0 || motion_norm(p.T_camera_world) <= max_norm);
  }

  // Re-matches around the projections at the found pose and solves again;
  // keeps the result with more inliers.
  void refine(const detail::FrameFeatures& ref, const detail::FrameFeatures& cur, Attempt& a,
              const PnpOptions& pnp) {
    if (opt.refine_radius_px <= 0.0) return;
    const auto m = detail::match_guided(ref, cur, a.pnp.T_camera_world, camera, opt.refine_radius_px,
                                        opt.guided_max_distance, 0.0);
    if (m.size() < opt.min_matches) return;
    PnpResult p = detail::solve_frame_pnp(ref, cur, m, camera, pnp);
    if (p.ok() && p.inliers.size() > a.pnp.inliers.size()) {
      a.pnp = std::move(p);
      a.used = m;
      a.matches = m.size();
    }
  }

  // Guided search at the predicted pose, then brute force.
  // Search: guided at the prediction, then brute force; guided only; or
  // brute force only.
  enum class Search { GuidedThenBrute, GuidedOnly, BruteOnly };

  Attempt estimate(const detail::FrameFeatures& ref, const detail::FrameFeatures& cur,
                   const SE3d& T_cur_ref_predicted, double radius, Search search,
                   const PnpOptions& pnp, double max_norm, double& match_seconds,
                   double& pnp_seconds) {
    const bool allow_guided = search != Search::BruteOnly && radius > 0.0;
    Attempt a;
    Stopwatch sw;
    if (allow_guided) {
      const auto m = detail::match_guided(ref, cur, T_cur_ref_predicted, camera, radius,
                                          opt.guided_max_distance, opt.match.ratio);
      match_seconds += sw.lap();
      a.matches = m.size();
      if (m.size() >= opt.min_matches) {
        a.pnp = detail::solve_frame_pnp(ref, cur, m, camera, pnp);
        a.used = m;
        a.good = acceptable(a.pnp, pnp.min_inliers, max_norm);
        a.guided = a.good;
      }
      pnp_seconds += sw.lap();
    }
    if (!a.good && (search != Search::GuidedOnly || !allow_guided)) {
      const auto m = detail::match_brute_force(ref, cur, opt.match);
      match_seconds += sw.lap();
      a.matches = m.size();
      if (m.size() >= opt.min_matches) {
        a.pnp = detail::solve_frame_pnp(ref, cur, m, camera, pnp);
        a.used = m;
        a.good = acceptable(a.pnp, pnp.min_inliers, max_norm);
      }
      pnp_seconds += sw.lap();
    }
    if (a.good) {
      refine(ref, cur, a, pnp);
      pnp_seconds += sw.lap();
    }
    return a;
  }

  PointCloud keyframe_cloud(const RgbdFrame& frame, const detail::FrameFeatures& f) {
    Stopwatch sw;
    RgbdCloudOptions co;
    co.min_depth = opt.min_depth;
    co.max_depth = opt.map_max_depth;
    co.stride = opt.map_stride;
    PointCloud c = voxel_downsample(rgbd_to_cloud(frame, camera, co), static_cast<float>(opt.voxel_grid));
    const double readout = opt.rolling_shutter_readout.value_or(0.0);
    if (readout > 0.0 && f.omega.squaredNorm() > 0.0 && frame.color.height > 0) {
      // Each point carried from its row's time to the middle row's, as the
      // features were (rove/slam/rgbd_slam_options.h).
      const double h = static_cast<double>(frame.color.height);
      for (std::size_t i = 0; i < c.size(); ++i) {
        const Eigen::Vector3d p = c[i].cast<double>();
        if (!(p.z() > 0.0)) continue;
        const double v = camera.fy * p.y() / p.z() + camera.cy;
        c[i] = (SO3d::exp(f.omega * ((v / h - 0.5) * readout)) * p).cast<float>();
      }
    }
    stats.map_seconds += sw.elapsed();
    return c;
  }

  void add_edge(std::size_t from, std::size_t to, const SE3d& T_from_to, const Mat6& info) {
    PoseGraphEdge<SE3d> e;
    e.from = from;
    e.to = to;
    e.measurement = T_from_to;
    e.information = info;
    e.kernel = RobustKernel(RobustKernelType::Huber, opt.huber_delta);
    graph.add_edge(e);
  }

  // A keyframe from a frame at T_world_camera, joined to keyframe `from` by
  // the measurement T_from_new with covariance `cov` (right tangent).
  std::size_t add_keyframe(detail::FrameFeatures&& f, const RgbdFrame& frame, std::size_t index,
                           double time, const SE3d& T_world_camera, std::size_t from,
                           const SE3d& T_from_new, const Mat6& info) {
    const std::size_t id = keyframes.size();
    PointCloud cloud = keyframe_cloud(frame, f);
    keyframes.push_back({index, time, std::move(f), std::move(cloud)});
    graph.add_vertex(id, T_world_camera, id == 0);
    if (from != kNoKeyframe) {
      add_edge(from, id, T_from_new, info);
      add_icp_edge(from, id, T_from_new);
    }
    ++stats.keyframes;
    if (opt.appearance_loops > 0) places.add(id, keyframes[id].features.descriptors);
    return id;
  }

  Mat6 measured_information(const Mat6& cov) const {
    return detail::edge_information(cov, opt.edge_min_sigma_translation, opt.edge_min_sigma_rotation);
  }

  std::vector<std::pair<std::size_t, RgbdLoopKind>> loop_candidates(std::size_t k) {
    std::vector<std::pair<std::size_t, RgbdLoopKind>> out;
    if (k < 2) return out;
    std::vector<bool> chosen(k, false);
    chosen[k - 1] = true;  // joined already
    for (std::size_t n = 0; n < opt.nearby_loops && n + 2 <= k; ++n) {
      const std::size_t c = k - 2 - n;
      chosen[c] = true;
      out.emplace_back(c, RgbdLoopKind::Nearby);
    }
    const SE3d T_world_k = graph.pose(k);
    std::vector<std::pair<double, std::size_t>> by_norm;
    for (std::size_t c = 0; c < k; ++c) {
      if (chosen[c]) continue;
      const double n = motion_norm(graph.pose(c).inverse() * T_world_k);
      if (n <= opt.proximity_max_norm) by_norm.emplace_back(n, c);
    }
    std::sort(by_norm.begin(), by_norm.end());
    for (std::size_t i = 0; i < by_norm.size() && i < opt.proximity_loops; ++i) {
      chosen[by_norm[i].second] = true;
      out.emplace_back(by_norm[i].second, RgbdLoopKind::Proximity);
    }
    if (opt.appearance_loops > 0) {
      std::size_t taken = 0;
      for (const PlaceCandidate& p : places.query(keyframes[k].features.descriptors, k + 1)) {
        if (taken == opt.appearance_loops) break;
        if (p.place >= k || chosen[p.place] || p.score < opt.appearance_min_score) continue;
        chosen[p.place] = true;
        out.emplace_back(p.place, RgbdLoopKind::Appearance);
        ++taken;
      }
    }
    std::vector<std::size_t> rest;
    for (std::size_t c = 0; c < k; ++c) {
      if (!chosen[c]) rest.push_back(c);
    }
    for (std::size_t n = 0; n < opt.random_loops && !rest.empty(); ++n) {
      std::uniform_int_distribution<std::size_t> pick(0, rest.size() - 1);
      const std::size_t i = pick(rng);
      out.emplace_back(rest[i], RgbdLoopKind::Random);
      rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(i));
    }
    return out;
  }

  // The same relative pose measured the other way round: `to`'s points in
  // `from`'s image, so the depth noise of `to` enters instead of `from`'s.
  bool add_reverse_edge(std::size_t from, std::size_t to, const SE3d& T_from_to) {
    if (!opt.symmetric_edges) return false;
    double ignored_match = 0.0, ignored_pnp = 0.0;
    const Attempt r = estimate(keyframes[to].features, keyframes[from].features, T_from_to,
                               opt.guided_radius_px, Search::GuidedOnly, pnp_loop, 0.0, ignored_match,
                               ignored_pnp);
    if (!r.good) return false;
    add_edge(from, to, r.pnp.T_camera_world, measured_information(r.pnp.covariance));
    record_pairs(to, from, r);
    return true;
  }

  std::size_t close_loops(std::size_t k) {
    Stopwatch sw;
    std::size_t accepted = 0;
    double ignored_match = 0.0, ignored_pnp = 0.0;
    for (const auto& [c, kind] : loop_candidates(k)) {
      const SE3d T_k_c = graph.pose(k).inverse() * graph.pose(c);
      const Attempt a = estimate(keyframes[c].features, keyframes[k].features, T_k_c,
                                 kLoopRadiusFactor * opt.guided_radius_px,
                                 kind == RgbdLoopKind::Random || kind == RgbdLoopKind::Appearance
                                     ? Search::BruteOnly
                                     : Search::GuidedOnly,
                                 pnp_loop, opt.loop_max_norm, ignored_match, ignored_pnp);
      RgbdLoopCheck check{k, c, kind, a.matches, a.pnp.ok() ? a.pnp.inliers.size() : 0,
                          a.pnp.ok() ? motion_norm(a.pnp.T_camera_world) : 0.0, a.good};
      loops.push_back(check);
      ++stats.loop_checks;
      if (!a.good) continue;
      const SE3d T_c_k = a.pnp.T_camera_world.inverse();
      add_edge(c, k, T_c_k,
               measured_information(detail::inverse_covariance(a.pnp.T_camera_world, a.pnp.covariance)));
      record_pairs(c, k, a);
      add_reverse_edge(c, k, T_c_k);
      add_icp_edge(c, k, T_c_k);
      ++accepted;
    }
    stats.loops_accepted += accepted;
    stats.loop_seconds += sw.elapsed();
    if (accepted > 0) optimize_graph();
    return accepted;
  }

  void optimize_graph() {
    Stopwatch sw;
    GraphOptimizerOptions go;
    go.max_iterations = 30;
    last_opt = optimize(graph, go);
    ++stats.optimizations;
    stats.graph_seconds += sw.elapsed();
  }

  // Tracks from the feature pairs (union–find over (keyframe, feature)),
  // then bundle adjustment of the keyframes and the tracks' points.
  void bundle_adjust_keyframes() {
    Stopwatch sw;
    const std::size_t K = keyframes.size();
    std::vector<std::size_t> offset(K + 1, 0);
    for (std::size_t k = 0; k < K; ++k) offset[k + 1] = offset[k] + keyframes[k].features.keypoints.size();
    std::vector<std::size_t> parent(offset[K]);
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    auto find = [&](std::size_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    std::vector<bool> used(offset[K], false);
    for (const FeaturePair& fp : feature_pairs) {
      const std::size_t a = offset[fp.keyframe_a] + fp.feature_a, b = offset[fp.keyframe_b] + fp.feature_b;
      used[a] = used[b] = true;
      const std::size_t ra = find(a), rb = find(b);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    // Members of each track, in (keyframe, feature) order.
    std::vector<std::vector<std::size_t>> members(offset[K]);
    for (std::size_t n = 0; n < offset[K]; ++n) {
      if (used[n]) members[find(n)].push_back(n);
    }
    BundleAdjustmentProblem p;
    p.fx = std::abs(camera.fx);
    p.fy = std::abs(camera.fy);
    for (std::size_t k = 0; k < K; ++k) p.T_world_camera.push_back(graph.pose(k));
    p.fixed.assign(K, false);
    p.fixed[0] = true;
    std::size_t conflicts = 0;
    for (const std::vector<std::size_t>& track : members) {
      if (track.size() < 2) continue;
      std::vector<std::size_t> kf(track.size());
      for (std::size_t i = 0; i < track.size(); ++i) {
        kf[i] = static_cast<std::size_t>(std::upper_bound(offset.begin(), offset.end(), track[i]) - offset.begin()) - 1;
      }
      if (std::adjacent_find(kf.begin(), kf.end()) != kf.end()) {
        ++conflicts;  // two features of one keyframe: a wrong pairing somewhere
        continue;
      }
      const std::size_t point = p.points_world.size();
      bool placed = false;
      for (std::size_t i = 0; i < track.size(); ++i) {
        const detail::FrameFeatures& f = keyframes[kf[i]].features;
        const std::size_t feat = track[i] - offset[kf[i]];
        const Eigen::Vector3d& pc = f.points[feat];
        if (!placed && std::isfinite(pc.z())) {
          p.points_world.push_back(p.T_world_camera[kf[i]] * pc);
          placed = true;
        }
        BaObservation o;
        o.camera = kf[i];
        o.point = point;
        o.normalized = camera.unproject(f.keypoints[feat].u, f.keypoints[feat].v).head<2>();
        o.sigma_px = std::pow(opt.orb.scale_factor, f.keypoints[feat].octave);
        if (std::isfinite(pc.z())) {
          o.inverse_depth = 1.0 / pc.z();
          o.sigma_inverse_depth = opt.ba_inverse_depth_sigma;
        }
        p.observations.push_back(o);
      }
      if (!placed) {
        p.observations.resize(p.observations.size() - track.size());
      }
    }
    p.relative_poses = ba_relatives;
    BundleAdjustmentOptions bo;
    bo.max_iterations = opt.ba_iterations;
    last_ba = bundle_adjust(p, bo);
    if (last_ba->improved()) {
      for (std::size_t k = 0; k < K; ++k) graph.set_pose(k, p.T_world_camera[k]);
    }
    stats.ba_points = last_ba->points_adjusted;
    stats.ba_observations = p.observations.size();
    stats.ba_outliers = last_ba->outliers;
    stats.ba_conflicts = conflicts;
    stats.ba_seconds += sw.elapsed();
  }

  SE3d frame_pose(std::size_t i) const {
    const FrameRecord& r = frames[i];
    if (r.keyframe == kNoKeyframe) return SE3d();
    return graph.pose(r.keyframe) * r.T_keyframe_frame;
  }

  // Makes the previous frame a keyframe (it was tracked against the current
  // keyframe); returns its keyframe index.
  std::size_t promote_previous() {
    PreviousFrame p = std::move(*previous);
    previous.reset();
    const std::size_t from = frames[p.index].keyframe;
    const SE3d T_world = graph.pose(from) * p.T_keyframe_frame;
    const std::size_t id = add_keyframe(std::move(p.features), p.frame, p.index, p.time, T_world, from,
                                        p.T_keyframe_frame, measured_information(p.covariance));
    frames[p.index].keyframe = id;
    frames[p.index].T_keyframe_frame = SE3d();
    frames[p.index].status = RgbdFrameStatus::Keyframe;
    record_pairs(from, id, p.inliers);
    add_reverse_edge(from, id, p.T_keyframe_frame);
    close_loops(id);
    return id;
  }

  // A keyframe whose features were described without an angular velocity
  // (the first frame, or after lost frames) gets its rolling-shutter
  // correction from the turn to the first frame tracked against it: its
  // features and its cloud. (Refining every keyframe's correction by the
  // turns into and out of it fed the errors of its pose back into its
  // features and diverged on fast turns.)
  void correct_keyframe_shutter(std::size_t kf, const SE3d& T_world_cur, double time) {
    KeyframeData& k = keyframes[kf];
    detail::FrameFeatures& f = k.features;
    if (f.raw_keypoints.empty() || f.omega.squaredNorm() > 0.0 || !(time > k.time)) return;
    const Eigen::Vector3d omega =
        (graph.pose(kf).rotation().inverse() * T_world_cur.rotation()).log() / (time - k.time);
    if (!(omega.squaredNorm() > 0.0)) return;
    detail::correct_rolling_shutter(f, camera, opt, omega);
    // The cloud: each point carried by its row's turn.
    const double readout = opt.rolling_shutter_readout.value_or(0.0);
    const double h = static_cast<double>(f.height);
    for (std::size_t i = 0; i < k.cloud.size(); ++i) {
      const Eigen::Vector3d p = k.cloud[i].cast<double>();
      if (!(p.z() > 0.0)) continue;
      const double dt = ((camera.fy * p.y() / p.z() + camera.cy) / h - 0.5) * readout;
      k.cloud[i] = (SO3d::exp(omega * dt) * p).cast<float>();
    }
    if (kf < icp_clouds.size()) icp_clouds[kf].reset();
  }

  RgbdFrameUpdate track(detail::FrameFeatures&& f, const RgbdFrame& frame, RgbdFrameUpdate u) {
    const std::size_t index = u.index;
    const double time = frames[index].time;
    std::size_t kf = frames[index - 1].keyframe;
    SE3d T_world_predicted = T_world_last * velocity;
    auto attempt = [&] {
      const SE3d T_cur_kf = T_world_predicted.inverse() * graph.pose(kf);
      return estimate(keyframes[kf].features, f, T_cur_kf, opt.guided_radius_px, Search::GuidedThenBrute, pnp_track,
                      opt.max_norm, stats.matching_seconds, stats.pnp_seconds);
    };
    Attempt a = attempt();
    if (!a.good && previous) {
      kf = promote_previous();
      T_world_predicted = graph.pose(kf) * velocity;  // the previous frame is the keyframe now
      a = attempt();
      if (a.good) ++stats.recovered;
    }
    u.matches = a.matches;
    FrameRecord& rec = frames[index];
    rec.keyframe = kf;
    if (!a.good) {
      rec.T_keyframe_frame = graph.pose(kf).inverse() * T_world_predicted;
      rec.status = RgbdFrameStatus::Lost;
      u.status = RgbdFrameStatus::Lost;
      ++stats.lost;
      ++consecutive_lost;
      previous.reset();
      T_world_last = T_world_predicted;
      if (consecutive_lost >= kLostBeforeRestart && f.index3d.size() >= 2 * opt.min_inliers) {
        restart(std::move(f), frame, index, time);
      }
      return u;
    }
    ++stats.tracked;
    correct_keyframe_shutter(kf, graph.pose(kf) * a.pnp.T_camera_world.inverse(), time);
    tracking_sq_sum += a.pnp.rmse_px * a.pnp.rmse_px * static_cast<double>(a.pnp.inliers.size());
    tracking_inliers += a.pnp.inliers.size();
    stats.tracking_rmse_px = std::sqrt(tracking_sq_sum / static_cast<double>(tracking_inliers));
    (a.guided ? stats.guided_tracked : stats.brute_force_tracked) += 1;
    consecutive_lost = 0;
    u.inliers = a.pnp.inliers.size();
    const SE3d T_kf_cur = a.pnp.T_camera_world.inverse();
    const Mat6 cov = detail::inverse_covariance(a.pnp.T_camera_world, a.pnp.covariance);
    const SE3d T_world_cur = graph.pose(kf) * T_kf_cur;
    velocity = T_world_last.inverse() * T_world_cur;
    velocity_dt = time - frames[index - 1].time;
    T_world_last = T_world_cur;
    rec.T_keyframe_frame = T_kf_cur;
    rec.status = RgbdFrameStatus::Tracked;
    u.status = RgbdFrameStatus::Tracked;
    const bool make_keyframe = motion_norm(T_kf_cur) > opt.keyframe_threshold ||
                               (opt.keyframe_min_inliers > 0 && u.inliers < opt.keyframe_min_inliers);
    if (!make_keyframe) {
      std::vector<DescriptorMatch> inliers;
      if (opt.bundle_adjustment) inliers = detail::pnp_inlier_matches(keyframes[kf].features, a.used, a.pnp);
      previous = PreviousFrame{index, time, std::move(f), frame, T_kf_cur, cov, std::move(inliers)};
      return u;
    }
    previous.reset();
    const std::size_t id = add_keyframe(std::move(f), frame, index, time, T_world_cur, kf, T_kf_cur,
                                        measured_information(cov));
    rec.keyframe = id;
    rec.T_keyframe_frame = SE3d();
    rec.status = RgbdFrameStatus::Keyframe;
    u.status = RgbdFrameStatus::Keyframe;
    record_pairs(kf, id, a);
    add_reverse_edge(kf, id, T_kf_cur);
    u.loops_accepted = close_loops(id);
    T_world_last = graph.pose(id);
    return u;
  }

  // After several lost frames: a keyframe at the predicted pose, joined by
  // a weak edge, from which tracking starts again.
  void restart(detail::FrameFeatures&& f, const RgbdFrame& frame, std::size_t index, double time) {
    const std::size_t from = frames[index].keyframe;
    const SE3d T_from_new = frames[index].T_keyframe_frame;
    Mat6 cov = Mat6::Zero();
    cov.diagonal() << Eigen::Vector3d::Constant(kWeakSigmaTranslation * kWeakSigmaTranslation),
        Eigen::Vector3d::Constant(kWeakSigmaRotation * kWeakSigmaRotation);
    const std::size_t id = add_keyframe(std::move(f), frame, index, time, graph.pose(from) * T_from_new,
                                        from, T_from_new, measured_information(cov));
    frames[index].keyframe = id;
    frames[index].T_keyframe_frame = SE3d();
    record_relative(from, id, T_from_new, cov);
    ++stats.weak_edges;
    consecutive_lost = 0;
    velocity = SE3d();
    velocity_dt = 0.0;
    close_loops(id);
    T_world_last = graph.pose(id);
  }

  RgbdFrameUpdate process(const RgbdFrame& frame, double time) {
    RgbdFrameUpdate u;
    u.index = frames.size();
    Stopwatch sw;
    // The angular velocity of the last two frames, when both were tracked.
    predicted_omega = velocity_dt > 0.0 && consecutive_lost == 0 && !frames.empty() &&
                              (frames.back().status == RgbdFrameStatus::Tracked ||
                               frames.back().status == RgbdFrameStatus::Keyframe)
                          ? Eigen::Vector3d(velocity.rotation().log() / velocity_dt)
                          : Eigen::Vector3d::Zero();
    detail::FrameFeatures f = detail::describe_frame(frame, camera, opt, predicted_omega);
    stats.features_seconds += sw.elapsed();
    u.features = f.keypoints.size();
    ++stats.frames;
    frames.push_back({time, keyframes.empty() ? kNoKeyframe : frames.back().keyframe, SE3d(),
                      RgbdFrameStatus::NoFeatures});
    if (f.index3d.size() < opt.min_inliers) {
      // Too few points to track or to start from: skipped, at the predicted pose.
      u.status = RgbdFrameStatus::NoFeatures;
      ++stats.no_features;
      if (!keyframes.empty()) {
        T_world_last = T_world_last * velocity;
        frames.back().T_keyframe_frame = graph.pose(frames.back().keyframe).inverse() * T_world_last;
      }
      previous.reset();
      return u;
    }
    if (keyframes.empty()) {
      add_keyframe(std::move(f), frame, u.index, time, SE3d(), kNoKeyframe, SE3d(), Mat6::Identity());
      frames.back().keyframe = 0;
      frames.back().status = RgbdFrameStatus::Keyframe;
      u.status = RgbdFrameStatus::Keyframe;
      ++stats.tracked;
      return u;
    }
    return track(std::move(f), frame, u);
  }
};

std::string_view to_string(RgbdFrameStatus status) {
  switch (status) {
    case RgbdFrameStatus::Keyframe: return "keyframe";
    case RgbdFrameStatus::Tracked: return "tracked";
    case RgbdFrameStatus::Lost: return "lost";
    case RgbdFrameStatus::NoFeatures: return "no-features";
  }
  return "?";
}

std::string_view to_string(RgbdLoopKind kind) {
  switch (kind) {
    case RgbdLoopKind::Nearby: return "nearby";
    case RgbdLoopKind::Random: return "random";
    case RgbdLoopKind::Proximity: return "proximity";
    case RgbdLoopKind::Appearance: return "appearance";
  }
  return "?";
}

RgbdSlam::RgbdSlam(const PinholeCamera& camera, const RgbdSlamOptions& options)
    : impl_(std::make_unique<Impl>(camera, options)) {}
RgbdSlam::~RgbdSlam() = default;
RgbdSlam::RgbdSlam(RgbdSlam&&) noexcept = default;
RgbdSlam& RgbdSlam::operator=(RgbdSlam&&) noexcept = default;

RgbdFrameUpdate RgbdSlam::process(const RgbdFrame& frame, double time) {
  ROVE_CHECK_MSG(impl_->frames.empty() || time > impl_->frames.back().time,
                 "frame times must increase: {} after {}", time,
                 impl_->frames.empty() ? 0.0 : impl_->frames.back().time);
  const PinholeCamera& c = impl_->camera;
  ROVE_CHECK_MSG((c.width == 0 || frame.color.width == c.width) && (c.height == 0 || frame.color.height == c.height),
                 "the frame is {}x{}, the camera {}x{}", frame.color.width, frame.color.height, c.width, c.height);
  return impl_->process(frame, time);
}

std::optional<GraphOptimizerResult> RgbdSlam::finish() {
  std::optional<GraphOptimizerResult> r;
  if (impl_->stats.loops_accepted > 0) {
    impl_->optimize_graph();
    r = impl_->last_opt;
  }
  if (impl_->opt.bundle_adjustment && impl_->keyframes.size() >= 2) impl_->bundle_adjust_keyframes();
  return r;
}

const std::optional<BundleAdjustmentResult>& RgbdSlam::bundle_adjustment() const noexcept {
  return impl_->last_ba;
}

std::size_t RgbdSlam::num_frames() const noexcept { return impl_->frames.size(); }

SE3d RgbdSlam::frame_pose(std::size_t i) const {
  ROVE_CHECK_LT(i, impl_->frames.size());
  return impl_->frame_pose(i);
}

double RgbdSlam::frame_time(std::size_t i) const {
  ROVE_CHECK_LT(i, impl_->frames.size());
  return impl_->frames[i].time;
}

RgbdFrameStatus RgbdSlam::frame_status(std::size_t i) const {
  ROVE_CHECK_LT(i, impl_->frames.size());
  return impl_->frames[i].status;
}

std::vector<RgbdKeyframe> RgbdSlam::keyframes() const {
  std::vector<RgbdKeyframe> out;
  for (std::size_t k = 0; k < impl_->keyframes.size(); ++k) {
    const KeyframeData& d = impl_->keyframes[k];
    out.push_back({d.frame, d.time, impl_->graph.pose(k), d.features.keypoints.size(),
                   d.features.index3d.size()});
  }
  return out;
}

const std::vector<RgbdLoopCheck>& RgbdSlam::loop_checks() const noexcept { return impl_->loops; }
const PoseGraph3D& RgbdSlam::graph() const noexcept { return impl_->graph; }
const std::optional<GraphOptimizerResult>& RgbdSlam::last_optimization() const noexcept {
  return impl_->last_opt;
}
const RgbdSlamStats& RgbdSlam::stats() const noexcept { return impl_->stats; }
const RgbdSlamOptions& RgbdSlam::options() const noexcept { return impl_->opt; }

PointCloud RgbdSlam::map_cloud() {
  Stopwatch sw;
  PointCloud all;
  all.set_channels(PointChannels::Color);
  for (std::size_t k = 0; k < impl_->keyframes.size(); ++k) {
    const PointCloud& c = impl_->keyframes[k].cloud;
    const SE3d T = impl_->graph.pose(k);
    const Eigen::Matrix3f R = T.rotation_matrix().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    const bool colored = c.has_colors();
    for (std::size_t i = 0; i < c.size(); ++i) {
      const Eigen::Vector3f p = R * c[i] + t;
      if (colored) {
        all.push_back(p, c.colors()[i]);
      } else {
        all.push_back(p, Rgb8{128, 128, 128});
      }
    }
  }
  PointCloud out = voxel_downsample(all, static_cast<float>(impl_->opt.voxel_grid));
  impl_->stats.map_seconds += sw.elapsed();
  return out;
}

OccupancyOctree RgbdSlam::map_octree() {
  const RgbdSlamOptions& o = impl_->opt;
  ROVE_CHECK_MSG(o.octree_resolution > 0.0, "map_octree needs octree_resolution > 0, got {}",
                 o.octree_resolution);
  Stopwatch sw;
  OccupancyOctree tree(o.octree_resolution);
  OctreeInsertOptions io;
  io.mode = OctreeUpdateMode::Discretized;
  io.skip_invalid_points = true;  // a point beyond the tree's ±3.3 km is dropped, not an error
  io.num_threads = o.octree_threads;
  std::vector<Eigen::Vector3f> points;
  for (std::size_t k = 0; k < impl_->keyframes.size(); ++k) {
    const PointCloud& c = impl_->keyframes[k].cloud;
    if (c.empty()) continue;
    const SE3d T = impl_->graph.pose(k);  // T_world_camera
    const Eigen::Matrix3f R = T.rotation_matrix().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    points.clear();
    points.reserve(c.size());
    for (const Eigen::Vector3f& p : c.points()) points.push_back(R * p + t);
    tree.insert_point_cloud(points, T.translation(), io);
  }
  impl_->stats.octree_seconds += sw.elapsed();
  return tree;
}

}  // namespace rove
