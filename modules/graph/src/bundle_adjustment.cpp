// Bundle adjustment: LM on cameras and points, points eliminated by the
// Schur complement, the reduced camera system solved by sparse LDLᵀ.
#include "rove/graph/bundle_adjustment.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <fmt/format.h>

#include "rove/core/check.h"

namespace rove {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat3 = Eigen::Matrix3d;
using Vec3 = Eigen::Vector3d;

// Cost of an observation that lies behind its camera (or nearer than
// min_depth): a constant, so a step is judged by the observations that
// stay in front, and moving a point behind a camera costs as much as a
// gross outlier.
constexpr double kBehindChi2 = 1e4;
// Damping of the LM gives up beyond this λ.
constexpr double kMaxLambda = 1e16;

Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

double huber(double chi2, double delta) {
  const double d2 = delta * delta;
  return chi2 <= d2 ? chi2 : 2.0 * delta * std::sqrt(chi2) - d2;
}

double huber_weight(double chi2, double delta) {
  return chi2 <= delta * delta ? 1.0 : delta / std::sqrt(chi2);
}

bool finite_pose(const SE3d& T) {
  return T.translation().allFinite() && T.quaternion().coeffs().allFinite();
}

std::string check_problem(const BundleAdjustmentProblem& p) {
  if (!(p.fx > 0.0 && std::isfinite(p.fx) && p.fy > 0.0 && std::isfinite(p.fy))) {
    return fmt::format("focal lengths must be finite and positive, got fx {} fy {}", p.fx, p.fy);
  }
  const std::size_t nc = p.T_world_camera.size(), np = p.points_world.size();
  if (!p.fixed.empty() && p.fixed.size() != nc) {
    return fmt::format("fixed has {} entries for {} cameras", p.fixed.size(), nc);
  }
  if (nc > 0 && !p.fixed.empty() && std::none_of(p.fixed.begin(), p.fixed.end(), [](bool b) { return b; })) {
    return "no camera is fixed: the problem's gauge (a rigid motion of everything) is free";
  }
  for (std::size_t i = 0; i < nc; ++i) {
    if (!finite_pose(p.T_world_camera[i])) return fmt::format("camera {} has a non-finite pose", i);
  }
  for (std::size_t j = 0; j < np; ++j) {
    if (!p.points_world[j].allFinite()) return fmt::format("point {} is not finite", j);
  }
  for (std::size_t k = 0; k < p.observations.size(); ++k) {
    const BaObservation& o = p.observations[k];
    if (o.camera >= nc) return fmt::format("observation {}: camera {} of {}", k, o.camera, nc);
    if (o.point >= np) return fmt::format("observation {}: point {} of {}", k, o.point, np);
    if (!o.normalized.allFinite()) return fmt::format("observation {}: non-finite image coordinates", k);
    if (!(o.sigma_px > 0.0 && std::isfinite(o.sigma_px))) {
      return fmt::format("observation {}: sigma_px must be finite and positive, got {}", k, o.sigma_px);
    }
    if (!std::isnan(o.inverse_depth)) {
      if (!(o.inverse_depth > 0.0 && std::isfinite(o.inverse_depth))) {
        return fmt::format("observation {}: inverse depth must be positive (or NaN for none), got {}", k,
                           o.inverse_depth);
      }
      if (!(o.sigma_inverse_depth > 0.0 && std::isfinite(o.sigma_inverse_depth))) {
        return fmt::format("observation {}: sigma_inverse_depth must be finite and positive, got {}", k,
                           o.sigma_inverse_depth);
      }
    }
  }
  for (std::size_t k = 0; k < p.relative_poses.size(); ++k) {
    const BaRelativePose& r = p.relative_poses[k];
    if (r.from >= nc || r.to >= nc || r.from == r.to) {
      return fmt::format("relative pose {}: cameras {} and {} of {}", k, r.from, r.to, nc);
    }
    if (!finite_pose(r.T_from_to) || !r.information.allFinite()) {
      return fmt::format("relative pose {}: non-finite measurement or information", k);
    }
  }
  return {};
}

// One observation's whitened residual and Jacobians at the current state;
// the third rows (depth) are zero for an image-only observation.
struct Linearized {
  Eigen::Matrix<double, 3, 6> Jc = Eigen::Matrix<double, 3, 6>::Zero();
  Mat3 Jp = Mat3::Zero();
  Vec3 r = Vec3::Zero();
  int dim = 0;         // 2 or 3; 0 when the point is behind the camera
  double weight = 0.0; // Huber's ρ'(χ²)
};

class Solver {
 public:
  Solver(BundleAdjustmentProblem& p, const BundleAdjustmentOptions& o) : p_(p), o_(o) {
    const std::size_t nc = p.T_world_camera.size();
    T_cw_.resize(nc);
    for (std::size_t i = 0; i < nc; ++i) T_cw_[i] = p.T_world_camera[i].inverse();
    fixed_.assign(nc, false);
    if (p.fixed.empty()) {
      if (nc > 0) fixed_[0] = true;
    } else {
      for (std::size_t i = 0; i < nc; ++i) fixed_[i] = p.fixed[i];
    }
    points_ = p.points_world;
    inlier_.assign(p.observations.size(), true);
  }

