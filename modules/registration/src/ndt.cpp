// GCC 12 at -O3 reports -Wmaybe-uninitialized inside Eigen's JacobiSVD once
// it is inlined here (a false positive of its inliner: SVDBase's members are
// written by compute() before any read). The pragma precedes the includes
// because GCC matches it against the location inside Eigen's headers.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "rove/registration/ndt.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/interrupt.h"
#include "rove/poses/angle.h"
#include "rove/registration/degeneracy.h"
#include "rove/core/parallel.h"
#include "rove/registration/pose_covariance.h"

namespace rove {

// ---------------------------------------------------------------- the grid

template <int Dim>
NdtGrid<Dim>::NdtGrid() = default;
template <int Dim>
NdtGrid<Dim>::NdtGrid(NdtGrid&&) noexcept = default;
template <int Dim>
NdtGrid<Dim>& NdtGrid<Dim>::operator=(NdtGrid&&) noexcept = default;
template <int Dim>
NdtGrid<Dim>::~NdtGrid() = default;

template <int Dim>
NdtGrid<Dim>::NdtGrid(std::span<const Eigen::Matrix<float, Dim, 1>> points,
                      const NdtGridOptions& options)
    : options_(options) {
  ROVE_CHECK_MSG(std::isfinite(options.resolution) && options.resolution > 0,
                 "resolution must be finite and > 0, got {}", options.resolution);
  ROVE_CHECK_GE(options.min_points_per_voxel, 3);
  ROVE_CHECK_MSG(options.min_covariance_eigenvalue_ratio > 0 &&
                     options.min_covariance_eigenvalue_ratio <= 1,
                 "min_covariance_eigenvalue_ratio must be in (0, 1], got {}",
                 options.min_covariance_eigenvalue_ratio);
  using VecD = Eigen::Matrix<double, Dim, 1>;
  using MatD = Eigen::Matrix<double, Dim, Dim>;
  constexpr int kSq = Dim * (Dim + 1) / 2;  // upper triangle of Σ x·xᵀ
  using SqD = Eigen::Matrix<double, kSq, 1>;
  struct Acc {
    std::uint64_t key = 0;
    VecD sum = VecD::Zero();
    SqD sum_sq = SqD::Zero();
    std::int64_t n = 0;
  };
  // Cell index as PCL: floor(p · (1/resolution)) in float.
  const float inv = static_cast<float>(1.0 / options.resolution);
  constexpr std::int64_t kRange = std::int64_t{1} << 20;  // ±2^20 cells per axis
  // The cells, and an open-addressing table of their positions + 1 (0:
  // free), keyed by cell index, capacity a power of two at most half full.
  std::vector<Acc> accs;
  std::vector<std::uint32_t> slots(64, 0);
  auto slot_of = [&slots](std::uint64_t key) {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 32) & (slots.size() - 1);
  };
  auto cell_of = [&](std::uint64_t key) -> Acc& {
    for (std::size_t s = slot_of(key);; s = (s + 1) & (slots.size() - 1)) {
      if (slots[s] == 0) {
        ROVE_CHECK_MSG(accs.size() < std::numeric_limits<std::uint32_t>::max() - 1,
                       "more than 2^32 - 2 NDT cells");
        accs.push_back(Acc{key});
        slots[s] = static_cast<std::uint32_t>(accs.size());
        if (2 * accs.size() > slots.size()) {
          slots.assign(2 * slots.size(), 0);
          for (std::size_t c = 0; c < accs.size(); ++c) {
            std::size_t t = slot_of(accs[c].key);
            while (slots[t] != 0) t = (t + 1) & (slots.size() - 1);
            slots[t] = static_cast<std::uint32_t>(c + 1);
          }
        }
        return accs.back();
      }
      if (accs[slots[s] - 1].key == key) return accs[slots[s] - 1];
    }
  };
  // A scan's points come in runs within one cell: a run is summed in
  // plain scalars (an Eigen vector was kept in memory, with overlapping
  // loads and stores) and added to its cell when the cell changes.
  std::uint64_t run_key = 0;
  double run_sum[Dim] = {};
  double run_sq[kSq] = {};
  std::int64_t run_n = 0;
  auto end_run = [&] {
    if (run_n == 0) return;
    Acc& a = cell_of(run_key);
    for (int d = 0; d < Dim; ++d) a.sum[d] += run_sum[d];
    for (int k = 0; k < kSq; ++k) a.sum_sq[k] += run_sq[k];
    a.n += run_n;
  };
  for (const auto& p : points) {
    if (!p.allFinite()) continue;
    std::uint64_t key = 0;
    for (int d = 0; d < Dim; ++d) {
      const float f = std::floor(p[d] * inv);
      ROVE_CHECK_MSG(f > -static_cast<float>(kRange) && f < static_cast<float>(kRange),
                     "a point at ({}, {}) is more than 2^20 cells from the origin at resolution {}",
                     p[0], p[1], options.resolution);
      const auto i = static_cast<std::int64_t>(f) + kRange;
      key = (key << 21) | static_cast<std::uint64_t>(i & ((std::int64_t{1} << 21) - 1));
    }
    if (key != run_key) {
      end_run();
      run_key = key;
      for (double& v : run_sum) v = 0;
      for (double& v : run_sq) v = 0;
      run_n = 0;
    }
    const double x = p[0], y = p[1];
    run_sum[0] += x;
    run_sum[1] += y;
    run_sq[0] += x * x;
    run_sq[1] += x * y;
    if constexpr (Dim == 2) {
      run_sq[2] += y * y;
    } else {
      const double z = p[2];
      run_sum[2] += z;
      run_sq[2] += x * z;
      run_sq[3] += y * y;
      run_sq[4] += y * z;
      run_sq[5] += z * z;
    }
    ++run_n;
  }
  end_run();
  // Deterministic cell order: by key.
  std::vector<std::pair<std::uint64_t, const Acc*>> order;
  order.reserve(accs.size());
  for (const Acc& a : accs) order.emplace_back(a.key, &a);
  std::sort(order.begin(), order.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<VecD> means;
  for (const auto& [key, a] : order) {
    if (a->n < options.min_points_per_voxel) continue;
    NdtCell<Dim> c;
    c.points = static_cast<int>(std::min<std::int64_t>(a->n, std::numeric_limits<int>::max()));
    c.mean = a->sum / static_cast<double>(a->n);
    // Sample covariance (n − 1), as PCL's VoxelGridCovariance.
    MatD sum_sq;
    for (int r = 0, k = 0; r < Dim; ++r)
      for (int q = r; q < Dim; ++q, ++k) sum_sq(r, q) = sum_sq(q, r) = a->sum_sq[k];
    MatD cov = (sum_sq - a->sum * c.mean.transpose()) / (static_cast<double>(a->n) - 1.0);
    Eigen::SelfAdjointEigenSolver<MatD> eig(cov);
    VecD ev = eig.eigenvalues();
    if (!(ev(Dim - 1) > 0) || ev(0) < -Eigen::NumTraits<double>::dummy_precision()) continue;
    const double floor = options.min_covariance_eigenvalue_ratio * ev(Dim - 1);
    // A cell whose points lie on a line (3D: second eigenvalue below the
    // floor too) has no defined surface normal.
    const bool has_normal = Dim == 2 || ev(1) >= floor;
    for (int d = 0; d < Dim - 1; ++d) ev(d) = std::max(ev(d), floor);
    cov = eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
    c.inverse_covariance = eig.eigenvectors() * ev.cwiseInverse().asDiagonal() *
                           eig.eigenvectors().transpose();
    if (!c.inverse_covariance.allFinite()) continue;
    c.normal = has_normal ? VecD(eig.eigenvectors().col(0)) : VecD::Zero();
    cells_.push_back(c);
    means.push_back(c.mean);
  }
  tree_ = KdTree<Dim, double>(std::move(means));
  build_lookup();
}

template <int Dim>
void NdtGrid<Dim>::build_lookup() {
  using Key = Eigen::Matrix<std::int64_t, Dim, 1>;
  if (cells_.empty()) return;
  const double inv = 1.0 / options_.resolution;
  std::vector<Key> own(cells_.size());
  Key lo = Key::Constant(std::numeric_limits<std::int64_t>::max());
  Key hi = Key::Constant(std::numeric_limits<std::int64_t>::min());
  for (std::size_t c = 0; c < cells_.size(); ++c) {
    for (int d = 0; d < Dim; ++d) own[c][d] = static_cast<std::int64_t>(std::floor(cells_[c].mean[d] * inv));
    lo = lo.cwiseMin(own[c]);
    hi = hi.cwiseMax(own[c]);
  }
  // One cell of margin on every side: a query up to a cell outside the
  // means' box still reads one list.
  const Key size = hi - lo + Key::Constant(3);
  double volume = 1;
  for (int d = 0; d < Dim; ++d) volume *= static_cast<double>(size[d]);
  const double cap = std::max(double{1 << 22}, 64.0 * static_cast<double>(cells_.size()));
  constexpr std::size_t kSpan = Dim == 3 ? 27 : 9;  // lists a cell is in
  // Sparse and wide, or more list entries than 32 bits count: cells_near
  // searches the tree.
  if (volume > cap || cells_.size() > std::numeric_limits<std::uint32_t>::max() / kSpan) return;
  lookup_min_ = lo - Key::Ones();
  lookup_size_ = size;
  auto linear = [&](const Key& k) {
    std::size_t l = 0;
    for (int d = Dim - 1; d >= 0; --d)
      l = l * static_cast<std::size_t>(size[d]) + static_cast<std::size_t>(k[d] - lookup_min_[d]);
    return l;
  };
  // The 3^Dim lookup cells around one: their steps per axis and linear
  // offsets, in row-major order (the order cells_near reports in).
  std::array<Key, kSpan> steps;
  std::array<std::int64_t, kSpan> offsets{};
  for (std::size_t o = 0; o < kSpan; ++o) {
    std::size_t rest = o;
    for (int d = 0; d < Dim; ++d, rest /= 3) steps[o][d] = static_cast<std::int64_t>(rest % 3) - 1;
    for (int d = Dim - 1; d >= 0; --d) offsets[o] = offsets[o] * size[d] + steps[o][d];
  }
  // A list holds only the cells whose mean is within r of its lookup
  // cell's box: no other can be within r of a query in it. The box is
  // widened by a relative 1e-9 so that a query whose floor(x / r) rounds
  // across a face still finds every cell.
  const double r = options_.resolution;
  auto reaches = [&](std::uint32_t c, std::size_t o) {
    double d2 = 0;
    for (int d = 0; d < Dim; ++d) {
      const double lo_face = static_cast<double>(own[c][d] + steps[o][d]) * r;
      const double hi_face = lo_face + r;
      const double slack = 1e-9 * (std::abs(lo_face) + r);
      const double m = cells_[c].mean[d];
      const double gap = std::max({lo_face - slack - m, m - hi_face - slack, 0.0});
      d2 += gap * gap;
    }
    return d2 <= r * r;
  };
  // Cells by own lookup cell, then index: filling the lists in this order
  // leaves every list in row-major order of the cells it holds.
  std::vector<std::pair<std::size_t, std::uint32_t>> order(cells_.size());
  for (std::size_t c = 0; c < cells_.size(); ++c) order[c] = {linear(own[c]), static_cast<std::uint32_t>(c)};
  std::sort(order.begin(), order.end());
  lookup_start_.assign(static_cast<std::size_t>(volume) + 1, 0);
  // Own cells are at least one cell inside the margin, so every neighbour
  // is in the index.
  for (const auto& [l, c] : order)
    for (std::size_t o = 0; o < kSpan; ++o)
      if (reaches(c, o)) ++lookup_start_[static_cast<std::size_t>(static_cast<std::int64_t>(l) + offsets[o]) + 1];
  for (std::size_t l = 1; l < lookup_start_.size(); ++l) lookup_start_[l] += lookup_start_[l - 1];
  lookup_cells_.resize(lookup_start_.back());
  std::vector<std::uint32_t> fill(lookup_start_.begin(), lookup_start_.end() - 1);
  for (const auto& [l, c] : order)
    for (std::size_t o = 0; o < kSpan; ++o)
      if (reaches(c, o)) lookup_cells_[fill[static_cast<std::size_t>(static_cast<std::int64_t>(l) + offsets[o])]++] = c;
  lookup_means_.resize(cells_.size());
  for (std::size_t c = 0; c < cells_.size(); ++c) lookup_means_[c] = cells_[c].mean;
}

template <int Dim>
std::int64_t NdtGrid<Dim>::lookup_index(const Point& x) const {
  const double inv = 1.0 / options_.resolution;
  std::int64_t l = 0;
  for (int d = Dim - 1; d >= 0; --d) {
    const double f = std::floor(x[d] * inv);  // NaN fails both comparisons
    if (!(f >= static_cast<double>(lookup_min_[d]) &&
          f < static_cast<double>(lookup_min_[d] + lookup_size_[d])))
      return -1;
    l = l * lookup_size_[d] + (static_cast<std::int64_t>(f) - lookup_min_[d]);
  }
  return l;
}

template <int Dim>
std::size_t NdtGrid<Dim>::cells_near(const Point& x, std::span<Neighbor<double>, kMaxNear> out) const {
  const double r = options_.resolution;
  if (lookup_start_.empty()) {
    if (cells_.empty()) return 0;
    thread_local std::vector<Neighbor<double>> hits;
    tree_.radius(x, r, hits, false);
    const std::size_t n = std::min(hits.size(), kMaxNear);
    std::copy_n(hits.begin(), n, out.begin());
    return n;
  }
  // A mean within r of x lies in x's lookup cell or one of its neighbours
  // (cells have side r): x's list holds the whole answer.
  const std::int64_t l = lookup_index(x);
  if (l < 0) return 0;
  const double r2 = r * r;
  std::size_t n = 0;
  const std::uint32_t* c = lookup_cells_.data() + lookup_start_[static_cast<std::size_t>(l)];
  const std::uint32_t* const end = lookup_cells_.data() + lookup_start_[static_cast<std::size_t>(l) + 1];
  if (static_cast<std::size_t>(end - c) <= kMaxNear) {
    // Every candidate fits: write each, keep those within r (no branch to
    // mispredict).
    for (; c != end; ++c) {
      const double d2 = (x - lookup_means_[*c]).squaredNorm();
      out[n] = Neighbor<double>{*c, d2};
      n += d2 <= r2 ? 1 : 0;
    }
    return n;
  }
  for (; c != end; ++c) {
    const double d2 = (x - lookup_means_[*c]).squaredNorm();
    if (d2 <= r2 && n < kMaxNear) out[n++] = Neighbor<double>{*c, d2};
  }
  return n;
}

template <int Dim>
std::optional<Neighbor<double>> NdtGrid<Dim>::nearest_cell(const Point& x) const {
  const double r = options_.resolution;
  if (lookup_start_.empty()) {
    if (cells_.empty() || !x.allFinite()) return std::nullopt;
    const auto nn = tree_.nearest(x, r);
    if (!nn) return std::nullopt;
    return Neighbor<double>{nn->index, nn->sq_distance};
  }
  const std::int64_t l = lookup_index(x);
  if (l < 0) return std::nullopt;
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t best = kNone;  // cells_.size() < kNone (build_lookup)
  double best_d2 = r * r;
  for (std::uint32_t j = lookup_start_[static_cast<std::size_t>(l)];
       j < lookup_start_[static_cast<std::size_t>(l) + 1]; ++j) {
    const std::uint32_t c = lookup_cells_[j];
    const double d2 = (x - lookup_means_[c]).squaredNorm();
    const bool better = d2 < best_d2 || (d2 == best_d2 && c < best);
    best = better ? c : best;
    best_d2 = better ? d2 : best_d2;
  }
  if (best == kNone) return std::nullopt;
  return Neighbor<double>{best, best_d2};
}

template class NdtGrid<2>;
template class NdtGrid<3>;

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

// ------------------------------------------------------- the motion models

namespace {

/// 3D: parameters (x, y, z, roll, pitch, yaw), R = Rx(roll)·Ry(pitch)·Rz(yaw)
/// as PCL's NDT. Precomputes R, its first and second derivatives with
/// respect to the three angles (Magnusson eq. 6.17-6.21 in matrix form).
struct Model3 {
  static constexpr int D = 3, P = 6, A = 3;  // dims, parameters, angles
  using Params = Eigen::Matrix<double, P, 1>;
  using Vec = Eigen::Vector3d;
  using Mat = Eigen::Matrix3d;
  Mat R;
  Vec t;
  Mat dR[A];
  Mat d2R[A][A];
  explicit Model3(const Params& p) {
    const double ca = std::cos(p(3)), sa = std::sin(p(3));
    const double cb = std::cos(p(4)), sb = std::sin(p(4));
    const double cc = std::cos(p(5)), sc = std::sin(p(5));
    Mat X[3], Y[3], Z[3];  // value, first, second derivative
    X[0] << 1, 0, 0, 0, ca, -sa, 0, sa, ca;
    X[1] << 0, 0, 0, 0, -sa, -ca, 0, ca, -sa;
    X[2] << 0, 0, 0, 0, -ca, sa, 0, -sa, -ca;
    Y[0] << cb, 0, sb, 0, 1, 0, -sb, 0, cb;
    Y[1] << -sb, 0, cb, 0, 0, 0, -cb, 0, -sb;
    Y[2] << -cb, 0, -sb, 0, 0, 0, sb, 0, -cb;
    Z[0] << cc, -sc, 0, sc, cc, 0, 0, 0, 1;
    Z[1] << -sc, -cc, 0, cc, -sc, 0, 0, 0, 0;
    Z[2] << -cc, sc, 0, -sc, -cc, 0, 0, 0, 0;
    R = X[0] * Y[0] * Z[0];
    t = p.head<3>();
    dR[0] = X[1] * Y[0] * Z[0];
    dR[1] = X[0] * Y[1] * Z[0];
    dR[2] = X[0] * Y[0] * Z[1];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int oi[3] = {i == 0 ? 1 : 0, i == 1 ? 1 : 0, i == 2 ? 1 : 0};
        const int oj[3] = {j == 0 ? 1 : 0, j == 1 ? 1 : 0, j == 2 ? 1 : 0};
        d2R[i][j] = X[oi[0] + oj[0]] * Y[oi[1] + oj[1]] * Z[oi[2] + oj[2]];
      }
  }
  static Params from_isometry(const Eigen::Isometry3d& T) {
    const Mat& m = T.linear();
    Params p;
    p.head<3>() = T.translation();
    // R = Rx(a)·Ry(b)·Rz(c): R(0,2) = sin b, R(1,2) = −sin a cos b,
    // R(2,2) = cos a cos b, R(0,1) = −cos b sin c, R(0,0) = cos b cos c.
    p(4) = std::asin(std::clamp(m(0, 2), -1.0, 1.0));
    p(3) = std::atan2(-m(1, 2), m(2, 2));
    p(5) = std::atan2(-m(0, 1), m(0, 0));
    return p;
  }
  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = t;
    return T;
  }
};

