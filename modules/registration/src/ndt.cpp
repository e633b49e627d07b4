// GCC 12 at -O3 reports -Wmaybe-uninitialized inside Eigen's JacobiSVD once
// it is inlined here (a false positive of its inliner: SVDBase's members are
// written by compute() before any read). The pragma precedes the includes
// because GCC matches it against the location inside Eigen's headers.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "rove/registration/ndt.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <fmt/format.h>

#include "ndt_solver.h"
#include "rove/core/check.h"
#include "rove/poses/lie_conversion.h"
#include "rove/registration/degeneracy.h"
#include "rove/registration/pose_covariance.h"

namespace rove {

void NdtOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(step_size) && step_size > 0, "step_size must be finite and > 0, got {}",
                 step_size);
  ROVE_CHECK_MSG(std::isfinite(transformation_epsilon) && transformation_epsilon >= 0,
                 "transformation_epsilon must be finite and >= 0, got {}", transformation_epsilon);
  ROVE_CHECK_MSG(std::isfinite(transformation_rotation_epsilon) &&
                     transformation_rotation_epsilon >= 0 && transformation_rotation_epsilon <= 1,
                 "transformation_rotation_epsilon must be in [0, 1], got {}",
                 transformation_rotation_epsilon);
  ROVE_CHECK_MSG(std::isfinite(translation_tolerance) && translation_tolerance >= 0,
                 "translation_tolerance must be finite and >= 0, got {}", translation_tolerance);
  ROVE_CHECK_MSG(std::isfinite(rotation_tolerance) && rotation_tolerance >= 0,
                 "rotation_tolerance must be finite and >= 0, got {}", rotation_tolerance);
  ROVE_CHECK_GE(max_iterations, 1);
  ROVE_CHECK_MSG(outlier_ratio > 0 && outlier_ratio < 1, "outlier_ratio must be in (0, 1), got {}",
                 outlier_ratio);
  ROVE_CHECK_MSG(degeneracy_threshold >= 0 && degeneracy_threshold < 1,
                 "degeneracy_threshold must be in [0, 1), got {}", degeneracy_threshold);
  (void)resolve_thread_count(num_threads, "NdtOptions::num_threads");
}

namespace detail {

template <int P>
Eigen::Matrix<double, P, P> ndt_covariance(const Eigen::Matrix<double, P, P>& information) {
  return covariance_from_information<P>(information, 1.0, 1e-12);
}
template Eigen::Matrix3d ndt_covariance<3>(const Eigen::Matrix3d&);
template Eigen::Matrix<double, 6, 6> ndt_covariance<6>(const Eigen::Matrix<double, 6, 6>&);

bool mt_update_interval(double& a_l, double& f_l, double& g_l, double& a_u, double& f_u, double& g_u,
                     double a_t, double f_t, double g_t) {
  if (f_t > f_l) {  // case U1
    a_u = a_t;
    f_u = f_t;
    g_u = g_t;
    return false;
  }
  if (g_t * (a_l - a_t) > 0) {  // case U2
    a_l = a_t;
    f_l = f_t;
    g_l = g_t;
    return false;
  }
  if (g_t * (a_l - a_t) < 0) {  // case U3
    a_u = a_l;
    f_u = f_l;
    g_u = g_l;
    a_l = a_t;
    f_l = f_t;
    g_l = g_t;
    return false;
  }
  return true;  // the interval has collapsed
}

namespace {
double cubic_min(double a_l, double f_l, double g_l, double a_t, double f_t, double g_t) {
  const double z = 3 * (f_t - f_l) / (a_t - a_l) - g_t - g_l;
  const double w = std::sqrt(z * z - g_t * g_l);
  return a_l + (a_t - a_l) * (w - g_l - z) / (g_t - g_l + 2 * w);
}

}  // namespace

double mt_select_trial(double a_l, double f_l, double g_l, double a_u, double f_u, double g_u,
                    double a_t, double f_t, double g_t) {
  if (a_t == a_l && a_t == a_u) return a_t;
  if (a_t != a_l && f_t > f_l) {  // case 1: higher function value
    const double a_c = cubic_min(a_l, f_l, g_l, a_t, f_t, g_t);
    const double a_q = a_l - 0.5 * (a_l - a_t) * g_l / (g_l - (f_l - f_t) / (a_l - a_t));
    return std::abs(a_c - a_l) < std::abs(a_q - a_l) ? a_c : 0.5 * (a_q + a_c);
  }
  if (a_t != a_l && g_t * g_l < 0) {  // case 2: derivatives of opposite sign
    const double a_c = cubic_min(a_l, f_l, g_l, a_t, f_t, g_t);
    const double a_s = a_l - (a_l - a_t) / (g_l - g_t) * g_l;
    return std::abs(a_c - a_t) >= std::abs(a_s - a_t) ? a_c : a_s;
  }
  if (a_t != a_l && std::abs(g_t) <= std::abs(g_l)) {  // case 3: derivative shrinks
    const double a_c = cubic_min(a_l, f_l, g_l, a_t, f_t, g_t);
    const double a_s = a_l - (a_l - a_t) / (g_l - g_t) * g_l;
    const double next = std::abs(a_c - a_t) < std::abs(a_s - a_t) ? a_c : a_s;
    return a_t > a_l ? std::min(a_t + 0.66 * (a_u - a_t), next)
                     : std::max(a_t + 0.66 * (a_u - a_t), next);
  }
  // case 4: the derivative does not shrink
  return cubic_min(a_u, f_u, g_u, a_t, f_t, g_t);
}

template <int D>
double ndt_conditioning(const NdtGrid<D>& grid,
                        std::span<const Eigen::Matrix<double, D, 1>> transformed) {
  std::vector<Eigen::Vector3d> q, n;
  for (const auto& x : transformed) {
    if (!x.allFinite()) continue;
    const auto nn = grid.nearest_cell(x);
    if (!nn) continue;
    Eigen::Vector3d p3 = Eigen::Vector3d::Zero(), n3 = Eigen::Vector3d::Zero();
    p3.head<D>() = x;
    n3.head<D>() = grid.cells()[nn->index].normal;
    q.push_back(p3);
    n.push_back(n3);
  }
  if constexpr (D == 3) {
    return point_to_plane_conditioning(q, n);
  } else {
    // Planar: information over (x, y, phi) about the centroid.
    if (q.size() < 3) return 0.0;
    Eigen::Vector2d c = Eigen::Vector2d::Zero();
    for (const auto& p : q) c += p.head<2>();
    c /= static_cast<double>(q.size());
    double r2 = 0;
    for (const auto& p : q) r2 += (p.head<2>() - c).squaredNorm();
    const double L = std::sqrt(r2 / static_cast<double>(q.size()));
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < q.size(); ++i) {
      const Eigen::Vector2d d = q[i].head<2>() - c;
      const Eigen::Vector3d j(n[i].x(), n[i].y(),
                              L > 0 ? (d.x() * n[i].y() - d.y() * n[i].x()) / L : 0.0);
      A += j * j.transpose();
    }
    const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(A).eigenvalues();
    return ev(2) > 0 ? std::max(ev(0), 0.0) / ev(2) : 0.0;
  }
}