  BundleAdjustmentResult run() {
    BundleAdjustmentResult res;
    res.initial_cost = cost(T_cw_, points_);
    GraphTermination last = GraphTermination::Converged;
    for (int round = 0; round < o_.rounds; ++round) {
      setup_round();
      last = optimize_round(res.iterations);
      if (last == GraphTermination::NumericalFailure) break;
      if (round + 1 < o_.rounds) drop_outliers();
    }
    res.termination = last;
    res.final_cost = cost(T_cw_, points_);
    res.inlier = inlier_;
    res.outliers = static_cast<std::size_t>(std::count(inlier_.begin(), inlier_.end(), false));
    res.points_adjusted = static_cast<std::size_t>(std::count(point_slot_.begin(), point_slot_.end(), true));
    res.cameras_adjusted = num_slots_;
    res.rmse_px = rmse_px();
    if (last != GraphTermination::NumericalFailure) {
      for (std::size_t i = 0; i < T_cw_.size(); ++i) {
        if (cam_slot_[i] >= 0) p_.T_world_camera[i] = T_cw_[i].inverse();
      }
      for (std::size_t j = 0; j < points_.size(); ++j) {
        if (point_slot_[j]) p_.points_world[j] = points_[j];
      }
    }
    res.message = fmt::format("{} after {} iterations in {} rounds: cost {:.6g} -> {:.6g}, {} of {} observations "
                              "dropped as outliers, image RMSE {:.3f} px",
                              to_string(last), res.iterations, o_.rounds, res.initial_cost, res.final_cost,
                              res.outliers, p_.observations.size(), res.rmse_px);
    return res;
  }

 private:
  // Whitened residual of observation k at the given state (dim 0: behind).
  Linearized residual(std::size_t k, const SE3d& T_cw, const Vec3& pw, bool jacobians) const {
    const BaObservation& o = p_.observations[k];
    Linearized l;
    const Vec3 pc = T_cw * pw;
    if (!(pc.z() >= o_.min_depth)) return l;
    const double iz = 1.0 / pc.z();
    const double sx = p_.fx / o.sigma_px, sy = p_.fy / o.sigma_px;
    l.r.x() = sx * (pc.x() * iz - o.normalized.x());
    l.r.y() = sy * (pc.y() * iz - o.normalized.y());
    const bool depth = !std::isnan(o.inverse_depth);
    l.dim = depth ? 3 : 2;
    if (depth) l.r.z() = (iz - o.inverse_depth) / o.sigma_inverse_depth;
    if (!jacobians) return l;
    Mat3 Jproj = Mat3::Zero();
    Jproj.row(0) << sx * iz, 0.0, -sx * pc.x() * iz * iz;
    Jproj.row(1) << 0.0, sy * iz, -sy * pc.y() * iz * iz;
    if (depth) Jproj.row(2) << 0.0, 0.0, -iz * iz / o.sigma_inverse_depth;
    // p_c = exp(δ)·T·p_w: ∂p_c/∂δ = [I, −[p_c]×]; ∂p_c/∂p_w = R.
    l.Jc.leftCols<3>() = Jproj;
    l.Jc.rightCols<3>() = -Jproj * skew(pc);
    l.Jp = Jproj * T_cw.rotation_matrix();
    const double chi2 = l.r.squaredNorm();
    l.weight = huber_weight(chi2, depth ? o_.huber_delta_3d : o_.huber_delta_2d);
    return l;
  }

