#include "rove/registration/icp_3d.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/cpu.h"
#include "rove/core/interrupt.h"
#include "rove/math/se3.h"
#include "rove/registration/degeneracy.h"
#include "rove/core/parallel.h"
#include "rove/registration/pose_covariance.h"

namespace rove {

void Icp3dOptions::check() const {
  ROVE_CHECK_MSG(std::isfinite(max_correspondence_distance) && max_correspondence_distance > 0,
                 "max_correspondence_distance must be finite and > 0, got {}",
                 max_correspondence_distance);
  ROVE_CHECK_GE(max_iterations, 1);
  ROVE_CHECK_MSG(std::isfinite(rotation_epsilon) && rotation_epsilon >= 0,
                 "rotation_epsilon must be finite and >= 0, got {}", rotation_epsilon);
  ROVE_CHECK_MSG(std::isfinite(translation_epsilon) && translation_epsilon >= 0,
                 "translation_epsilon must be finite and >= 0, got {}", translation_epsilon);
  ROVE_CHECK_MSG(std::isfinite(lm_initial_lambda) && lm_initial_lambda >= 0,
                 "lm_initial_lambda must be finite and >= 0, got {}", lm_initial_lambda);
  ROVE_CHECK_MSG(std::isfinite(point_variance) && point_variance > 0,
                 "point_variance must be finite and > 0, got {}", point_variance);
  ROVE_CHECK_GE(min_correspondences, std::size_t{6});
  ROVE_CHECK_MSG(degeneracy_threshold >= 0 && degeneracy_threshold < 1,
                 "degeneracy_threshold must be in [0, 1), got {}", degeneracy_threshold);
  ROVE_CHECK_GE(normal_neighbors, std::size_t{3});
  ROVE_CHECK_GE(lm_max_tries, 1);
  (void)resolve_thread_count(num_threads, "Icp3dOptions::num_threads");
}

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

struct Pair3 {
  std::uint32_t source;
  std::uint32_t target;
};

struct Linear6 {
  Mat6 H = Mat6::Zero();
  Vec6 b = Vec6::Zero();
  double cost = 0;     // Σ ρ(s)
  double sq_dist = 0;  // Σ ‖q‖²
  Linear6& operator+=(const Linear6& o) {
    H += o.H;
    b += o.b;
    cost += o.cost;
    sq_dist += o.sq_dist;
    return *this;
  }
};

/// A symmetric 3×3 matrix by its upper triangle; T is double, or V4 (four
/// pairs in vector lanes, below).
template <typename T>
struct Sym3 {
  T xx, xy, xz, yy, yz, zz;
};

/// GICP's information matrix of one pair in the source frame, with both
/// covariances of the plane form I − c·uuᵀ (prepared_cloud.h):
/// (C_s + RᵀC_tR)⁻¹ = (2I − c_s·aaᵀ − c_t·mmᵀ)⁻¹, m = Rᵀn, by its adjugate.
/// The sum's eigenvalues are at least ε_s + ε_t > 0, so it is never
/// singular.
template <typename T>
[[gnu::always_inline]] inline Sym3<T> gicp_information(const T& ax, const T& ay, const T& az, double cs,
                                                       const T& mx, const T& my, const T& mz, double ct) {
  const T s00 = 2.0 - cs * ax * ax - ct * mx * mx;
  const T s01 = 0.0 - cs * ax * ay - ct * mx * my;
  const T s02 = 0.0 - cs * ax * az - ct * mx * mz;
  const T s11 = 2.0 - cs * ay * ay - ct * my * my;
  const T s12 = 0.0 - cs * ay * az - ct * my * mz;
  const T s22 = 2.0 - cs * az * az - ct * mz * mz;
  const T w00 = s11 * s22 - s12 * s12;
  const T w01 = s02 * s12 - s01 * s22;
  const T w02 = s01 * s12 - s02 * s11;
  const T inv = 1.0 / (s00 * w00 + s01 * w01 + s02 * w02);
  return {w00 * inv,
          w01 * inv,
          w02 * inv,
          (s00 * s22 - s02 * s02) * inv,
          (s01 * s02 - s00 * s12) * inv,
          (s00 * s11 - s01 * s01) * inv};
}

/// The terms of JᵀR W RᵀJ and JᵀR·v for J = [R, −R[s]×] (see linearize)
/// and a symmetric W: h, the upper triangle of [W, −WS; SW, −SWS] row by
/// row (S = [s]×), and g = (v, s × v). The columns of WS are s₂W₁ − s₁W₂,
/// s₀W₂ − s₂W₀, s₁W₀ − s₀W₁ (Wⱼ the columns of W), and the rows of S·WS
/// are s₁(WS)₂ − s₂(WS)₁, s₂(WS)₀ − s₀(WS)₂, s₀(WS)₁ − s₁(WS)₀.
template <typename T>
[[gnu::always_inline]] inline void quadratic_terms(const Sym3<T>& W, const T& sx, const T& sy, const T& sz,
                                                   const T& vx, const T& vy, const T& vz, T (&h)[21],
                                                   T (&g)[6]) {
  // X = W·S by columns.
  const T X00 = sz * W.xy - sy * W.xz, X10 = sz * W.yy - sy * W.yz, X20 = sz * W.yz - sy * W.zz;
  const T X01 = sx * W.xz - sz * W.xx, X11 = sx * W.yz - sz * W.xy, X21 = sx * W.zz - sz * W.xz;
  const T X02 = sy * W.xx - sx * W.xy, X12 = sy * W.xy - sx * W.yy, X22 = sy * W.xz - sx * W.yz;
  // Y = S·X, upper triangle.
  const T Y00 = sy * X20 - sz * X10, Y01 = sy * X21 - sz * X11, Y02 = sy * X22 - sz * X12;
  const T Y11 = sz * X01 - sx * X21, Y12 = sz * X02 - sx * X22;
  const T Y22 = sx * X12 - sy * X02;
  h[0] = W.xx, h[1] = W.xy, h[2] = W.xz, h[3] = -X00, h[4] = -X01, h[5] = -X02;
  h[6] = W.yy, h[7] = W.yz, h[8] = -X10, h[9] = -X11, h[10] = -X12;
  h[11] = W.zz, h[12] = -X20, h[13] = -X21, h[14] = -X22;
  h[15] = -Y00, h[16] = -Y01, h[17] = -Y02;
  h[18] = -Y11, h[19] = -Y12;
  h[20] = -Y22;
  g[0] = vx, g[1] = vy, g[2] = vz;
  g[3] = sy * vz - sz * vy;
  g[4] = sz * vx - sx * vz;
  g[5] = sx * vy - sy * vx;
}

/// Adds w·JᵀR W RᵀJ to the upper triangle of acc.H and w·JᵀR·v to acc.b
/// (quadratic_terms).
inline void add_quadratic_sym(Linear6& acc, const Sym3<double>& W, const Eigen::Vector3d& s, double w,
                              const Eigen::Vector3d& v) {
  double h[21], g[6];
  quadratic_terms(W, s.x(), s.y(), s.z(), v.x(), v.y(), v.z(), h, g);
  int j = 0;
  for (int row = 0; row < 6; ++row)
    for (int col = row; col < 6; ++col, ++j) acc.H(row, col) += w * h[j];
  for (int row = 0; row < 6; ++row) acc.b[row] += w * g[row];
}

/// Four doubles (GCC's vector extension): GICP's pairs are linearized four
/// at a time, lane by lane the same arithmetic as one at a time. The
/// baseline build runs each operation as two SSE2 halves, the AVX2 version
/// as one instruction; the results are the same bit for bit.
using V4 = double __attribute__((vector_size(32)));

/// GICP's pairs [b, e) of `pairs` at T (R, t), four per step, added to `a`:
/// the cost and, unless `cost_only`, the upper triangle of H and b
/// (gicp_information and quadratic_terms in every lane), each lane summed
/// on its own and the lanes added in order at the end of the block. Pairs past e ride in the last lanes as
/// copies of pair e − 1 at weight zero.
template <typename Kernel>
[[gnu::always_inline]] inline void gicp_pairs_body(const PreparedCloud3D& target, const PreparedCloud3D& source,
                                                   const std::vector<Pair3>& pairs, std::size_t b, std::size_t e,
                                                   const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double cs,
                                                   double ct, const Kernel& kernel, bool cost_only, Linear6& a) {
  const Eigen::Vector3f* sp = source.points().data();
  const Eigen::Vector3f* tp = target.points().data();
  const Eigen::Vector3d* sa = source.gicp_axes().data();
  const Eigen::Vector3d* ta = target.gicp_axes().data();
  const double r00 = R(0, 0), r01 = R(0, 1), r02 = R(0, 2);
  const double r10 = R(1, 0), r11 = R(1, 1), r12 = R(1, 2);
  const double r20 = R(2, 0), r21 = R(2, 1), r22 = R(2, 2);
  const double tx = t.x(), ty = t.y(), tz = t.z();
  constexpr std::size_t kLanes = 4;
  V4 H[21] = {};  // upper triangle, row by row
  V4 g[6] = {};
  V4 cost = {}, sq = {};
  for (std::size_t k = b; k < e; k += kLanes) {
    std::uint32_t si[kLanes], ti[kLanes];
    V4 live;
    for (std::size_t l = 0; l < kLanes; ++l) {
      const bool in = k + l < e;
      const Pair3& pr = pairs[in ? k + l : e - 1];
      si[l] = pr.source;
      ti[l] = pr.target;
      live[l] = in ? 1.0 : 0.0;
    }
    V4 sx, sy, sz, px, py, pz, ax, ay, az, nx, ny, nz;
    for (std::size_t l = 0; l < kLanes; ++l) {
      const Eigen::Vector3f& s = sp[si[l]];
      const Eigen::Vector3f& p = tp[ti[l]];
      const Eigen::Vector3d& u = sa[si[l]];
      const Eigen::Vector3d& n = ta[ti[l]];
      sx[l] = s.x(), sy[l] = s.y(), sz[l] = s.z();
      px[l] = p.x(), py[l] = p.y(), pz[l] = p.z();
      ax[l] = u.x(), ay[l] = u.y(), az[l] = u.z();
      nx[l] = n.x(), ny[l] = n.y(), nz[l] = n.z();
    }
    // q = R·s + t − p, the residual in the target frame.
    const V4 qx = r00 * sx + r01 * sy + r02 * sz + tx - px;
    const V4 qy = r10 * sx + r11 * sy + r12 * sz + ty - py;
    const V4 qz = r20 * sx + r21 * sy + r22 * sz + tz - pz;
    sq += live * (qx * qx + qy * qy + qz * qz);
    // m = Rᵀn: the target's axis in the source frame.
    const V4 mx = r00 * nx + r10 * ny + r20 * nz;
    const V4 my = r01 * nx + r11 * ny + r21 * nz;
    const V4 mz = r02 * nx + r12 * ny + r22 * nz;
    // W = (2I − c_s·aaᵀ − c_t·mmᵀ)⁻¹.
    const Sym3<V4> W = gicp_information(ax, ay, az, cs, mx, my, mz, ct);
    // qs = Rᵀq and v = W·qs, in the source frame.
    const V4 ux = r00 * qx + r10 * qy + r20 * qz;
    const V4 uy = r01 * qx + r11 * qy + r21 * qz;
    const V4 uz = r02 * qx + r12 * qy + r22 * qz;
    const V4 vx = W.xx * ux + W.xy * uy + W.xz * uz;
    const V4 vy = W.xy * ux + W.yy * uy + W.yz * uz;
    const V4 vz = W.xz * ux + W.yz * uy + W.zz * uz;
    const V4 m2 = ux * vx + uy * vy + uz * vz;
    V4 rho, w;
    for (std::size_t l = 0; l < kLanes; ++l) {
      const KernelValues kv = kernel.evaluate(std::max(0.0, m2[l]));
      rho[l] = kv.rho;
      w[l] = kv.d1;
    }
    cost += live * rho;
    if (cost_only) continue;
    w *= live;
    // add_quadratic_sym, lane by lane.
    V4 h[21], gt[6];
    quadratic_terms(W, sx, sy, sz, vx, vy, vz, h, gt);
    for (int j = 0; j < 21; ++j) H[j] += w * h[j];
    for (int j = 0; j < 6; ++j) g[j] += w * gt[j];
  }
  const auto lanes = [](const V4& v) { return ((v[0] + v[1]) + v[2]) + v[3]; };
  a.cost += lanes(cost);
  a.sq_dist += lanes(sq);
  if (cost_only) return;
  int j = 0;
  for (int row = 0; row < 6; ++row)
    for (int col = row; col < 6; ++col, ++j) a.H(row, col) += lanes(H[j]);
  for (int row = 0; row < 6; ++row) a.b[row] += lanes(g[row]);
}

template <typename Kernel>
void gicp_pairs_baseline(const PreparedCloud3D& target, const PreparedCloud3D& source,
                         const std::vector<Pair3>& pairs, std::size_t b, std::size_t e, const Eigen::Matrix3d& R,
                         const Eigen::Vector3d& t, double cs, double ct, const Kernel& kernel, bool cost_only,
                         Linear6& a) {
  gicp_pairs_body(target, source, pairs, b, e, R, t, cs, ct, kernel, cost_only, a);
}

#if ROVE_AVX2_KERNELS
template <typename Kernel>
__attribute__((target("avx2"))) void gicp_pairs_avx2(const PreparedCloud3D& target, const PreparedCloud3D& source,
                                                     const std::vector<Pair3>& pairs, std::size_t b, std::size_t e,
                                                     const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double cs,
                                                     double ct, const Kernel& kernel, bool cost_only, Linear6& a) {
  gicp_pairs_body(target, source, pairs, b, e, R, t, cs, ct, kernel, cost_only, a);
}
#endif

/// GICP's pairs [b, e), by the AVX2 version where it runs (rove/core/cpu.h).
template <typename Kernel>
void linearize_gicp_pairs(const PreparedCloud3D& target, const PreparedCloud3D& source,
                          const std::vector<Pair3>& pairs, std::size_t b, std::size_t e,
                          const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double cs, double ct,
                          const Kernel& kernel, bool cost_only, Linear6& a) {
#if ROVE_AVX2_KERNELS
  if (avx2_enabled()) {
    gicp_pairs_avx2(target, source, pairs, b, e, R, t, cs, ct, kernel, cost_only, a);
    return;
  }
#endif
  gicp_pairs_baseline(target, source, pairs, b, e, R, t, cs, ct, kernel, cost_only, a);
}

/// Linearizes (or, with `cost_only`, evaluates) the cost of the pairs at T.
template <typename Kernel>
Linear6 linearize(const PreparedCloud3D& target, const PreparedCloud3D& source,
                  const std::vector<Pair3>& pairs, const Eigen::Isometry3d& T,
                  Icp3dMethod method, const Kernel& kernel, bool cost_only,
                  ThreadTeam& team) {
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Matrix3d Rt = R.transpose();
  const Eigen::Vector3d t = T.translation();
  const double cs = 1 - source.options().gicp_epsilon;
  const double ct = 1 - target.options().gicp_epsilon;
  Linear6 sum = parallel_reduce(pairs.size(), team, Linear6{},
                                 [&](std::size_t b, std::size_t e, Linear6& a) {
    // With J = ∂q/∂(ρ, ω) = [R, −R[s]×] and Rᵀ applied to the target side,
    // every product is taken in the source frame: for a symmetric W,
    // JᵀRWRᵀJ = [W, −W[s]×; [s]×W, −[s]×W[s]×], and JᵀR·v = (v, s × v).
    if (method == Icp3dMethod::Gicp) {
      linearize_gicp_pairs(target, source, pairs, b, e, R, t, cs, ct, kernel, cost_only, a);
      return;
    }
    for (std::size_t k = b; k < e; ++k) {
      const Pair3& pr = pairs[k];
      const Eigen::Vector3d s = source.points()[pr.source].cast<double>();
      const Eigen::Vector3d q = R * s + t - target.points()[pr.target].cast<double>();
      a.sq_dist += q.squaredNorm();
      switch (method) {
        case Icp3dMethod::PointToPoint: {
          const auto kv = kernel.evaluate(q.squaredNorm());
          a.cost += kv.rho;
          if (!cost_only) add_quadratic_sym(a, Sym3<double>{1, 0, 0, 1, 0, 1}, s, kv.d1, Rt * q);
          break;
        }
        case Icp3dMethod::PointToPlane: {
          const Eigen::Vector3d n = target.normals()[pr.target].cast<double>();
          const double r = n.dot(q);
          const auto kv = kernel.evaluate(r * r);
          a.cost += kv.rho;
          if (!cost_only) {
            const Eigen::Vector3d m = Rt * n;
            Vec6 j;
            j << m, s.cross(m);
            const Vec6 wj = kv.d1 * j;
            for (int col = 0; col < 6; ++col)
              for (int row = 0; row <= col; ++row) a.H(row, col) += wj[row] * j[col];
            a.b += r * wj;
          }
          break;
        }
        case Icp3dMethod::Gicp:
          break;  // linearize_gicp_pairs, above
      }
    }
  });
  // Only the upper triangle was accumulated.
  sum.H.triangularView<Eigen::StrictlyLower>() = sum.H.transpose();
  return sum;
}

/// Squared distance as KdTree computes it (float, (0 + dx²) + dy² + dz²), so
/// that comparisons agree with its searches.
inline float tree_sq_distance(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  const float dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
  return dx * dx + dy * dy + dz * dz;
}

/// The unique nearest target point to q, found without a tree search by
/// walking from `start` over the target's neighbourhoods. Point p is q's
/// unique nearest when q is strictly nearer to p than to every point p'
/// with |p' − p| < 2|q − p|: any other p' has |q − p'| >= |p' − p| − |q − p|
/// >= |q − p|. Those p' are the front of p's row of neighbours (sorted by
/// distance), and the row must reach past 2|q − p| — beyond its end lie
/// points the row does not list. The factor 4 on squares carries a margin
/// (1e-4 relative) far above the rounding of float distances, so the
/// computed distances order as the true ones and the tree would return the
/// same point. A neighbour strictly nearer than p moves the walk there.
struct Walk {
  std::uint32_t point;  // where the walk ended: q's nearest when certified
  bool certified;
};
Walk certified_nearest(const PreparedCloud3D& target, const Eigen::Vector3f& q, std::uint32_t start) {
  const std::size_t k = target.neighbors_per_point();
  const Neighbor<float>* rows = target.neighborhoods().data();
  const Eigen::Vector3f* pts = target.points().data();
  std::uint32_t p = start;
  float dp = tree_sq_distance(q, pts[p]);
  for (int step = 0; step < 8; ++step) {
    const Neighbor<float>* row = rows + static_cast<std::size_t>(p) * k;
    const float reach = 4.0f * dp * (1.0f + 1e-4f);
    std::uint32_t best = p;
    float best_d = dp;
    bool tie = false, covered = false;
    for (std::size_t j = 0; j < k; ++j) {
      if (row[j].sq_distance > reach) {
        covered = true;  // this one and the rest of the row, and all beyond
        break;
      }
      const std::uint32_t o = row[j].index;
      if (o == p) continue;
      const float d = tree_sq_distance(q, pts[o]);
      if (d < best_d) {
        best = o;
        best_d = d;
        tie = false;
      } else if (d == best_d) {
        tie = true;
      }
    }
    if (best == p) return {p, covered && !tie};
    p = best;
    dp = best_d;
  }
  return {p, false};
}

/// Pairs every source point (moved by T) with its nearest target point within
/// max_dist. `slot` holds the previous pairing (−1: none; empty on the
/// first call): the previous partner's distance bounds the search, which
/// prunes most of the tree and finds the same nearest point.
void find_pairs(const PreparedCloud3D& target, const PreparedCloud3D& source,
                const Eigen::Isometry3d& T, double max_dist, ThreadTeam& team,
                std::vector<std::int64_t>& slot, std::vector<Pair3>& pairs) {
  if (slot.size() != source.size()) slot.assign(source.size(), -1);
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  const float gate = static_cast<float>(max_dist);
  // Admitted as the tree admits: strictly below one ulp above gate².
  const float gate_sq = std::nextafter(gate * gate, std::numeric_limits<float>::infinity());
  const bool certify = target.has_neighborhoods();
  // Source points in their tree's order: consecutive queries are close in
  // space, so their searches walk the same part of the target tree.
  const std::span<const std::uint32_t> order = source.tree().tree_order();
  struct Nothing {
    Nothing& operator+=(const Nothing&) { return *this; }
  };
  parallel_reduce(source.size(), team, Nothing{}, [&](std::size_t b, std::size_t e, Nothing&) {
    // The partner of the previous query of the block: where a query without
    // a partner of its own (the first iteration) starts its walk.
    std::int64_t previous = -1;
    for (std::size_t k = b; k < e; ++k) {
      const std::size_t i = order[k];
      const Eigen::Vector3f q = R * source.points()[i] + t;
      std::int64_t hint = slot[i] >= 0 ? slot[i] : previous;
      if (certify && hint >= 0) {
        const Walk w = certified_nearest(target, q, static_cast<std::uint32_t>(hint));
        if (w.certified) {
          previous = w.point;
          slot[i] = tree_sq_distance(q, target.points()[w.point]) < gate_sq
                        ? static_cast<std::int64_t>(w.point)
                        : std::int64_t{-1};
          continue;
        }
        hint = w.point;
      }
      // The hint (none: −1, out of range) bounds the search: the same
      // nearest point, a smaller ball.
      const auto nn = target.tree().nearest(q, gate, static_cast<std::uint32_t>(hint));
      slot[i] = nn ? static_cast<std::int64_t>(nn->index) : -1;
      if (nn) previous = slot[i];
    }
  });
  pairs.clear();
  for (std::size_t i = 0; i < slot.size(); ++i)
    if (slot[i] >= 0)
      pairs.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(slot[i])});
}

}  // namespace