/// 2D: parameters (x, y, phi).
struct Model2 {
  static constexpr int D = 2, P = 3, A = 1;
  using Params = Eigen::Vector3d;
  using Vec = Eigen::Vector2d;
  using Mat = Eigen::Matrix2d;
  Mat R;
  Vec t;
  Mat dR[A];
  Mat d2R[A][A];
  explicit Model2(const Params& p) {
    const double c = std::cos(p(2)), s = std::sin(p(2));
    R << c, -s, s, c;
    dR[0] << -s, -c, c, -s;
    d2R[0][0] = -R;
    t = p.head<2>();
  }
};

template <class M>
struct Eval {
  double score = 0;
  typename M::Params g = M::Params::Zero();
  Eigen::Matrix<double, M::P, M::P> H = Eigen::Matrix<double, M::P, M::P>::Zero();
  std::size_t with_cell = 0;
  double nearest_sq = 0;
  Eval& operator+=(const Eval& o) {
    score += o.score;
    g += o.g;
    H += o.H;
    with_cell += o.with_cell;
    nearest_sq += o.nearest_sq;
    return *this;
  }
};

struct Gauss {
  double d1, d2;
};

/// Score, gradient and (optionally) Hessian of the NDT score at `p`
/// (Magnusson Algorithm 2, lines 17-21; eq. 6.10, 6.12, 6.13).
///
/// Every cell near one source point shares that point's Jacobian J = [I | J_r]
/// (J_r's columns ∂R/∂angle_k · x), so the sums over the point's cells are
/// taken before J is applied: with v = C·x' and f = d₁d₂·exp(−d₂/2·x'ᵀv),
///   g_i = Jᵀ·w,  w = Σ f·v,
///   H_i = Jᵀ·S·J + Σ_kl w·(∂²R/∂k∂l · x),  S = Σ f·(C − d₂·v·vᵀ),
/// which is eq. 6.12-6.13 summed in another order: 3 + 6 numbers per cell
/// instead of a 6 × 6 product.
template <class M>
Eval<M> evaluate(const NdtGrid<M::D>& grid, std::span<const Eigen::Matrix<float, M::D, 1>> source,
                 const typename M::Params& p, bool hessian, const Gauss& gc,
                 ThreadTeam& team) {
  using Vec = typename M::Vec;
  using Mat = typename M::Mat;
  constexpr int D = M::D, A = M::A;
  const M model(p);
  return parallel_reduce(source.size(), team, Eval<M>{},
                                 [&](std::size_t b, std::size_t e, Eval<M>& a) {
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
      for (int k = 0; k < A; ++k) Jr.col(k) = model.dR[k] * x;
      a.g.template head<D>() += w;
      a.g.template tail<A>() += Jr.transpose() * w;
      if (hessian) {
        const Eigen::Matrix<double, D, A> SJr = S * Jr;
        a.H.template topLeftCorner<D, D>() += S;
        a.H.template topRightCorner<D, A>() += SJr;
        a.H.template bottomLeftCorner<A, D>() += SJr.transpose();
        Eigen::Matrix<double, A, A> rr = Jr.transpose() * SJr;
        for (int k = 0; k < A; ++k)
          for (int l = 0; l < A; ++l) rr(k, l) += w.dot(model.d2R[k][l] * x);
        a.H.template bottomRightCorner<A, A>() += rr;
      }
    }
  });
}