  double obs_cost(std::size_t k, const std::vector<SE3d>& T_cw, const std::vector<Vec3>& pts) const {
    const BaObservation& o = p_.observations[k];
    const Linearized l = residual(k, T_cw[o.camera], pts[o.point], false);
    const bool depth = !std::isnan(o.inverse_depth);
    const double delta = depth ? o_.huber_delta_3d : o_.huber_delta_2d;
    return huber(l.dim == 0 ? kBehindChi2 : l.r.squaredNorm(), delta);
  }

  // e = log(Z⁻¹·T_a_w·T_b_w⁻¹) = log(Z⁻¹·T_w_a⁻¹·T_w_b).
  Vec6 relative_error(const BaRelativePose& r, const std::vector<SE3d>& T_cw) const {
    return (r.T_from_to.inverse() * T_cw[r.from] * T_cw[r.to].inverse()).log();
  }

  double cost(const std::vector<SE3d>& T_cw, const std::vector<Vec3>& pts) const {
    double c = 0.0;
    for (std::size_t k = 0; k < p_.observations.size(); ++k) {
      if (inlier_[k]) c += obs_cost(k, T_cw, pts);
    }
    for (const BaRelativePose& r : p_.relative_poses) {
      const Vec6 e = relative_error(r, T_cw);
      c += e.dot(r.information * e);
    }
    return c;
  }

  // Slots of the cameras and points that this round optimizes, and the
  // blocks of the reduced camera system.
  void setup_round() {
    const std::size_t nc = T_cw_.size(), np = points_.size();
    cam_slot_.assign(nc, -1);
    std::vector<int> views(np, 0), depth_views(np, 0);
    for (std::size_t k = 0; k < p_.observations.size(); ++k) {
      if (!inlier_[k]) continue;
      const BaObservation& o = p_.observations[k];
      ++views[o.point];
      if (!std::isnan(o.inverse_depth)) ++depth_views[o.point];
    }
    // A point is adjusted when its position is observable: two views, or
    // one with depth.
    point_slot_.assign(np, false);
    for (std::size_t j = 0; j < np; ++j) point_slot_[j] = views[j] >= 2 || depth_views[j] >= 1;
    num_slots_ = 0;
    auto slot = [&](std::size_t i) {
      if (!fixed_[i] && cam_slot_[i] < 0) cam_slot_[i] = static_cast<int>(num_slots_++);
    };
    for (std::size_t k = 0; k < p_.observations.size(); ++k) {
      if (inlier_[k]) slot(p_.observations[k].camera);
    }
    for (const BaRelativePose& r : p_.relative_poses) {
      slot(r.from);
      slot(r.to);
    }
    // Observations grouped by point.
    obs_start_.assign(np + 1, 0);
    for (std::size_t k = 0; k < p_.observations.size(); ++k) {
      if (inlier_[k]) ++obs_start_[p_.observations[k].point + 1];
    }
    for (std::size_t j = 0; j < np; ++j) obs_start_[j + 1] += obs_start_[j];
    obs_items_.resize(obs_start_[np]);
    std::vector<std::size_t> fill(obs_start_.begin(), obs_start_.end() - 1);
    for (std::size_t k = 0; k < p_.observations.size(); ++k) {
      if (inlier_[k]) obs_items_[fill[p_.observations[k].point]++] = k;
    }
    // Blocks (a ≤ b) of the reduced system.
    block_index_.clear();
    blocks_.clear();
    for (std::size_t s = 0; s < num_slots_; ++s) block(static_cast<int>(s), static_cast<int>(s));
    for (std::size_t j = 0; j < np; ++j) {
      for (std::size_t a = obs_start_[j]; a < obs_start_[j + 1]; ++a) {
        const int sa = cam_slot_[p_.observations[obs_items_[a]].camera];
        if (sa < 0) continue;
        if (!point_slot_[j]) continue;
        for (std::size_t b = a + 1; b < obs_start_[j + 1]; ++b) {
          const int sb = cam_slot_[p_.observations[obs_items_[b]].camera];
          if (sb >= 0) block(sa, sb);
        }
      }
    }
    for (const BaRelativePose& r : p_.relative_poses) {
      if (cam_slot_[r.from] >= 0 && cam_slot_[r.to] >= 0) block(cam_slot_[r.from], cam_slot_[r.to]);
    }
  }

