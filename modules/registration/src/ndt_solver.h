#pragma once
// The NDT solver shared by rove's parametrization (NdtSe3 / NdtSe2 below: a
// local perturbation of the pose, free of gimbal lock) and PCL's
// (ndt_pcl.h: Euler angles, NdtCompat::Pcl). A parametrization M provides:
//   D, P, A        dimensions, parameters, rotation parameters;
//   State          the estimate (SE3d / SE2d, or PCL's parameter vector);
//   M(state)       R, t (x' = R·x + t), dR[A], d2R[A][A] and basis(x): the
//                  first and second derivatives of the moved point with
//                  respect to the rotation parameters are dR[k]·basis(x) and
//                  d2R[k][l]·basis(x), the translation parameters move x'
//                  by themselves;
//   retract(s, δ)  the state moved by δ; finite(s); step_translation_sq(δ),
//                  step_cos_angle(δ) the size of a step.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <fmt/format.h>

#include "rove/core/interrupt.h"
#include "rove/core/parallel.h"
#include "rove/math/se2.h"
#include "rove/math/se3.h"
#include "rove/math/so2.h"
#include "rove/math/so3.h"
#include "rove/registration/ndt.h"

namespace rove::detail {

/// Score, gradient and Hessian of the NDT score at one estimate, and the
/// counts the result reports.
template <class M>
struct NdtEval {
  double score = 0;
  typename M::Params g = M::Params::Zero();
  Eigen::Matrix<double, M::P, M::P> H = Eigen::Matrix<double, M::P, M::P>::Zero();
  std::size_t with_cell = 0;
  double nearest_sq = 0;
  NdtEval& operator+=(const NdtEval& o) {
    score += o.score;
    g += o.g;
    H += o.H;
    with_cell += o.with_cell;
    nearest_sq += o.nearest_sq;
    return *this;
  }
};

/// d₁, d₂ of the score (Magnusson 2009, eq. 6.8).
struct NdtGauss {
  double d1 = 0, d2 = 0;
};

/// Magnusson 2009, eq. 6.8 (as PCL): c₁ = 10(1 − p_o), c₂ = p_o / r^dim.
inline NdtGauss ndt_gauss_constants(double outlier_ratio, double resolution, int dim) {
  const double c1 = 10 * (1 - outlier_ratio);
  const double c2 = outlier_ratio / std::pow(resolution, dim);
  const double d3 = -std::log(c2);
  NdtGauss g;
  g.d1 = -std::log(c1 + c2) - d3;
  g.d2 = -2 * std::log((-std::log(c1 * std::exp(-0.5) + c2) - d3) / g.d1);
  return g;
}

/// Score, gradient and (optionally) Hessian of the NDT score at `state`
/// (Magnusson Algorithm 2, lines 17-21; eq. 6.10, 6.12, 6.13).
///
/// Every cell near one source point shares that point's Jacobian J = [I | J_r]
/// (J_r's columns dR_k · basis(x)), so the sums over the point's cells are
/// taken before J is applied: with v = C·x' and f = d₁d₂·exp(−d₂/2·x'ᵀv),
///   g_i = Jᵀ·w,  w = Σ f·v,
///   H_i = Jᵀ·S·J + Σ_kl w·(d2R_kl · basis(x)),  S = Σ f·(C − d₂·v·vᵀ),
/// which is eq. 6.12-6.13 summed in another order: 3 + 6 numbers per cell
/// instead of a 6 × 6 product.
template <class M>
NdtEval<M> ndt_evaluate(const NdtGrid<M::D>& grid,
                        std::span<const Eigen::Matrix<float, M::D, 1>> source,
                        const typename M::State& state, bool hessian, const NdtGauss& gc,
                        ThreadTeam& team) {
  using Vec = typename M::Vec;
  using Mat = typename M::Mat;
  constexpr int D = M::D, A = M::A;
  const M model(state);
  return parallel_reduce(source.size(), team, NdtEval<M>{},
                                   [&](std::size_t b, std::size_t e, NdtEval<M>& a) {
    std::array<Neighbor<double>, NdtGrid<D>::kMaxNear> near;
    Eigen::Matrix<double, D, A> Jr;
    for (std::size_t i = b; i < e; ++i) {
      if (!source[i].allFinite()) continue;
      const Vec x = source[i].template cast<double>();
      const Vec xt = model.R * x + model.t;
      const std::size_t n_near = grid.cells_near(xt, near);
      if (n_near == 0) continue;
      ++a.with_cell;
      double best = std::numeric_limits<double>::infinity();
      Vec w = Vec::Zero();
      Mat S = Mat::Zero();
      bool any = false;
      for (std::size_t j = 0; j < n_near; ++j) {
        const Neighbor<double>& nb = near[j];
        best = std::min(best, nb.sq_distance);
        const auto& cell = grid.cells()[nb.index];
        const Vec xp = xt - cell.mean;
        const Vec v = cell.inverse_covariance * xp;
        const double ex = std::exp(-gc.d2 * xp.dot(v) / 2);
        const double d2ex = gc.d2 * ex;
        if (d2ex > 1 || d2ex < 0 || std::isnan(d2ex)) continue;  // PCL's guard
        a.score += -gc.d1 * ex;
        const double f = gc.d1 * d2ex;
        w += f * v;
        if (hessian) S.noalias() += f * cell.inverse_covariance - (f * gc.d2) * v * v.transpose();
        any = true;
      }
      a.nearest_sq += best;
      if (!any) continue;
      const Vec bx = model.basis(x);
      for (int k = 0; k < A; ++k) Jr.col(k) = model.dR[k] * bx;
      a.g.template head<D>() += w;
      a.g.template tail<A>() += Jr.transpose() * w;
      if (hessian) {
        const Eigen::Matrix<double, D, A> SJr = S * Jr;
        a.H.template topLeftCorner<D, D>() += S;
        a.H.template topRightCorner<D, A>() += SJr;
        a.H.template bottomLeftCorner<A, D>() += SJr.transpose();
        Eigen::Matrix<double, A, A> rr = Jr.transpose() * SJr;
        for (int k = 0; k < A; ++k)
          for (int l = 0; l < A; ++l) rr(k, l) += w.dot(model.d2R[k][l] * bx);
        a.H.template bottomRightCorner<A, A>() += rr;
      }
    }
  });
}

/// (−H)⁻¹ with unconstrained directions given kUnconstrainedVariance
/// (covariance_from_information, scale 1).
template <int P>
Eigen::Matrix<double, P, P> ndt_covariance(const Eigen::Matrix<double, P, P>& information);

// Moré–Thuente (1994) helpers, in the notation of the paper: ψ(α) =
// φ(α) − φ(0) − μφ'(0)α, the interval update of Sec. 2 and the trial value
// selection of Sec. 4 (cases 1-4). Defined in ndt.cpp.
bool mt_update_interval(double& a_l, double& f_l, double& g_l, double& a_u, double& f_u,
                        double& g_u, double a_t, double f_t, double g_t);
double mt_select_trial(double a_l, double f_l, double g_l, double a_u, double f_u, double g_u,
                       double a_t, double f_t, double g_t);

template <class M>
struct NdtRun {
  typename M::State state;
  NdtEval<M> last;
  int iterations = 0;
  bool converged = false;
  bool diverged = false;
  bool stalled = false;  // the line search found no step that raised the score
  // The Newton step at the result (before the step_size cap), as the
  // convergence test measures it: translation m, rotation rad; NaN when the
  // score Hessian there is not negative definite (no maximum nearby).
  double newton_translation = 0, newton_rotation = 0;
};

/// One Moré–Thuente search along `delta` (unit length) from `state`, whose
/// evaluation is `ev`, for φ(α) = −score(retract(state, α·δ)), α in
/// [step_min, step_max] starting at `a_t`; at most 10 trials. Leaves in `ev`
/// the evaluation at the returned α (without Hessian when a trial moved it).
template <class M>
double ndt_line_search(const NdtGrid<M::D>& grid,
                       std::span<const Eigen::Matrix<float, M::D, 1>> source,
                       const typename M::State& state, const typename M::Params& delta,
                       double a_t, double step_min, double step_max, const NdtGauss& gc,
                       ThreadTeam& team, NdtEval<M>& ev, int& trials) {
  const double mu = 1e-4, nu = 0.9;
  const double phi_0 = -ev.score, d_phi_0 = -ev.g.dot(delta);
  const auto psi = [&](double a, double f_a) { return f_a - phi_0 - mu * d_phi_0 * a; };
  const auto dpsi = [&](double g_a) { return g_a - mu * d_phi_0; };
  double a_l = 0, a_u = 0;
  double f_l = psi(a_l, phi_0), g_l = dpsi(d_phi_0);
  double f_u = f_l, g_u = g_l;
  bool interval_converged = (step_max - step_min) < 0, open_interval = true;
  ev = ndt_evaluate<M>(grid, source, M::retract(state, delta * a_t), true, gc, team);
  double phi_t = -ev.score, d_phi_t = -ev.g.dot(delta);
  double psi_t = psi(a_t, phi_t), d_psi_t = dpsi(d_phi_t);
  trials = 0;
  while (!interval_converged && trials < 10 && !(psi_t <= 0 && d_phi_t <= -nu * d_phi_0)) {
    a_t = open_interval ? mt_select_trial(a_l, f_l, g_l, a_u, f_u, g_u, a_t, psi_t, d_psi_t)
                        : mt_select_trial(a_l, f_l, g_l, a_u, f_u, g_u, a_t, phi_t, d_phi_t);
    a_t = std::clamp(a_t, step_min, step_max);
    ev = ndt_evaluate<M>(grid, source, M::retract(state, delta * a_t), false, gc, team);
    phi_t = -ev.score;
    d_phi_t = -ev.g.dot(delta);
    psi_t = psi(a_t, phi_t);
    d_psi_t = dpsi(d_phi_t);
    if (open_interval && psi_t <= 0 && d_psi_t >= 0) {
      open_interval = false;  // switch from ψ to φ (Moré–Thuente Sec. 3)
      f_l += phi_0 - mu * d_phi_0 * a_l;
      g_l += mu * d_phi_0;
      f_u += phi_0 - mu * d_phi_0 * a_u;
      g_u += mu * d_phi_0;
    }
    interval_converged =
        open_interval ? mt_update_interval(a_l, f_l, g_l, a_u, f_u, g_u, a_t, psi_t, d_psi_t)
                      : mt_update_interval(a_l, f_l, g_l, a_u, f_u, g_u, a_t, phi_t, d_phi_t);
    ++trials;
  }
  return a_t;
}

/// Newton iterations with the Moré–Thuente line search (PCL 1.13's
/// computeTransformation / computeStepLengthMT). `pcl_rule`: PCL's
/// convergence test and shortest step, and steps taken even when they lower
/// the score (NdtCompat::Pcl); otherwise rove's (NdtOptions).
template <class M>
NdtRun<M> run_ndt(const NdtGrid<M::D>& grid, std::span<const Eigen::Matrix<float, M::D, 1>> source,
                  typename M::State state, const NdtOptions& o, bool pcl_rule) {
  using Params = typename M::Params;
  using MatP = Eigen::Matrix<double, M::P, M::P>;
  const NdtGauss gc = ndt_gauss_constants(o.outlier_ratio, grid.options().resolution, M::D);
  NdtRun<M> run;
  ThreadTeam team(resolve_thread_count(o.num_threads, "NdtOptions::num_threads"));
  NdtEval<M> ev = ndt_evaluate<M>(grid, source, state, true, gc, team);
  // The Newton step's size at the current estimate; NaN when −H is not
  // positive definite (the score has no maximum the step would reach).
  const auto measure_newton = [&](const Params& newton) {
    const Eigen::SelfAdjointEigenSolver<MatP> eig(-0.5 * (ev.H + ev.H.transpose()),
                                                  Eigen::EigenvaluesOnly);
    const bool maximum = eig.info() == Eigen::Success && eig.eigenvalues()(0) > 0;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    run.newton_translation = maximum ? std::sqrt(M::step_translation_sq(newton)) : nan;
    run.newton_rotation =
        maximum ? std::acos(std::clamp(M::step_cos_angle(newton), -1.0, 1.0)) : nan;
  };
  while (true) {
    throw_if_interrupted();
    Eigen::JacobiSVD<MatP> svd(ev.H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Params delta = svd.solve(-ev.g);
    const double delta_norm = delta.norm();
    if (!std::isfinite(delta_norm)) {
      run.diverged = true;
      break;
    }
    if (!pcl_rule) {
      // Converged: the score has a maximum here (−H positive definite) and
      // the full Newton step to it is within the tolerances. A step the
      // step_size cap or the line search shortened never counts.
      measure_newton(delta);
      if (run.newton_translation <= o.translation_tolerance &&
          run.newton_rotation <= o.rotation_tolerance) {
        run.converged = true;
        break;
      }
      if (run.iterations >= o.max_iterations) break;
    }
    if (delta_norm > 0) delta /= delta_norm;
    const double d_phi_0 = -ev.g.dot(delta);
    if (delta_norm == 0 || d_phi_0 == 0) {
      run.converged = pcl_rule;  // PCL: a zero step is convergence
      run.stalled = !pcl_rule;   // here: zero gradient but not a maximum
      break;
    }
    if (d_phi_0 > 0) delta = -delta;  // not a descent direction: search the other way
    // PCL's shortest step is transformation_epsilon / 2; rove's lets the
    // search shorten a step to a thousandth of the tolerances.
    const double step_max = o.step_size;
    const double step_min =
        pcl_rule ? o.transformation_epsilon / 2
                 : std::max(1e-3 * std::min(o.translation_tolerance, o.rotation_tolerance), 1e-12);
    const double phi_0 = -ev.score;
    int trials = 0;
    const double a_t = ndt_line_search<M>(grid, source, state, delta,
                                          std::clamp(delta_norm, step_min, step_max), step_min,
                                          step_max, gc, team, ev, trials);
    const double phi_t = -ev.score;
    const Params step = delta * a_t;
    if (!pcl_rule && std::isfinite(phi_t) && phi_t >= phi_0) {
      // No step along the direction raised the score: keep the estimate
      // (PCL would take the step anyway).
      ev = ndt_evaluate<M>(grid, source, state, true, gc, team);
      run.stalled = true;
      break;
    }
    const typename M::State next = M::retract(state, step);
    ++run.iterations;
    if (!M::finite(next)) {
      run.diverged = true;  // the result keeps the last finite estimate
      break;
    }
    state = next;
    if (trials) ev = ndt_evaluate<M>(grid, source, state, true, gc, team);
    if (!std::isfinite(ev.score)) {
      run.diverged = true;
      break;
    }
    if (!pcl_rule) continue;  // tested at the top, on the new estimate
    const double tsq = M::step_translation_sq(step);
    const double cos_angle = M::step_cos_angle(step);
    const double te = o.transformation_epsilon, re = o.transformation_rotation_epsilon;
    const bool trans_ok = te > 0 && tsq <= te;
    const bool rot_ok = re > 0 && cos_angle >= re;
    if ((trans_ok && rot_ok) || (te <= 0 && rot_ok) || (trans_ok && re <= 0)) {
      run.converged = true;
      break;
    }
    if (run.iterations >= o.max_iterations) break;
  }
  run.state = state;
  run.last = ev;
  return run;
}

/// λmin/λmax of the information of the matched cells' normals at the moved
/// source points (3D: point-to-plane; 2D: (x, y, φ) about the centroid).
template <int D>
double ndt_conditioning(const NdtGrid<D>& grid, std::span<const Eigen::Matrix<double, D, 1>> moved);

/// Termination and message of a run that was neither diverged nor without
/// cells nor degenerate.
std::pair<RegistrationTermination, std::string> ndt_outcome(
    bool stalled, bool converged, int iterations, double newton_translation,
    double newton_rotation, const NdtOptions& o, double probability);

/// What both NDT entry points report, with the estimate's uncertainty in the
/// right tangent of the group (SE(3): (ρ, ω); SE(2): (ρx, ρy, θ)).
template <int P>
struct NdtReport {
  Eigen::Matrix<double, P, P> information = Eigen::Matrix<double, P, P>::Zero();
  Eigen::Matrix<double, P, P> covariance = Eigen::Matrix<double, P, P>::Zero();
  bool has_covariance = false;
  double transformation_probability = 0, goodness = 0, fitness = 0, final_cost = 0;
  std::size_t correspondences = 0;
  int iterations = 0;
  double conditioning = std::numeric_limits<double>::quiet_NaN();
  RegistrationTermination termination = RegistrationTermination::InvalidInput;
  std::string message;
};

/// The estimate and its report.
template <class M>
struct NdtSolution {
  typename M::State state;
  NdtReport<M::P> report;
};

/// Runs NDT from `initial` and reports it (the ending both dimensions and
/// both parametrizations share).
template <class M>
NdtSolution<M> ndt_solve(const NdtGrid<M::D>& grid,
                         std::span<const Eigen::Matrix<float, M::D, 1>> source,
                         const typename M::State& initial, const NdtOptions& o, bool pcl_rule) {
  NdtSolution<M> res;
  res.state = initial;
  NdtReport<M::P>& r = res.report;
  const std::size_t finite =
      std::count_if(source.begin(), source.end(), [](const auto& p) { return p.allFinite(); });
  if (grid.empty() || finite == 0) {
    r.message = grid.empty() ? "the target has no NDT cell (too few points per cell?)"
                               : "the source has no finite point";
    return res;
  }
  const NdtRun<M> run = run_ndt<M>(grid, source, initial, o, pcl_rule);
  res.state = run.state;
  r.iterations = run.iterations;
  r.transformation_probability = run.last.score / static_cast<double>(source.size());
  r.goodness = static_cast<double>(run.last.with_cell) / static_cast<double>(finite);
  r.fitness = run.last.with_cell ? run.last.nearest_sq / static_cast<double>(run.last.with_cell) : 0.0;
  r.final_cost = -run.last.score;
  r.correspondences = run.last.with_cell;
  if (run.diverged) {
    r.termination = RegistrationTermination::Diverged;
    r.message = fmt::format("the Newton step became non-finite at iteration {}", run.iterations);
    return res;
  }
  if (run.last.with_cell == 0) {
    r.termination = RegistrationTermination::TooFewCorrespondences;
    r.message = "no source point lies within one resolution of a target cell";
    return res;
  }
  // Covariance: (−H)⁻¹ of the score Hessian over the parameters, then in
  // the group's right tangent.
  const Eigen::Matrix<double, M::P, M::P> info = -run.last.H;
  const Eigen::Matrix<double, M::P, M::P> C = ndt_covariance<M::P>(info);
  const Eigen::Matrix<double, M::P, M::P> J = M::right_from_params(run.state);
  const Eigen::Matrix<double, M::P, M::P> J_inv = J.inverse();
  r.information = J_inv.transpose() * info * J_inv;
  r.information = 0.5 * (r.information + r.information.transpose());
  r.covariance = J * C * J.transpose();
  r.covariance = 0.5 * (r.covariance + r.covariance.transpose());
  r.has_covariance = true;
  bool degenerate = false;
  if (o.degeneracy_threshold > 0) {
    const M m(run.state);
    std::vector<typename M::Vec> moved;
    moved.reserve(source.size());
    for (const auto& p : source) moved.push_back(m.R * p.template cast<double>() + m.t);
    r.conditioning = ndt_conditioning<M::D>(grid, moved);
    degenerate = r.conditioning < o.degeneracy_threshold;
  }
  if (degenerate) {
    r.termination = RegistrationTermination::Degenerate;
    r.message = fmt::format(
        "the matched cells leave a direction unconstrained (conditioning {:.3g} < {:.3g})",
        r.conditioning, o.degeneracy_threshold);
  } else {
    std::tie(r.termination, r.message) =
        ndt_outcome(run.stalled, run.converged, run.iterations, run.newton_translation,
                    run.newton_rotation, o, r.transformation_probability);
  }
  return res;
}

/// The types and members every parametrization has (see the file comment):
/// D dimensions, P parameters of which A rotate, the estimate's type, and
/// x' = R·x + t with the derivatives dR, d2R of R over the A angles.
template <int Dim, int NumParams, int NumAngles, class StateType>
struct NdtModelBase {
  static constexpr int D = Dim, P = NumParams, A = NumAngles;
  using Params = Eigen::Matrix<double, P, 1>;
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;
  using State = StateType;
  Mat R = Mat::Identity();
  Vec t = Vec::Zero();
  Mat dR[A];
  Mat d2R[A][A];
};

/// rove's parametrization in 3D: a local perturbation of the pose with the
/// target frame's axes about the sensor's position, R ← Exp(ω)·R,
/// t ← t + ρ, ξ = (ρ, ω): the moved point is Exp(ω)·R·x + t + ρ, whose
/// first and second derivatives are exact (generators [e_k]× and
/// ½([e_k]×[e_l]× + [e_l]×[e_k]×) on R·x). Free of gimbal lock, and equal
/// to the right tangent of SE(3) rotated by R to first order: ξ_right =
/// diag(Rᵀ, Rᵀ)·ξ, which is how the result's uncertainty is reported.
struct NdtSe3 : NdtModelBase<3, 6, 3, SE3d> {
  explicit NdtSe3(const SE3d& T) {
    R = T.rotation_matrix();
    t = T.translation();
    for (int k = 0; k < A; ++k) dR[k] = SO3d::hat(Vec::Unit(k));
    for (int k = 0; k < A; ++k)
      for (int l = 0; l < A; ++l) d2R[k][l] = 0.5 * (dR[k] * dR[l] + dR[l] * dR[k]);
  }
  Vec basis(const Vec& x) const { return R * x; }
  static SE3d retract(const SE3d& T, const Params& d) {
    return SE3d(SO3d::exp(d.tail<3>()) * T.rotation(), T.translation() + d.head<3>());
  }
  static bool finite(const SE3d& T) { return T.matrix().allFinite(); }
  static double step_translation_sq(const Params& d) { return d.head<3>().squaredNorm(); }
  static double step_cos_angle(const Params& d) { return std::cos(d.tail<3>().norm()); }
  static Eigen::Matrix<double, P, P> right_from_params(const SE3d& T) {
    Eigen::Matrix<double, P, P> J = Eigen::Matrix<double, P, P>::Zero();
    J.topLeftCorner<3, 3>() = T.rotation_matrix().transpose();
    J.bottomRightCorner<3, 3>() = J.topLeftCorner<3, 3>();
    return J;
  }
  static SE3d to_group(const SE3d& T) { return T; }
};

/// rove's parametrization in 2D, as NdtSe3: θ ← θ + ω, t ← t + ρ.
struct NdtSe2 : NdtModelBase<2, 3, 1, SE2d> {
  explicit NdtSe2(const SE2d& T) {
    R = T.rotation().matrix();
    t = T.translation();
    dR[0] << 0, -1, 1, 0;
    d2R[0][0] = -Mat::Identity();
  }
  Vec basis(const Vec& x) const { return R * x; }
  static SE2d retract(const SE2d& T, const Params& d) {
    return SE2d(SO2d::exp(d.tail<1>()) * T.rotation(), T.translation() + d.head<2>());
  }
  static bool finite(const SE2d& T) { return T.matrix().allFinite(); }
  static double step_translation_sq(const Params& d) { return d.head<2>().squaredNorm(); }
  static double step_cos_angle(const Params& d) { return std::cos(d(2)); }
  static Eigen::Matrix3d right_from_params(const SE2d& T) {
    Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
    J.topLeftCorner<2, 2>() = T.rotation().matrix().transpose();
    return J;
  }
  static SE2d to_group(const SE2d& T) { return T; }
};

/// A solution in another parametrization (PCL's) as the group's.
template <class G, class M>
NdtSolution<G> as_group_solution(const NdtSolution<M>& s) {
  return NdtSolution<G>{M::to_group(s.state), s.report};
}

/// NdtCompat::Pcl (ndt_pcl.cpp).
NdtSolution<NdtSe3> ndt_pcl_3d(const NdtGrid3D& grid, std::span<const Eigen::Vector3f> source,
                               const SE3d& initial, const NdtOptions& o);
NdtSolution<NdtSe2> ndt_pcl_2d(const NdtGrid2D& grid, std::span<const Eigen::Vector2f> source,
                               const SE2d& initial, const NdtOptions& o);

}  // namespace rove::detail