// Moré–Thuente (1994) helpers, in the notation of the paper: ψ(α) =
// φ(α) − φ(0) − μφ'(0)α, the interval update of Sec. 2 and the trial value
// selection of Sec. 4 (cases 1-4).
double psi(double a, double f_a, double f_0, double g_0, double mu) {
  return f_a - f_0 - mu * g_0 * a;
}
double dpsi(double g_a, double g_0, double mu) { return g_a - mu * g_0; }

bool update_interval(double& a_l, double& f_l, double& g_l, double& a_u, double& f_u, double& g_u,
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

double cubic_min(double a_l, double f_l, double g_l, double a_t, double f_t, double g_t) {
  const double z = 3 * (f_t - f_l) / (a_t - a_l) - g_t - g_l;
  const double w = std::sqrt(z * z - g_t * g_l);
  return a_l + (a_t - a_l) * (w - g_l - z) / (g_t - g_l + 2 * w);
}

double select_trial(double a_l, double f_l, double g_l, double a_u, double f_u, double g_u,
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

template <class M>
struct NdtRun {
  typename M::Params p;
  Eval<M> last;
  int iterations = 0;
  bool converged = false;
  bool diverged = false;
  bool stalled = false;  // the line search found no step that raised the score
  // The Newton step at the result (before the step_size cap), as the
  // convergence test measures it: translation m, rotation rad; NaN when the
  // score Hessian there is not negative definite (no maximum nearby).
  double newton_translation = 0, newton_rotation = 0;
};

/// Newton iterations with the Moré–Thuente line search (PCL 1.13's
/// computeTransformation / computeStepLengthMT).
template <class M>
NdtRun<M> run_ndt(const NdtGrid<M::D>& grid, std::span<const Eigen::Matrix<float, M::D, 1>> source,
                  typename M::Params p, const NdtOptions& o, const Gauss& gc,
                  double (*step_translation_sq)(const typename M::Params&),
                  double (*step_cos_angle)(const typename M::Params&)) {
  using Params = typename M::Params;
  using MatP = Eigen::Matrix<double, M::P, M::P>;
  const bool pcl_rule = o.convergence == NdtConvergence::Pcl;
  NdtRun<M> run;
  ThreadTeam team(resolve_thread_count(o.num_threads, "NdtOptions::num_threads"));
  Eval<M> ev = evaluate<M>(grid, source, p, true, gc, team);
  // The Newton step's size at the current estimate; NaN when −H is not
  // positive definite (the score has no maximum the step would reach).
  const auto measure_newton = [&](const Params& newton) {
    const Eigen::SelfAdjointEigenSolver<MatP> eig(-0.5 * (ev.H + ev.H.transpose()),
                                                  Eigen::EigenvaluesOnly);
    const bool maximum = eig.info() == Eigen::Success && eig.eigenvalues()(0) > 0;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    run.newton_translation = maximum ? std::sqrt(step_translation_sq(newton)) : nan;
    run.newton_rotation =
        maximum ? std::acos(std::clamp(step_cos_angle(newton), -1.0, 1.0)) : nan;
  };
  while (true) {
    throw_if_interrupted();
    Eigen::JacobiSVD<MatP> svd(ev.H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Params delta = svd.solve(-ev.g);
    double delta_norm = delta.norm();
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
    if (delta_norm == 0) {
      run.converged = pcl_rule;  // PCL: a zero step is convergence
      run.stalled = !pcl_rule;   // here: zero gradient but not a maximum
      break;
    }
    delta /= delta_norm;
    // Line search on φ(α) = −score(p + α·δ). PCL's shortest step is
    // transformation_epsilon / 2; the default rule lets the search shorten
    // a step to a thousandth of the tolerances.
    const double step_max = o.step_size;
    const double step_min =
        pcl_rule ? o.transformation_epsilon / 2
                 : std::max(1e-3 * std::min(o.translation_tolerance, o.rotation_tolerance), 1e-12);
    const double mu = 1e-4, nu = 0.9;
    const double phi_0 = -ev.score;
    double d_phi_0 = -ev.g.dot(delta);
    double a_t = 0;
    if (d_phi_0 >= 0) {
      if (d_phi_0 == 0) {
        run.converged = pcl_rule;
        run.stalled = !pcl_rule;
        break;
      }
      d_phi_0 = -d_phi_0;  // not a descent direction: search the other way
      delta = -delta;
    }
    double a_l = 0, a_u = 0;
    double f_l = psi(a_l, phi_0, phi_0, d_phi_0, mu), g_l = dpsi(d_phi_0, d_phi_0, mu);
    double f_u = f_l, g_u = g_l;
    bool interval_converged = (step_max - step_min) < 0, open_interval = true;
    a_t = std::clamp(delta_norm, step_min, step_max);
    ev = evaluate<M>(grid, source, p + delta * a_t, true, gc, team);
    double phi_t = -ev.score, d_phi_t = -ev.g.dot(delta);
    double psi_t = psi(a_t, phi_t, phi_0, d_phi_0, mu), d_psi_t = dpsi(d_phi_t, d_phi_0, mu);
    int steps = 0;
    while (!interval_converged && steps < 10 && !(psi_t <= 0 && d_phi_t <= -nu * d_phi_0)) {
      a_t = open_interval ? select_trial(a_l, f_l, g_l, a_u, f_u, g_u, a_t, psi_t, d_psi_t)
                          : select_trial(a_l, f_l, g_l, a_u, f_u, g_u, a_t, phi_t, d_phi_t);
      a_t = std::clamp(a_t, step_min, step_max);
      ev = evaluate<M>(grid, source, p + delta * a_t, false, gc, team);
      phi_t = -ev.score;
      d_phi_t = -ev.g.dot(delta);
      psi_t = psi(a_t, phi_t, phi_0, d_phi_0, mu);
      d_psi_t = dpsi(d_phi_t, d_phi_0, mu);
      if (open_interval && psi_t <= 0 && d_psi_t >= 0) {
        open_interval = false;  // switch from ψ to φ (Moré–Thuente Sec. 3)
        f_l += phi_0 - mu * d_phi_0 * a_l;
        g_l += mu * d_phi_0;
        f_u += phi_0 - mu * d_phi_0 * a_u;
        g_u += mu * d_phi_0;
      }
      interval_converged =
          open_interval ? update_interval(a_l, f_l, g_l, a_u, f_u, g_u, a_t, psi_t, d_psi_t)
                        : update_interval(a_l, f_l, g_l, a_u, f_u, g_u, a_t, phi_t, d_phi_t);
      ++steps;
    }
    const Params step = delta * a_t;
    if (!pcl_rule && std::isfinite(phi_t) && phi_t >= phi_0) {
      // No step along the direction raised the score: keep the estimate
      // (PCL would take the step anyway).
      ev = evaluate<M>(grid, source, p, true, gc, team);
      run.stalled = true;
      break;
    }
    p += step;
    if (steps) ev = evaluate<M>(grid, source, p, true, gc, team);
    ++run.iterations;
    if (!p.allFinite() || !std::isfinite(ev.score)) {
      run.diverged = true;
      break;
    }
    if (!pcl_rule) continue;  // tested at the top, on the new estimate
    const double tsq = step_translation_sq(step);
    const double cos_angle = step_cos_angle(step);
    const double te = o.transformation_epsilon, re = o.transformation_rotation_epsilon;
    const bool trans_ok = te > 0 && tsq <= te;
    const bool rot_ok = re > 0 && cos_angle >= re;
    if ((trans_ok && rot_ok) || (te <= 0 && rot_ok) || (trans_ok && re <= 0)) {
      run.converged = true;
      break;
    }
    if (run.iterations >= o.max_iterations) break;
  }
  run.p = p;
  run.last = ev;
  return run;
}

Gauss gauss_constants(double outlier_ratio, double resolution, int dim) {
  // Magnusson 2009, eq. 6.8 (as PCL): c₁ = 10(1 − p_o), c₂ = p_o / r^dim.
  const double c1 = 10 * (1 - outlier_ratio);
  const double c2 = outlier_ratio / std::pow(resolution, dim);
  const double d3 = -std::log(c2);
  Gauss g;
  g.d1 = -std::log(c1 + c2) - d3;
  g.d2 = -2 * std::log((-std::log(c1 * std::exp(-0.5) + c2) - d3) / g.d1);
  return g;
}

template <int D, typename Pt>
double conditioning_of(const NdtGrid<D>& grid, std::span<const Pt> transformed) {
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

/// Termination and message of a run that was neither diverged nor without
/// cells nor degenerate.
template <class M>
std::pair<RegistrationTermination, std::string> ndt_outcome(const NdtRun<M>& run,
                                                            const NdtOptions& o,
                                                            double probability) {
  constexpr double kDeg = 180.0 / 3.14159265358979323846;
  const std::string newton =
      std::isnan(run.newton_translation)
          ? std::string("the score has no maximum there (its Hessian is not negative definite)")
          : fmt::format("the Newton step there is {:.3g} m, {:.3g}° (tolerances {:g} m, {:g}°)",
                        run.newton_translation, run.newton_rotation * kDeg, o.translation_tolerance,
                        o.rotation_tolerance * kDeg);
  if (run.stalled)
    return {RegistrationTermination::Stalled,
            fmt::format("no step along the Newton direction raised the score after {} "
                        "iteration(s); the estimate is the last one that did{}; {}",
                        run.iterations, run.iterations == 0 ? " (the initial guess)" : "", newton)};
  if (run.converged && o.convergence == NdtConvergence::Pcl)
    return {RegistrationTermination::Converged,
            fmt::format("PCL's rule met in {} iteration(s) (a step's translation² <= {:g} m²; not "
                        "a test of the optimum), probability {:.4g}",
                        run.iterations, o.transformation_epsilon, probability)};
  if (run.converged)
    return {RegistrationTermination::Converged,
            fmt::format("converged in {} iteration(s): {}, probability {:.4g}", run.iterations,
                        newton, probability)};
  return {RegistrationTermination::MaxIterations,
          o.convergence == NdtConvergence::Pcl
              ? fmt::format("{} iterations without a step below the epsilons", run.iterations)
              : fmt::format("stopped at the iteration cap ({}); {}", run.iterations, newton)};
}

}  // namespace

Ndt3dResult ndt_3d(const NdtGrid3D& target, std::span<const Eigen::Vector3f> source,
                   const Eigen::Isometry3d& initial, const NdtOptions& o) {
  o.check();
  ROVE_CHECK_FINITE(initial.matrix());
  ROVE_CHECK_MSG((initial.linear().transpose() * initial.linear() - Eigen::Matrix3d::Identity())
                         .cwiseAbs()
                         .maxCoeff() < 1e-6,
                 "the initial transform is not rigid");
  Ndt3dResult res;
  res.matrix = initial.matrix();
  res.T_target_source = Pose3Gaussian(Pose3(initial.linear(), initial.translation(), 1e-6));
  res.conditioning = std::numeric_limits<double>::quiet_NaN();
  const std::size_t finite = std::count_if(source.begin(), source.end(),
                                           [](const auto& p) { return p.allFinite(); });
  if (target.empty() || finite == 0) {
    res.message = target.empty() ? "the target has no NDT cell (too few points per cell?)"
                                 : "the source has no finite point";
    return res;
  }
  const Gauss gc = gauss_constants(o.outlier_ratio, target.options().resolution, 3);
  auto tsq = [](const Model3::Params& s) { return s.head<3>().squaredNorm(); };
  auto cosang = [](const Model3::Params& s) { return 0.5 * (Model3(s).R.trace() - 1); };
  const auto run = run_ndt<Model3>(target, source, Model3::from_isometry(initial), o, gc, tsq, cosang);
  const Model3 m(run.p);
  res.iterations = run.iterations;
  res.matrix = m.isometry().matrix();
  res.transformation_probability = run.last.score / static_cast<double>(source.size());
  res.goodness = static_cast<double>(run.last.with_cell) / static_cast<double>(finite);
  res.fitness = run.last.with_cell ? run.last.nearest_sq / static_cast<double>(run.last.with_cell) : 0.0;
  res.final_cost = -run.last.score;
  res.correspondences = run.last.with_cell;
  const Pose3 mean(m.R, m.t, 1e-6);
  if (run.diverged) {
    res.T_target_source = Pose3Gaussian(mean);
    res.termination = RegistrationTermination::Diverged;
    res.message = fmt::format("the Newton step became non-finite at iteration {}", run.iterations);
    return res;
  }
  if (run.last.with_cell == 0) {
    res.T_target_source = Pose3Gaussian(mean);
    res.termination = RegistrationTermination::TooFewCorrespondences;
    res.message = "no source point lies within one resolution of a target cell";
    return res;
  }
  // Covariance: (−H)⁻¹ over PCL's (t, roll, pitch, yaw), mapped to rove's
  // (t, yaw, pitch, roll) through the left rotation rates of both.
  const Eigen::Matrix<double, 6, 6> info = -run.last.H;
  res.information = info;
  const Eigen::Matrix<double, 6, 6> C_pcl = covariance_from_information<6>(info, 1.0, 1e-12);
  Eigen::Matrix3d E_pcl;  // ω = E_pcl · (roll, pitch, yaw)˙ for R = Rx·Ry·Rz
  {
    const Eigen::Matrix3d Rx = Eigen::AngleAxisd(run.p(3), Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Matrix3d Ry = Eigen::AngleAxisd(run.p(4), Eigen::Vector3d::UnitY()).toRotationMatrix();
    E_pcl.col(0) = Eigen::Vector3d::UnitX();
    E_pcl.col(1) = Rx * Eigen::Vector3d::UnitY();
    E_pcl.col(2) = Rx * Ry * Eigen::Vector3d::UnitZ();
  }
  Eigen::Matrix<double, 6, 6> J = ypr_jacobian_wrt_left_tangent(mean);
  J.bottomRightCorner<3, 3>() = J.bottomRightCorner<3, 3>() * E_pcl;
  Eigen::Matrix<double, 6, 6> C = J * C_pcl * J.transpose();
  C = 0.5 * (C + C.transpose());
  res.T_target_source = Pose3Gaussian(detail::kUnchecked, mean, C);

  bool degenerate = false;
  if (o.degeneracy_threshold > 0) {
    std::vector<Eigen::Vector3d> moved;
    moved.reserve(source.size());
    for (const auto& s : source) moved.push_back(m.R * s.cast<double>() + m.t);
    res.conditioning = conditioning_of<3, Eigen::Vector3d>(target, moved);
    degenerate = res.conditioning < o.degeneracy_threshold;
  }
  if (degenerate) {
    res.termination = RegistrationTermination::Degenerate;
    res.message = fmt::format(
        "the matched cells leave a direction unconstrained (conditioning {:.3g} < {:.3g})",
        res.conditioning, o.degeneracy_threshold);
  } else {
    std::tie(res.termination, res.message) = ndt_outcome(run, o, res.transformation_probability);
  }
  return res;
}

Ndt2dResult ndt_2d(const NdtGrid2D& target, std::span<const Eigen::Vector2f> source,
                   const Pose2& initial, const NdtOptions& o) {
  o.check();
  Ndt2dResult res;
  res.T_target_source = Pose2Gaussian(initial);
  res.conditioning = std::numeric_limits<double>::quiet_NaN();
  const std::size_t finite = std::count_if(source.begin(), source.end(),
                                           [](const auto& p) { return p.allFinite(); });
  if (target.empty() || finite == 0) {
    res.message = target.empty() ? "the target has no NDT cell (too few points per cell?)"
                                 : "the source has no finite point";
    return res;
  }
  const Gauss gc = gauss_constants(o.outlier_ratio, target.options().resolution, 2);
  auto tsq = [](const Model2::Params& s) { return s.head<2>().squaredNorm(); };
  auto cosang = [](const Model2::Params& s) { return std::cos(s(2)); };
  const auto run = run_ndt<Model2>(target, source, initial.to_vector(), o, gc, tsq, cosang);
  res.iterations = run.iterations;
  res.transformation_probability = run.last.score / static_cast<double>(source.size());
  res.goodness = static_cast<double>(run.last.with_cell) / static_cast<double>(finite);
  res.fitness = run.last.with_cell ? run.last.nearest_sq / static_cast<double>(run.last.with_cell) : 0.0;
  res.final_cost = -run.last.score;
  res.correspondences = run.last.with_cell;
  const Pose2 mean(run.p(0), run.p(1), wrap_to_pi(run.p(2)));
  if (run.diverged || !run.p.allFinite()) {
    res.termination = RegistrationTermination::Diverged;
    res.message = fmt::format("the Newton step became non-finite at iteration {}", run.iterations);
    return res;
  }
  if (run.last.with_cell == 0) {
    res.T_target_source = Pose2Gaussian(mean);
    res.termination = RegistrationTermination::TooFewCorrespondences;
    res.message = "no source point lies within one resolution of a target cell";
    return res;
  }
  res.information = -run.last.H;
  const Eigen::Matrix3d C = covariance_from_information<3>(res.information, 1.0, 1e-12);
  res.T_target_source = Pose2Gaussian(detail::kUnchecked, mean, C);
  bool degenerate = false;
  if (o.degeneracy_threshold > 0) {
    const Model2 m(run.p);
    std::vector<Eigen::Vector2d> moved;
    for (const auto& s : source) moved.push_back(m.R * s.cast<double>() + m.t);
    res.conditioning = conditioning_of<2, Eigen::Vector2d>(target, moved);
    degenerate = res.conditioning < o.degeneracy_threshold;
  }
  if (degenerate) {
    res.termination = RegistrationTermination::Degenerate;
    res.message = fmt::format(
        "the matched cells leave a direction unconstrained (conditioning {:.3g} < {:.3g})",
        res.conditioning, o.degeneracy_threshold);
  } else {
    std::tie(res.termination, res.message) = ndt_outcome(run, o, res.transformation_probability);
  }
  return res;
}

}  // namespace rove