  static std::uint64_t block_key(int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
  }

  std::size_t block(int a, int b) {
    const auto [it, inserted] = block_index_.try_emplace(block_key(a, b), blocks_.size());
    if (a > b) std::swap(a, b);
    if (inserted) blocks_.push_back({a, b, Mat6::Zero()});
    return it->second;
  }

  std::size_t find_block(int a, int b) const { return block_index_.at(block_key(a, b)); }

  // Normal equations at the current state: H_cc (in blocks_), g_c, and per
  // point V, g_p and the observations' W = J_cᵀ·w·J_p.
  void linearize() {
    for (auto& b : blocks_) b.H.setZero();
    g_c_.assign(num_slots_, Vec6::Zero());
    const std::size_t np = points_.size();
    V_.assign(np, Mat3::Zero());
    g_p_.assign(np, Vec3::Zero());
    W_.assign(p_.observations.size(), Mat63::Zero());
    for (std::size_t k = 0; k < p_.observations.size(); ++k) {
      if (!inlier_[k]) continue;
      const BaObservation& o = p_.observations[k];
      const Linearized l = residual(k, T_cw_[o.camera], points_[o.point], true);
      if (l.dim == 0) continue;
      const auto& Jc = l.Jc;
      const auto& Jp = l.Jp;
      const auto& r = l.r;
      const int s = cam_slot_[o.camera];
      if (s >= 0) {
        blocks_[find_block(s, s)].H.noalias() += l.weight * Jc.transpose() * Jc;
        g_c_[static_cast<std::size_t>(s)].noalias() += l.weight * Jc.transpose() * r;
      }
      if (point_slot_[o.point]) {
        V_[o.point].noalias() += l.weight * Jp.transpose() * Jp;
        g_p_[o.point].noalias() += l.weight * Jp.transpose() * r;
        if (s >= 0) W_[k].noalias() = l.weight * Jc.transpose() * Jp;
      }
    }
    for (const BaRelativePose& r : p_.relative_poses) {
      const int sa = cam_slot_[r.from], sb = cam_slot_[r.to];
      const Vec6 e = relative_error(r, T_cw_);
      // E(δa) = exp(Ad(Z⁻¹)·δa)·E₀ and E(δb) = E₀·exp(−δb).
      const Mat6 Ja = SE3d::left_jacobian_inverse(e) * r.T_from_to.inverse().Adj();
      const Mat6 Jb = -SE3d::right_jacobian_inverse(e);
      if (sa >= 0) {
        blocks_[find_block(sa, sa)].H.noalias() += Ja.transpose() * r.information * Ja;
        g_c_[static_cast<std::size_t>(sa)].noalias() += Ja.transpose() * r.information * e;
      }
      if (sb >= 0) {
        blocks_[find_block(sb, sb)].H.noalias() += Jb.transpose() * r.information * Jb;
        g_c_[static_cast<std::size_t>(sb)].noalias() += Jb.transpose() * r.information * e;
      }
      if (sa >= 0 && sb >= 0) {
        Block& b = blocks_[find_block(sa, sb)];
        if (b.a == sa) {
          b.H.noalias() += Ja.transpose() * r.information * Jb;
        } else {
          b.H.noalias() += Jb.transpose() * r.information * Ja;
        }
      }
    }
  }

