// The target of NDT: Gaussian cells of the points (PCL's
// VoxelGridCovariance) and the index that finds the cells near a point.

#include "rove/registration/ndt.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Eigenvalues>

#include "rove/core/check.h"

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

}  // namespace rove
