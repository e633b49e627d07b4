#include "rove/registration/prepared_cloud.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "rove/core/check.h"
#include "rove/core/cpu.h"
#include "rove/core/parallel.h"

namespace rove {

namespace {
struct Nothing {
  Nothing& operator+=(const Nothing&) { return *this; }
};
// The k nearest points of `query` (bounded by `bound`; infinite: none)
// and the covariance of their coordinates. Returns the distance to the
// farthest neighbour (infinite when fewer than 3 were found, and then
// `covariance` is not written). `neighbors` (k entries) receives the
// neighbours, nearest first.
template <typename PointOf>
float neighbourhood_covariance(const KdTree3f& tree, const PointOf& point, const Eigen::Vector3f& query,
                               std::size_t k, float bound, std::span<Neighbor<float>> neighbors,
                               Eigen::Matrix3d& covariance);
// The normal and GICP covariance / axis of a neighbourhood's covariance,
// given its smallest eigenpair (found = false: no extent).
void surface_outputs(bool found, const Eigen::Vector3d& v, double gicp_epsilon, Eigen::Vector3f* normal,
                     Eigen::Matrix3d* covariance, Eigen::Vector3d* axis);
}  // namespace

PreparedCloud3D::PreparedCloud3D() = default;
PreparedCloud3D::PreparedCloud3D(PreparedCloud3D&&) noexcept = default;
PreparedCloud3D& PreparedCloud3D::operator=(PreparedCloud3D&&) noexcept = default;
PreparedCloud3D::~PreparedCloud3D() = default;

PreparedCloud3D::PreparedCloud3D(std::vector<Eigen::Vector3f> points, const PrepareOptions& options)
    : points_(std::move(points)), options_(options) {
  ROVE_CHECK_GE(options.neighbors, std::size_t{3});
  ROVE_CHECK_MSG(options.gicp_epsilon > 0 && options.gicp_epsilon <= 1,
                 "gicp_epsilon must be in (0, 1], got {}", options.gicp_epsilon);
  const int threads = resolve_thread_count(options.num_threads, "PrepareOptions::num_threads");
  ROVE_CHECK_LT(points_.size(), std::size_t{std::numeric_limits<std::uint32_t>::max()});
  std::erase_if(points_, [](const Eigen::Vector3f& p) { return !p.allFinite(); });
  tree_ = KdTree3f(points_);
  if (points_.empty()) return;
  if (options.normals) normals_.assign(points_.size(), Eigen::Vector3f::Zero());
  if (options.covariances) gicp_axes_.assign(points_.size(), Eigen::Vector3d::Zero());
  if (!options.normals && !options.covariances) return;
  // The tree indexes every point of points_ (all finite), so a neighbour's
  // index is its position in points_.
  const auto point = [this](std::uint32_t j) -> const Eigen::Vector3f& { return points_[j]; };
  // Points are visited in the tree's order, so consecutive queries are
  // close in space, and each search is bounded by what the previous one
  // found: the k neighbours of p, within r of it, are within r + |q − p| of
  // q, so q's k nearest all lie in that ball and the search needs to look
  // nowhere else (the same neighbours as an unbounded search, but for which
  // of several points tied at the k-th distance is kept; far fewer nodes
  // visited). Blocks of the order run in parallel, each from an
  // unbounded first search, so the results do not depend on the threads.
  const std::span<const std::uint32_t> order = tree_.tree_order();
  const std::size_t k = std::min(options.neighbors, points_.size());
  if (options.neighborhoods) {
    neighbors_per_point_ = k;
    neighborhoods_.assign(points_.size() * k, Neighbor<float>{});
  }
  constexpr float kInf = std::numeric_limits<float>::infinity();
  parallel_reduce(order.size(), threads, Nothing{},
                          [&](std::size_t begin, std::size_t end, Nothing&) {
    float reach = kInf;  // previous query's farthest neighbour, meters
    Eigen::Vector3f prev = Eigen::Vector3f::Zero();
    // The eigenpairs are solved in batches (smallest_eigenpairs_psd
    // overlaps their Newton steps).
    constexpr std::size_t kBatch = 16;
    std::array<Eigen::Matrix3d, kBatch> C;
    std::array<std::uint32_t, kBatch> owner;
    std::array<double, kBatch> lambda;
    std::array<Eigen::Vector3d, kBatch> axis;
    bool found[kBatch];
    std::size_t pending = 0;
    // Where the neighbours go when the rows are not kept (one allocation
    // per block, not a cleared buffer per point).
    std::vector<Neighbor<float>> scratch(options.neighborhoods ? 0 : k);
    auto solve = [&] {
      smallest_eigenpairs_psd(std::span(C.data(), pending), std::span(lambda.data(), pending),
                              std::span(axis.data(), pending), std::span(found, pending));
      for (std::size_t j = 0; j < pending; ++j) {
        const std::uint32_t i = owner[j];
        surface_outputs(found[j], axis[j], options.gicp_epsilon, options.normals ? &normals_[i] : nullptr,
                        nullptr, options.covariances ? &gicp_axes_[i] : nullptr);
      }
      pending = 0;
    };
    for (std::size_t t = begin; t < end; ++t) {
      const std::uint32_t i = order[t];
      const Eigen::Vector3f& q = points_[i];
      // A hair above, so rounding cannot drop a neighbour on the sphere.
      const float bound =
          reach == kInf ? kInf : (reach + (q - prev).norm()) * (1 + 1e-5f) + 1e-6f;
      const std::span<Neighbor<float>> row =
          options.neighborhoods ? std::span(neighborhoods_).subspan(i * k, k) : std::span(scratch);
      reach = neighbourhood_covariance(tree_, point, q, k, bound, row, C[pending]);
      prev = q;
      // Fewer than 3 neighbours: no extent, the zero outputs stay.
      if (reach == kInf) continue;
      owner[pending++] = i;
      if (pending == kBatch) solve();
    }
    solve();
  });
}

Eigen::Matrix3d PreparedCloud3D::covariance(std::size_t i) const {
  ROVE_CHECK_MSG(has_covariances(), "the cloud was prepared without covariances");
  ROVE_CHECK_LT(i, size());
  const Eigen::Vector3d& v = gicp_axes_[i];
  if (v.isZero(0)) return Eigen::Matrix3d::Identity();
  // The expression local_surface_3d evaluates, to the last bit.
  return Eigen::Matrix3d::Identity() - (1.0 - options_.gicp_epsilon) * v * v.transpose();
}

namespace {

template <typename PointOf>
float neighbourhood_covariance(const KdTree3f& tree, const PointOf& point, const Eigen::Vector3f& query,
                               std::size_t k, float bound, std::span<Neighbor<float>> nn,
                               Eigen::Matrix3d& covariance) {
  std::size_t m = std::isfinite(bound) ? tree.knn(query, k, nn, bound) : tree.knn(query, k, nn);
  if (m < std::min(k, tree.size())) m = tree.knn(query, k, nn);  // the bound was too tight
  if (m < 3) return std::numeric_limits<float>::infinity();
  const float reach = std::sqrt(nn[m - 1].sq_distance);
  // Moments about the query point: the sums stay small, so the covariance
  // keeps its precision far from the origin.
  const double ox = query.x(), oy = query.y(), oz = query.z();
  double sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
  for (std::size_t j = 0; j < m; ++j) {
    const Eigen::Vector3f& pf = point(nn[j].index);
    const double x = static_cast<double>(pf.x()) - ox;
    const double y = static_cast<double>(pf.y()) - oy;
    const double z = static_cast<double>(pf.z()) - oz;
    sx += x;
    sy += y;
    sz += z;
    sxx += x * x;
    sxy += x * y;
    sxz += x * z;
    syy += y * y;
    syz += y * z;
    szz += z * z;
  }
  const double inv = 1.0 / static_cast<double>(m);
  const double mx = sx * inv, my = sy * inv, mz = sz * inv;
  Eigen::Matrix3d& C = covariance;
  C(0, 0) = sxx * inv - mx * mx;
  C(0, 1) = C(1, 0) = sxy * inv - mx * my;
  C(0, 2) = C(2, 0) = sxz * inv - mx * mz;
  C(1, 1) = syy * inv - my * my;
  C(1, 2) = C(2, 1) = syz * inv - my * mz;
  C(2, 2) = szz * inv - mz * mz;
  return reach;
}

void surface_outputs(bool found, const Eigen::Vector3d& v, double gicp_epsilon, Eigen::Vector3f* normal,
                     Eigen::Matrix3d* covariance, Eigen::Vector3d* axis) {
  if (normal) *normal = found ? Eigen::Vector3f(v.cast<float>()) : Eigen::Vector3f::Zero();
  if (axis) *axis = found ? v : Eigen::Vector3d::Zero();
  if (covariance) {
    // V·diag(ε, 1, 1)·Vᵀ = I − (1 − ε)·v₁v₁ᵀ (PreparedCloud3D::covariance
    // evaluates the same expression).
    *covariance = found ? Eigen::Matrix3d(Eigen::Matrix3d::Identity() - (1.0 - gicp_epsilon) * v * v.transpose())
                        : Eigen::Matrix3d::Identity();
  }
}

}  // namespace

namespace {

/// The cubic of smallest_eigenpair_psd for one matrix, on C / scale.
struct Cubic {
  double scale, xx, xy, xz, yy, yz, zz, tr, m2, det, ceiling;
  double lambda;  // the iterate, from the start below the root
};

/// False when C is not finite or zero.
[[gnu::always_inline]] inline bool setup_cubic(const Eigen::Matrix3d& C, Cubic& c) {
  if (!C.allFinite()) return false;
  // On C / scale: entries at most 1, and tr >= 1 (a PSD matrix's largest
  // entry is on its diagonal).
  const double scale = C.cwiseAbs().maxCoeff();
  if (!(scale > 0)) return false;
  const double inv = 1 / scale;
  c.scale = scale;
  c.xx = C(0, 0) * inv;
  c.xy = C(0, 1) * inv;
  c.xz = C(0, 2) * inv;
  c.yy = C(1, 1) * inv;
  c.yz = C(1, 2) * inv;
  c.zz = C(2, 2) * inv;
  const double xx = c.xx, xy = c.xy, xz = c.xz, yy = c.yy, yz = c.yz, zz = c.zz;
  c.tr = xx + yy + zz;
  c.m2 = xx * yy + xx * zz + yy * zz - xy * xy - xz * xz - yz * yz;
  c.det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
  // λ₁ is at most the smallest diagonal entry (a Rayleigh quotient).
  c.ceiling = std::min({xx, yy, zz});
  // Start at det/m₂ = λ₁λ₂λ₃/(λ₁λ₂ + λ₁λ₃ + λ₂λ₃) <= λ₁: below the root
  // as Newton needs, and next to it when λ₁ ≪ λ₂ (a surface), where one or
  // two steps then finish.
  // m₂ at rounding level means rank one (λ₁ = λ₂ = 0) and det/m₂ would be
  // noise over noise; a start the rounding put above the root starts over
  // from 0.
  c.lambda = 0;
  if (c.det > 0 && c.m2 > 1e-12 * c.tr * c.tr) {
    const double start = std::min(c.det / c.m2, c.ceiling);
    if (((start - c.tr) * start + c.m2) * start - c.det < 0) c.lambda = start;
  }
  return true;
}

/// One Newton step on the cubic: whether to go on. λ moves only when the
/// step is taken.
//
// Quadratic convergence on a simple root; at a double root (λ₁ = λ₂,
// where the eigenvector is any vector of a plane) it halves the gap per
// step, so the cap of 64 steps still reaches double precision. Where q' is
// down to rounding (1e-12 of tr², its scale), λ is within ~1e-12 of a
// multiple root and a Newton step would divide noise by noise: stop.
// On a simple root the error after a step s is O(s²/gap), so once a step
// is below 1e-10·tr the next would change λ by ~1e-20 of tr²/gap: stop
// there (the eigenvalue returned is the Rayleigh quotient below anyway).
// That saved one step in four on scan neighbourhoods.
//
// Without branches (both sides of each test computed, then selected), so
// that the steps of several cubics interleave.
inline bool newton_step(Cubic& c) {
  const double lambda = c.lambda;
  const double q = ((lambda - c.tr) * lambda + c.m2) * lambda - c.det;
  const double dq = (3 * lambda - 2 * c.tr) * lambda + c.m2;
  const bool descend = q < 0 && dq > 1e-12 * c.tr * c.tr;
  const double next = std::min(lambda + -q / dq, c.ceiling);
  const bool moves = descend && next > lambda;
  const bool small = !(next - lambda > 1e-10 * c.tr);
  c.lambda = moves ? next : lambda;
  return moves && !small;
}

void newton(Cubic& c) {
  for (int it = 0; it < 64; ++it)
    if (!newton_step(c)) return;
}

/// The eigenvector of the root found and its Rayleigh quotient.
[[gnu::always_inline]] inline void finish_eigenpair(const Cubic& c, double& eigenvalue, Eigen::Vector3d& eigenvector) {
  const double xx = c.xx, xy = c.xy, xz = c.xz, yy = c.yy, yz = c.yz, zz = c.zz;
  const double lambda = c.lambda;
  const Eigen::Vector3d r0(xx - lambda, xy, xz), r1(xy, yy - lambda, yz), r2(xz, yz, zz - lambda);
  // The largest of the three cross products (the first of equals), picked
  // without branches: which one wins depends on the surface's orientation,
  // so a branch would be mispredicted about every other point.
  const Eigen::Vector3d c0 = r0.cross(r1), c1 = r0.cross(r2), c2 = r1.cross(r2);
  const double n0 = c0.squaredNorm(), n1 = c1.squaredNorm(), n2 = c2.squaredNorm();
  const bool take1 = n1 > n0;
  double best_sq = take1 ? n1 : n0;
  const bool take2 = n2 > best_sq;
  best_sq = take2 ? n2 : best_sq;
  Eigen::Vector3d best;
  for (int d = 0; d < 3; ++d) best[d] = take2 ? c2[d] : take1 ? c1[d] : c0[d];
  const double row_sq = std::max({r0.squaredNorm(), r1.squaredNorm(), r2.squaredNorm()});
  // A cross product carries rounding of ~1e-16·|row|²; far above that
  // (1e-10·|row|²) its direction is good to 1e-6. Below it, λ₁ and λ₂
  // agree to 1e-10 (relative) and the eigenvector is any vector of their
  // plane.
  if (best_sq > 1e-20 * row_sq * row_sq) {
    eigenvector = best / std::sqrt(best_sq);
  } else {
    // Rank one or zero: the eigenspace is a plane (orthogonal to the
    // largest row, the first of equals) or everything.
    const Eigen::Vector3d* r[3] = {&r0, &r1, &r2};
    int top = 0;
    for (int i = 1; i < 3; ++i)
      if (r[i]->squaredNorm() > r[top]->squaredNorm()) top = i;
    const Eigen::Vector3d& row = *r[top];
    if (row_sq > 1e-24) {
      Eigen::Index axis = 0;
      row.cwiseAbs().minCoeff(&axis);
      eigenvector = row.cross(Eigen::Vector3d::Unit(axis)).normalized();
    } else {
      eigenvector = Eigen::Vector3d::UnitX();
    }
  }
  // The Rayleigh quotient: exact for an exact eigenvector, and accurate
  // where λ, a multiple root of the cubic, is found only to the square (or
  // cube) root of the rounding.
  const Eigen::Vector3d& v = eigenvector;
  const double rayleigh = xx * v.x() * v.x() + yy * v.y() * v.y() + zz * v.z() * v.z() +
                          2 * (xy * v.x() * v.y() + xz * v.x() * v.z() + yz * v.y() * v.z());
  eigenvalue = std::max(rayleigh, 0.0) * c.scale;
}

}  // namespace

bool smallest_eigenpair_psd(const Eigen::Matrix3d& C, double& eigenvalue, Eigen::Vector3d& eigenvector) {
  Cubic c;
  if (!setup_cubic(C, c)) return false;
  newton(c);
  finish_eigenpair(c, eigenvalue, eigenvector);
  return true;
}

namespace {

/// Four doubles (GCC's vector extension), and a lane mask of the same
/// width (all ones where true).
using V4 = double __attribute__((vector_size(32)));
using M4 = std::int64_t __attribute__((vector_size(32)));

/// smallest_eigenpairs_psd on four matrices at a time, for AVX2:
/// setup_cubic, newton_step and finish_eigenpair lane by lane in vectors,
/// every operation as the scalar code does it (so the results are the
/// same bit for bit). A lane whose cross products all vanish (rank one or
/// zero, rare) takes the scalar finish_eigenpair.
[[gnu::always_inline]] inline void eigenpairs_body(std::span<const Eigen::Matrix3d> C, std::span<double> eigenvalues,
                                                   std::span<Eigen::Vector3d> eigenvectors, std::span<bool> found) {
  constexpr std::size_t kLanes = 4;
  for (std::size_t g = 0; g < C.size(); g += kLanes) {
    const std::size_t n = std::min(kLanes, C.size() - g);
    // setup_cubic, four lanes at once (padding lanes are zero matrices,
    // which it rejects).
    V4 e[9] = {};  // C(r, c) at e[3c + r]
    for (std::size_t j = 0; j < n; ++j)
      for (int i = 0; i < 9; ++i) e[i][j] = C[g + j].data()[i];
    M4 finite = ~M4{};
    V4 scale = {};
    for (int i = 0; i < 9; ++i) {
      const V4 a = e[i] < 0.0 ? -e[i] : e[i];
      finite &= a <= std::numeric_limits<double>::max();  // false for NaN and ±inf
      scale = scale < a ? a : scale;  // the largest |entry|, as cwiseAbs().maxCoeff()
    }
    const M4 ok = finite & (scale > 0.0);
    const V4 inv = 1.0 / scale;
    const V4 xx = e[0] * inv, xy = e[3] * inv, xz = e[6] * inv;
    const V4 yy = e[4] * inv, yz = e[7] * inv, zz = e[8] * inv;
    const V4 tr = xx + yy + zz;
    const V4 m2 = xx * yy + xx * zz + yy * zz - xy * xy - xz * xz - yz * yz;
    const V4 det = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
    V4 ceiling = yy < xx ? yy : xx;  // std::min({xx, yy, zz})
    ceiling = zz < ceiling ? zz : ceiling;
    const V4 ratio = det / m2;
    const V4 start = ceiling < ratio ? ceiling : ratio;  // std::min(det / m2, ceiling)
    const M4 below = (det > 0.0) & (m2 > 1e-12 * tr * tr) & (((start - tr) * start + m2) * start - det < 0.0);
    V4 lambda = below ? start : V4{};
    M4 going = ok;
    for (std::size_t j = 0; j < n; ++j) found[g + j] = ok[j] != 0;
    // newton_step, four lanes at once; a lane that stopped keeps its λ.
    const V4 flat = 1e-12 * tr * tr;
    const V4 tiny = 1e-10 * tr;
    for (int it = 0; it < 64; ++it) {
      const V4 q = ((lambda - tr) * lambda + m2) * lambda - det;
      const V4 dq = (3.0 * lambda - 2.0 * tr) * lambda + m2;
      const M4 descend = (q < 0.0) & (dq > flat);
      const V4 step = lambda + -q / dq;
      const V4 next = ceiling < step ? ceiling : step;  // std::min(step, ceiling)
      const M4 moves = descend & (next > lambda);
      const M4 small = ~(next - lambda > tiny);
      lambda = (going & moves) ? next : lambda;
      going = going & moves & ~small;
      bool any = false;
      for (std::size_t j = 0; j < kLanes; ++j) any = any || going[j] != 0;
      if (!any) break;
    }
    // finish_eigenpair: rows of C − λI, their cross products, the largest.
    const V4 r0x = xx - lambda, r0y = xy, r0z = xz;
    const V4 r1x = xy, r1y = yy - lambda, r1z = yz;
    const V4 r2x = xz, r2y = yz, r2z = zz - lambda;
    const V4 c0x = r0y * r1z - r0z * r1y, c0y = r0z * r1x - r0x * r1z, c0z = r0x * r1y - r0y * r1x;
    const V4 c1x = r0y * r2z - r0z * r2y, c1y = r0z * r2x - r0x * r2z, c1z = r0x * r2y - r0y * r2x;
    const V4 c2x = r1y * r2z - r1z * r2y, c2y = r1z * r2x - r1x * r2z, c2z = r1x * r2y - r1y * r2x;
    const V4 n0 = c0x * c0x + c0y * c0y + c0z * c0z;
    const V4 n1 = c1x * c1x + c1y * c1y + c1z * c1z;
    const V4 n2 = c2x * c2x + c2y * c2y + c2z * c2z;
    const M4 take1 = n1 > n0;
    V4 best_sq = take1 ? n1 : n0;
    const M4 take2 = n2 > best_sq;
    best_sq = take2 ? n2 : best_sq;
    const V4 bx = take2 ? c2x : take1 ? c1x : c0x;
    const V4 by = take2 ? c2y : take1 ? c1y : c0y;
    const V4 bz = take2 ? c2z : take1 ? c1z : c0z;
    const V4 q0 = r0x * r0x + r0y * r0y + r0z * r0z;
    const V4 q1 = r1x * r1x + r1y * r1y + r1z * r1z;
    const V4 q2 = r2x * r2x + r2y * r2y + r2z * r2z;
    V4 row_sq = q0 < q1 ? q1 : q0;  // std::max({q0, q1, q2})
    row_sq = row_sq < q2 ? q2 : row_sq;
    const M4 crossed = best_sq > 1e-20 * row_sq * row_sq;
    V4 norm;
    for (std::size_t j = 0; j < kLanes; ++j) norm[j] = std::sqrt(best_sq[j]);
    const V4 vx = bx / norm, vy = by / norm, vz = bz / norm;
    const V4 rayleigh =
        xx * vx * vx + yy * vy * vy + zz * vz * vz + 2.0 * (xy * vx * vy + xz * vx * vz + yz * vy * vz);
    const V4 value = (rayleigh < 0.0 ? V4{} : rayleigh);  // std::max(rayleigh, 0.0)
    for (std::size_t j = 0; j < n; ++j) {
      if (!found[g + j]) continue;
      if (crossed[j]) {
        eigenvectors[g + j] = Eigen::Vector3d(vx[j], vy[j], vz[j]);
        eigenvalues[g + j] = value[j] * scale[j];
      } else {
        Cubic c{};
        setup_cubic(C[g + j], c);
        c.lambda = lambda[j];
        finish_eigenpair(c, eigenvalues[g + j], eigenvectors[g + j]);
      }
    }
  }
}

/// The baseline version: groups of four in scalar code (the vectors above,
/// split into SSE2 halves, were slower: 120-130 vs 74 ns per matrix), the
/// Newton steps of the four interleaved — a step is a chain of dependent
/// operations ending in a division, and four independent chains keep the
/// divider and the multipliers busy where one would wait on each. A matrix
/// that has converged (or was rejected) keeps its λ while the others step.
void eigenpairs_baseline(std::span<const Eigen::Matrix3d> C, std::span<double> eigenvalues,
                         std::span<Eigen::Vector3d> eigenvectors, std::span<bool> found) {
  constexpr std::size_t kGroup = 4;
  for (std::size_t g = 0; g < C.size(); g += kGroup) {
    const std::size_t n = std::min(kGroup, C.size() - g);
    Cubic c[kGroup] = {};  // zero for the lanes setup_cubic rejects or pads
    bool going[kGroup] = {};
    for (std::size_t j = 0; j < n; ++j) {
      found[g + j] = setup_cubic(C[g + j], c[j]);
      going[j] = found[g + j];
    }
    for (int it = 0; it < 64; ++it) {
      bool any = false;
      for (std::size_t j = 0; j < kGroup; ++j) {
        Cubic stepped = c[j];
        const bool more = newton_step(stepped);
        c[j].lambda = going[j] ? stepped.lambda : c[j].lambda;
        going[j] = going[j] && more;
        any = any || going[j];
      }
      if (!any) break;
    }
    for (std::size_t j = 0; j < n; ++j)
      if (found[g + j]) finish_eigenpair(c[j], eigenvalues[g + j], eigenvectors[g + j]);
  }
}

#if ROVE_AVX2_KERNELS
__attribute__((target("avx2"))) void eigenpairs_avx2(std::span<const Eigen::Matrix3d> C,
                                                     std::span<double> eigenvalues,
                                                     std::span<Eigen::Vector3d> eigenvectors,
                                                     std::span<bool> found) {
  eigenpairs_body(C, eigenvalues, eigenvectors, found);
}
#endif

}  // namespace

void smallest_eigenpairs_psd(std::span<const Eigen::Matrix3d> C, std::span<double> eigenvalues,
                             std::span<Eigen::Vector3d> eigenvectors, std::span<bool> found) {
  ROVE_CHECK_MSG(eigenvalues.size() == C.size() && eigenvectors.size() == C.size() &&
                     found.size() == C.size(),
                 "{} matrices but {} eigenvalues, {} eigenvectors and {} flags", C.size(),
                 eigenvalues.size(), eigenvectors.size(), found.size());
#if ROVE_AVX2_KERNELS
  if (avx2_enabled()) {
    eigenpairs_avx2(C, eigenvalues, eigenvectors, found);
    return;
  }
#endif
  eigenpairs_baseline(C, eigenvalues, eigenvectors, found);
}

void local_surface_3d(const KdTree3f& tree, const Eigen::Vector3f& query, std::size_t k,
                      double gicp_epsilon, Eigen::Vector3f* normal, Eigen::Matrix3d* covariance) {
  Eigen::Matrix3d C;
  std::vector<Neighbor<float>> nn(k);
  const float reach = neighbourhood_covariance(
      tree, [&](std::uint32_t i) { return tree.indexed_point(i); }, query, k,
      std::numeric_limits<float>::infinity(), nn, C);
  double lambda = 0;
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  const bool found = std::isfinite(reach) && smallest_eigenpair_psd(C, lambda, v);
  surface_outputs(found, v, gicp_epsilon, normal, covariance, nullptr);
}

}  // namespace rove