  // Solves the damped system; false when it is not positive definite.
  bool solve(double lambda, std::vector<Vec6>& dc, std::vector<Vec3>& dp, double& predicted) {
    const std::size_t np = points_.size();
    std::vector<Mat6> S(blocks_.size());
    for (std::size_t b = 0; b < blocks_.size(); ++b) S[b] = blocks_[b].H;
    std::vector<Vec6> g(g_c_);
    std::vector<Mat6> Dc(num_slots_);
    for (std::size_t s = 0; s < num_slots_; ++s) {
      Mat6& H = S[find_block(static_cast<int>(s), static_cast<int>(s))];
      Dc[s] = Mat6::Zero();
      Dc[s].diagonal() = lambda * H.diagonal().cwiseMax(1e-12);
      H += Dc[s];
    }
    std::vector<Mat3> Vinv(np);
    std::vector<Mat3> Dp(np);
    for (std::size_t j = 0; j < np; ++j) {
      if (!point_slot_[j]) continue;
      Dp[j] = Mat3::Zero();
      Dp[j].diagonal() = lambda * V_[j].diagonal().cwiseMax(1e-12);
      const Mat3 V = V_[j] + Dp[j];
      const Eigen::LDLT<Mat3> ldlt(V);
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return false;
      Vinv[j] = ldlt.solve(Mat3::Identity());
      // S −= Σ W_a V⁻¹ W_bᵀ, g −= Σ W_a V⁻¹ g_p.
      for (std::size_t a = obs_start_[j]; a < obs_start_[j + 1]; ++a) {
        const std::size_t ka = obs_items_[a];
        const int sa = cam_slot_[p_.observations[ka].camera];
        if (sa < 0) continue;
        const Mat63 WV = W_[ka] * Vinv[j];
        g[static_cast<std::size_t>(sa)].noalias() -= WV * g_p_[j];
        // Only the upper blocks (sa ≤ sb) are kept; a camera that sees the
        // point twice adds both orders to its diagonal block.
        for (std::size_t b = obs_start_[j]; b < obs_start_[j + 1]; ++b) {
          const std::size_t kb = obs_items_[b];
          const int sb = cam_slot_[p_.observations[kb].camera];
          if (sb < sa) continue;
          S[find_block(sa, sb)].noalias() -= WV * W_[kb].transpose();
        }
      }
    }
    const Eigen::Index n = static_cast<Eigen::Index>(6 * num_slots_);
    dc.assign(num_slots_, Vec6::Zero());
    if (n > 0) {
      std::vector<Eigen::Triplet<double>> trip;
      trip.reserve(blocks_.size() * 36);
      for (std::size_t b = 0; b < blocks_.size(); ++b) {
        const int a = blocks_[b].a, c = blocks_[b].b;
        for (int r = 0; r < 6; ++r) {
          for (int q = 0; q < 6; ++q) {
            if (a == c && q < r) continue;  // upper triangle of a diagonal block
            trip.emplace_back(6 * a + r, 6 * c + q, S[b](r, q));
          }
        }
      }
      Eigen::SparseMatrix<double> A(n, n);
      A.setFromTriplets(trip.begin(), trip.end());
      Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper> ldlt(A);
      if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) return false;
      Eigen::VectorXd rhs(n);
      for (std::size_t s = 0; s < num_slots_; ++s) rhs.segment<6>(static_cast<Eigen::Index>(6 * s)) = -g[s];
      const Eigen::VectorXd x = ldlt.solve(rhs);
      if (!x.allFinite()) return false;
      for (std::size_t s = 0; s < num_slots_; ++s) dc[s] = x.segment<6>(static_cast<Eigen::Index>(6 * s));
    }
    // Back-substitution: δp = −V⁻¹(g_p + Σ W_aᵀ δc_a).
    dp.assign(np, Vec3::Zero());
    predicted = 0.0;
    for (std::size_t j = 0; j < np; ++j) {
      if (!point_slot_[j]) continue;
      Vec3 rhs = g_p_[j];
      for (std::size_t a = obs_start_[j]; a < obs_start_[j + 1]; ++a) {
        const std::size_t ka = obs_items_[a];
        const int sa = cam_slot_[p_.observations[ka].camera];
        if (sa >= 0) rhs.noalias() += W_[ka].transpose() * dc[static_cast<std::size_t>(sa)];
      }
      dp[j] = -Vinv[j] * rhs;
      // Decrease of the cost's quadratic model 2gᵀδ + δᵀHδ: −gᵀδ + λδᵀDδ.
      predicted += -g_p_[j].dot(dp[j]) + dp[j].dot(Dp[j] * dp[j]);
    }
    for (std::size_t s = 0; s < num_slots_; ++s) predicted += -g_c_[s].dot(dc[s]) + dc[s].dot(Dc[s] * dc[s]);
    return std::isfinite(predicted);
  }