Icp3dResult icp_3d(const PreparedCloud3D& target, const PreparedCloud3D& source,
                   const SE3d& initial, const Icp3dOptions& o) {
  o.check();
  ROVE_CHECK_MSG(o.method != Icp3dMethod::PointToPlane || target.has_normals() || target.empty(),
                 "point-to-plane ICP needs target normals (PrepareOptions::normals)");
  ROVE_CHECK_MSG(o.method != Icp3dMethod::Gicp ||
                     ((target.has_covariances() || target.empty()) &&
                      (source.has_covariances() || source.empty())),
                 "GICP needs covariances on both clouds (PrepareOptions::covariances)");
  Icp3dResult res;
  res.conditioning = std::numeric_limits<double>::quiet_NaN();
  Eigen::Isometry3d T(initial.matrix());
  auto finish_pose = [&](const Mat6* H, double scale) {
    // Re-orthonormalized: the products of many small steps drift off SO(3).
    res.T_target_source =
        SE3d(Eigen::Quaterniond(T.linear()).normalized(), Eigen::Vector3d(T.translation()));
    if (!H) return;
    res.information = *H;
    res.covariance = covariance_from_information<6>(*H, scale, 1e-12);
  };
  if (target.empty() || source.empty()) {
    finish_pose(nullptr, 1);
    res.termination = RegistrationTermination::InvalidInput;
    res.message = target.empty() ? "the target cloud has no finite point"
                                 : "the source cloud has no finite point";
    return res;
  }

  std::vector<std::int64_t> slot;
  std::vector<Pair3> pairs;
  bool converged = false, diverged = false, too_few = false, stalled = false;
  // Set when the run ends on a step that lowered no cost: the size of the
  // undamped Gauss–Newton step at the estimate (rotation rad, translation m).
  double stall_rotation = 0, stall_translation = 0, stall_relative_decrease = 0;
  Linear6 lin;
  ThreadTeam team(resolve_thread_count(o.num_threads, "Icp3dOptions::num_threads"));
  const auto within_tolerances = [&](const Vec6& d) {
    return d.tail<3>().norm() < o.rotation_epsilon && d.head<3>().norm() < o.translation_epsilon;
  };
  o.kernel.visit([&](const auto& kernel) {
    // Levenberg–Marquardt damping μ, in the units of H: it starts at
    // lm_initial_lambda × max diag(H) of the first linearization and follows
    // Nielsen's update (Madsen, Nielsen & Tingleff, "Methods for non-linear
    // least squares problems", 2004, eq. 3.15-3.16 and Algorithm 3.16). An
    // absolute damping is meaningless here: a GICP Hessian holds thousands
    // of pairs weighted by up to 1/ε each, so a damping of a few thousand
    // leaves a step that raises the cost unchanged.
    double mu = -1;
    for (int it = 0; it < o.max_iterations; ++it) {
      throw_if_interrupted();
      find_pairs(target, source, T, o.max_correspondence_distance, team, slot, pairs);
      res.iterations = it + 1;
      if (pairs.size() < o.min_correspondences) {
        too_few = true;
        return;
      }
      lin = linearize(target, source, pairs, T, o.method, kernel, false, team);
      if (!lin.H.allFinite() || !lin.b.allFinite() || !std::isfinite(lin.cost)) {
        diverged = true;
        return;
      }
      const double max_diag = std::max(lin.H.diagonal().maxCoeff(), 1e-300);
      if (mu < 0) mu = std::max(o.lm_initial_lambda, 1e-15) * max_diag;
      // Damped steps on the fixed pairs until one lowers their cost. The
      // model of Σρ around T is cost + 2bᵀδ + δᵀHδ (IRLS weights), so the
      // predicted decrease of δ = −(H + μI)⁻¹b is δᵀHδ + 2μ‖δ‖².
      double nu = 2;
      Vec6 delta = Vec6::Zero();
      Eigen::Isometry3d T_new = T;
      bool accepted = false;
      for (int tries = 0; tries < o.lm_max_tries; ++tries) {
        const Mat6 A = lin.H + mu * Mat6::Identity();
        delta = A.ldlt().solve(-lin.b);
        if (!delta.allFinite()) break;
        T_new = T * Eigen::Isometry3d(SE3d::exp(delta).matrix());
        const Linear6 trial = linearize(target, source, pairs, T_new, o.method, kernel, true, team);
        const double predicted = delta.dot(lin.H * delta) + 2 * mu * delta.squaredNorm();
        if (std::isfinite(trial.cost) && trial.cost < lin.cost && predicted > 0) {
          const double gain = (lin.cost - trial.cost) / predicted;
          mu *= std::max(1.0 / 3.0, 1 - std::pow(2 * gain - 1, 3));
          mu = std::max(mu, 1e-15 * max_diag);  // keep H + μI well scaled
          accepted = true;
          break;
        }
        // A step within the tolerances that still raises the cost: damping
        // further only shortens it (towards the gradient), stop here.
        if (within_tolerances(delta)) break;
        mu *= nu;
        nu *= 2;
      }
      if (!delta.allFinite() || !T_new.matrix().allFinite()) {
        diverged = true;
        return;
      }
      if (!accepted) {
        // No damped step lowered the cost. The estimate is a minimum of this
        // pairing only if the undamped Gauss–Newton step is itself within
        // the tolerances; otherwise the solve stalled away from one.
        // A second test, after Ceres' function tolerance: the model's best
        // decrease bᵀH⁻¹b is below kFunctionTolerance of the cost, i.e. the
        // estimate is stationary within the model's own error. GICP's model
        // holds the combined covariances fixed while the cost re-evaluates
        // them; on the small_gicp pair at 0.5 m that error hides a predicted
        // 1.3e-5 (a 0.2 mm, 0.002° step), while the stalls this guards
        // against predict a tenth or more of the cost.
        constexpr double kFunctionTolerance = 1e-4;
        const Vec6 gn = (lin.H + 1e-12 * max_diag * Mat6::Identity()).ldlt().solve(-lin.b);
        stall_rotation = gn.tail<3>().norm();
        stall_translation = gn.head<3>().norm();
        stall_relative_decrease = -lin.b.dot(gn) / std::max(lin.cost, 1e-300);
        if (gn.allFinite() &&
            (within_tolerances(gn) || stall_relative_decrease <= kFunctionTolerance)) {
          converged = true;
        } else {
          stalled = true;
        }
        return;
      }
      T = T_new;
      if (within_tolerances(delta)) {
        converged = true;
        return;
      }
    }
  });

  // Final statistics at T with the last pairing.
  res.correspondences = pairs.size();
  res.goodness = static_cast<double>(pairs.size()) / static_cast<double>(source.size());
  if (diverged) {
    finish_pose(nullptr, 1);
    res.termination = RegistrationTermination::Diverged;
    res.message = fmt::format("the step became non-finite at iteration {}", res.iterations);
    return res;
  }
  if (too_few) {
    finish_pose(nullptr, 1);
    res.termination = RegistrationTermination::TooFewCorrespondences;
    res.message = fmt::format("{} pair(s) within {} m at iteration {}; {} needed", pairs.size(),
                              o.max_correspondence_distance, res.iterations,
                              o.min_correspondences);
    return res;
  }
  const Linear6 fin = o.kernel.visit([&](const auto& kernel) {
    return linearize(target, source, pairs, T, o.method, kernel, false, team);
  });
  res.fitness = fin.sq_dist / static_cast<double>(pairs.size());
  res.final_cost = 0.5 * fin.cost;
  finish_pose(&fin.H, o.method == Icp3dMethod::Gicp ? 1.0 : o.point_variance);

  bool degenerate = false;
  if (o.degeneracy_threshold > 0) {
    std::vector<Eigen::Vector3d> q(pairs.size()), n(pairs.size());
    // A target without normals or covariances: fit a normal once per matched
    // target point (several source points often share one), on the team.
    std::vector<Eigen::Vector3f> fitted;
    if (!target.has_normals() && !target.has_covariances()) {
      std::vector<std::uint32_t> matched;
      matched.reserve(pairs.size());
      std::vector<bool> seen(target.size(), false);
      for (const Pair3& pr : pairs)
        if (!seen[pr.target]) {
          seen[pr.target] = true;
          matched.push_back(pr.target);
        }
      fitted.assign(target.size(), Eigen::Vector3f::Zero());
      parallel_for(matched.size(), team, [&](std::size_t j) {
        const std::uint32_t ti = matched[j];
        local_surface_3d(target.tree(), target.points()[ti], o.normal_neighbors, 1e-3, &fitted[ti],
                         nullptr);
      });
    }
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      q[k] = T * source.points()[pairs[k].source].cast<double>();
      const std::uint32_t ti = pairs[k].target;
      if (target.has_normals()) {
        n[k] = target.normals()[ti].cast<double>();
      } else if (target.has_covariances()) {
        n[k] = target.gicp_axes()[ti];  // the local surface's normal (zero: none)
      } else {
        n[k] = fitted[ti].cast<double>();
      }
    }
    res.conditioning = point_to_plane_conditioning(q, n);
    degenerate = res.conditioning < o.degeneracy_threshold;
  }

  if (degenerate) {
    res.termination = RegistrationTermination::Degenerate;
    res.message = degenerate_geometry_message(res.conditioning, o.degeneracy_threshold,
                                              "a single plane");
  } else if (stalled) {
    res.termination = RegistrationTermination::Stalled;
    res.message = fmt::format(
        "no damped step lowered the cost at iteration {} (the Gauss–Newton step was {:.3g} m, "
        "{:.3g}°, above the tolerances, for a predicted decrease of {:.2g} of the cost); the "
        "estimate is the last one that did{}",
        res.iterations, stall_translation, stall_rotation * 180 / 3.14159265358979323846,
        stall_relative_decrease,
        res.iterations == 1 ? " (the initial guess)" : "");
  } else if (converged) {
    res.termination = RegistrationTermination::Converged;
    res.message = fmt::format("converged in {} iterations, {} pairs, fitness {:.4g} m²{}",
                              res.iterations, res.correspondences, res.fitness,
                              stall_rotation > 0 || stall_translation > 0
                                  ? " (the last step, within the tolerances, did not lower the cost)"
                                  : "");
  } else {
    res.termination = RegistrationTermination::MaxIterations;
    res.message = fmt::format("{} iterations without meeting the step tolerances", res.iterations);
  }
  return res;
}

}  // namespace rove