template double ndt_conditioning<2>(const NdtGrid<2>&, std::span<const Eigen::Vector2d>);
template double ndt_conditioning<3>(const NdtGrid<3>&, std::span<const Eigen::Vector3d>);

std::pair<RegistrationTermination, std::string> ndt_outcome(
    bool stalled, bool converged, int iterations, double newton_translation,
    double newton_rotation, const NdtOptions& o, double probability) {
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  const std::string newton =
      std::isnan(newton_translation)
          ? std::string("the score has no maximum there (its Hessian is not negative definite)")
          : fmt::format("the Newton step there is {:.3g} m, {:.3g}° (tolerances {:g} m, {:g}°)",
                        newton_translation, newton_rotation * kDeg, o.translation_tolerance,
                        o.rotation_tolerance * kDeg);
  if (stalled)
    return {RegistrationTermination::Stalled,
            fmt::format("no step along the Newton direction raised the score after {} "
                        "iteration(s); the estimate is the last one that did{}; {}",
                        iterations, iterations == 0 ? " (the initial guess)" : "", newton)};
  if (converged && o.compat == NdtCompat::Pcl)
    return {RegistrationTermination::Converged,
            fmt::format("PCL's rule met in {} iteration(s) (a step's translation² <= {:g} m²; not "
                        "a test of the optimum), probability {:.4g}",
                        iterations, o.transformation_epsilon, probability)};
  if (converged)
    return {RegistrationTermination::Converged,
            fmt::format("converged in {} iteration(s): {}, probability {:.4g}", iterations,
                        newton, probability)};
  return {RegistrationTermination::MaxIterations,
          o.compat == NdtCompat::Pcl
              ? fmt::format("{} iterations without a step below the epsilons", iterations)
              : fmt::format("stopped at the iteration cap ({}); {}", iterations, newton)};
}

}  // namespace detail

namespace {

/// The fields both results take from the solution as they are.
template <class M, class Result>
void copy_report(const detail::NdtSolution<M>& solution, Result& res) {
  const auto& s = solution.report;
  res.information = s.information;
  res.transformation_probability = s.transformation_probability;
  res.goodness = s.goodness;
  res.fitness = s.fitness;
  res.final_cost = s.final_cost;
  res.correspondences = s.correspondences;
  res.iterations = s.iterations;
  res.conditioning = s.conditioning;
  res.termination = s.termination;
  res.message = s.message;
}

}  // namespace

Ndt3dResult ndt_3d(const NdtGrid3D& target, std::span<const Eigen::Vector3f> source,
                   const SE3d& T0, const NdtOptions& o) {
  o.check();
  const detail::NdtSolution<detail::NdtSe3> s =
      o.compat == NdtCompat::Pcl ? detail::ndt_pcl_3d(target, source, T0, o)
                                 : detail::ndt_solve<detail::NdtSe3>(target, source, T0, o, false);
  Ndt3dResult res;
  res.T_target_source = s.state;
  if (s.report.has_covariance) res.covariance = s.report.covariance;
  copy_report(s, res);
  return res;
}

Ndt2dResult ndt_2d(const NdtGrid2D& target, std::span<const Eigen::Vector2f> source,
                   const SE2d& T0, const NdtOptions& o) {
  o.check();
  const detail::NdtSolution<detail::NdtSe2> s =
      o.compat == NdtCompat::Pcl ? detail::ndt_pcl_2d(target, source, T0, o)
                                 : detail::ndt_solve<detail::NdtSe2>(target, source, T0, o, false);
  Ndt2dResult res;
  res.T_target_source = s.state;
  if (s.report.has_covariance) res.covariance = s.report.covariance;
  copy_report(s, res);
  return res;
}

}  // namespace rove