  GraphTermination optimize_round(int& iterations) {
    double lambda = o_.initial_lambda, nu = 2.0;
    double current = cost(T_cw_, points_);
    for (int it = 0; it < o_.max_iterations; ++it) {
      ++iterations;
      linearize();
      bool accepted = false;
      while (!accepted) {
        std::vector<Vec6> dc;
        std::vector<Vec3> dp;
        double predicted = 0.0;
        if (!solve(lambda, dc, dp, predicted)) {
          lambda *= nu;
          nu *= 2.0;
          if (lambda > kMaxLambda) return GraphTermination::NumericalFailure;
          continue;
        }
        std::vector<SE3d> T_new = T_cw_;
        for (std::size_t i = 0; i < T_cw_.size(); ++i) {
          if (cam_slot_[i] >= 0) T_new[i] = SE3d::exp(dc[static_cast<std::size_t>(cam_slot_[i])]) * T_cw_[i];
        }
        std::vector<Vec3> p_new = points_;
        for (std::size_t j = 0; j < points_.size(); ++j) {
          if (point_slot_[j]) p_new[j] += dp[j];
        }
        const double trial = cost(T_new, p_new);
        const double actual = current - trial;
        if (std::isfinite(trial) && actual > 0.0) {
          const double rho = predicted > 0.0 ? actual / predicted : 0.0;
          lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
          nu = 2.0;
          T_cw_ = std::move(T_new);
          points_ = std::move(p_new);
          const double before = current;
          current = trial;
          accepted = true;
          if (actual <= o_.function_tolerance * before) return GraphTermination::Converged;
        } else {
          if (!(predicted > 1e-15 * std::max(1.0, current))) return GraphTermination::Converged;
          lambda *= nu;
          nu *= 2.0;
          if (lambda > kMaxLambda) return GraphTermination::NoProgress;
        }
      }
    }
    return GraphTermination::MaxIterations;
  }

  void drop_outliers() {
    for (std::size_t k = 0; k < p_.observations.size(); ++k) {
      if (!inlier_[k]) continue;
      const BaObservation& o = p_.observations[k];
      const Linearized l = residual(k, T_cw_[o.camera], points_[o.point], false);
      const double bound = l.dim == 3 ? o_.outlier_chi2_3d : o_.outlier_chi2_2d;
      if (l.dim == 0 || l.r.squaredNorm() > bound) inlier_[k] = false;
    }
  }

  double rmse_px() const {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t k = 0; k < p_.observations.size(); ++k) {
      if (!inlier_[k]) continue;
      const BaObservation& o = p_.observations[k];
      const Linearized l = residual(k, T_cw_[o.camera], points_[o.point], false);
      if (l.dim == 0) continue;
      sum += (l.r.head<2>() * o.sigma_px).squaredNorm();
      ++n;
    }
    return n ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
  }

  struct Block {
    int a = 0, b = 0;  // slots, a ≤ b
    Mat6 H;
  };

  BundleAdjustmentProblem& p_;
  const BundleAdjustmentOptions& o_;
  std::vector<SE3d> T_cw_;
  std::vector<bool> fixed_;
  std::vector<Vec3> points_;
  std::vector<bool> inlier_;
  std::vector<int> cam_slot_;
  std::vector<bool> point_slot_;
  std::size_t num_slots_ = 0;
  std::vector<std::size_t> obs_start_, obs_items_;
  std::unordered_map<std::uint64_t, std::size_t> block_index_;
  std::vector<Block> blocks_;
  std::vector<Vec6> g_c_;
  std::vector<Mat3> V_;
  std::vector<Vec3> g_p_;
  std::vector<Mat63> W_;
};

}  // namespace

BundleAdjustmentResult bundle_adjust(BundleAdjustmentProblem& problem, const BundleAdjustmentOptions& options) {
  ROVE_CHECK_GE(options.rounds, 1);
  ROVE_CHECK_GE(options.max_iterations, 1);
  ROVE_CHECK_GT(options.huber_delta_2d, 0.0);
  ROVE_CHECK_GT(options.huber_delta_3d, 0.0);
  ROVE_CHECK_GT(options.outlier_chi2_2d, 0.0);
  ROVE_CHECK_GT(options.outlier_chi2_3d, 0.0);
  ROVE_CHECK_GT(options.min_depth, 0.0);
  ROVE_CHECK_GE(options.function_tolerance, 0.0);
  ROVE_CHECK_GT(options.initial_lambda, 0.0);
  const std::string problem_error = check_problem(problem);
  if (!problem_error.empty()) {
    BundleAdjustmentResult r;
    r.termination = GraphTermination::InvalidInput;
    r.message = "bundle adjustment: " + problem_error;
    r.inlier.assign(problem.observations.size(), false);
    return r;
  }
  Solver solver(problem, options);
  return solver.run();
}

}  // namespace rove
