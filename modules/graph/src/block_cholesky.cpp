// Left-looking block sparse Cholesky (Davis, "Direct Methods for Sparse
// Linear Systems", SIAM 2006: elimination tree and row subtrees §4.1–4.4,
// left-looking column Cholesky §4.8), with D×D blocks in place of scalars.
#include "block_cholesky.h"

#include <algorithm>
#include <cmath>

#include "rove/core/check.h"

namespace rove::detail {

namespace {

// L⁻¹ of the Cholesky factor L of the symmetric D×D block `a` (lower
// triangle read), by column Cholesky then forward substitution on the
// identity. False when `a` is not positive definite or not finite (a NaN
// pivot fails the `> 0` test too).
template <int D>
bool invert_cholesky_factor(const Eigen::Matrix<double, D, D>& a,
                            Eigen::Matrix<double, D, D>& inv) {
  Eigen::Matrix<double, D, D> l = Eigen::Matrix<double, D, D>::Zero();
  for (int c = 0; c < D; ++c) {
    double d = a(c, c);
    for (int k = 0; k < c; ++k) d -= l(c, k) * l(c, k);
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    const double lcc = std::sqrt(d);
    l(c, c) = lcc;
    for (int r = c + 1; r < D; ++r) {
      double x = a(r, c);
      for (int k = 0; k < c; ++k) x -= l(r, k) * l(c, k);
      l(r, c) = x / lcc;
    }
  }
  inv.setZero();
  for (int c = 0; c < D; ++c) {
    inv(c, c) = 1.0 / l(c, c);
    for (int r = c + 1; r < D; ++r) {
      double x = 0.0;
      for (int k = c; k < r; ++k) x -= l(r, k) * inv(k, c);
      inv(r, c) = x / l(r, r);
    }
  }
  return inv.allFinite();
}

}  // namespace

template <int D>
void BlockCholesky<D>::analyze(const Matrix& upper) {
  ROVE_CHECK_EQ(upper.rows(), upper.cols());
  ROVE_CHECK_EQ(upper.rows() % D, 0);
  ROVE_CHECK_MSG(upper.isCompressed(), "the matrix must be compressed");
  n_ = static_cast<int>(upper.cols() / D);
  const auto n = static_cast<std::size_t>(n_);
  const int* outer = upper.outerIndexPtr();
  const int* inner = upper.innerIndexPtr();

  // Block pattern of the strict upper triangle, per block column.
  std::vector<std::vector<int>> above(n);
  for (int c = 0; c < n_; ++c) {
    auto& rows = above[static_cast<std::size_t>(c)];
    for (int k = c * D; k < (c + 1) * D; ++k) {
      for (int e = outer[k]; e < outer[k + 1]; ++e) {
        const int r = inner[e] / D;
        ROVE_CHECK_MSG(inner[e] <= k, "entry ({}, {}) is below the diagonal", inner[e], k);
        if (r < c) rows.push_back(r);
      }
    }
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  }

  // Elimination tree (with path compression through `ancestor`).
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n_; ++k) {
    for (int i : above[static_cast<std::size_t>(k)]) {
      while (i != -1 && i < k) {
        const int up = ancestor[static_cast<std::size_t>(i)];
        ancestor[static_cast<std::size_t>(i)] = k;
        if (up == -1) parent[static_cast<std::size_t>(i)] = k;
        i = up;
      }
    }
  }
  // Row k of L is the row subtree of k: walk up from every A(i, k), i < k,
  // to a node already marked for k. Counted first, then filled; rows come
  // in ascending k, so every column's rows end up sorted.
  std::vector<int> mark(n, -1);
  auto for_each_in_row = [&](int k, auto&& f) {
    mark[static_cast<std::size_t>(k)] = k;
    for (int i : above[static_cast<std::size_t>(k)]) {
      for (int j = i; mark[static_cast<std::size_t>(j)] != k;
           j = parent[static_cast<std::size_t>(j)]) {
        mark[static_cast<std::size_t>(j)] = k;
        f(j);
      }
    }
  };
  colptr_.assign(n + 1, 0);
  for (int k = 0; k < n_; ++k) for_each_in_row(k, [&](int j) { ++colptr_[static_cast<std::size_t>(j) + 1]; });
  for (std::size_t j = 0; j < n; ++j) colptr_[j + 1] += colptr_[j] + 1;  // + the diagonal block
  rowind_.assign(static_cast<std::size_t>(colptr_[n]), 0);
  std::vector<int> fill(colptr_.begin(), colptr_.end() - 1);
  for (int k = 0; k < n_; ++k) rowind_[static_cast<std::size_t>(fill[static_cast<std::size_t>(k)]++)] = k;
  std::fill(mark.begin(), mark.end(), -1);
  for (int k = 0; k < n_; ++k) {
    for_each_in_row(k, [&](int j) { rowind_[static_cast<std::size_t>(fill[static_cast<std::size_t>(j)]++)] = k; });
  }
  values_.assign(rowind_.size() * D * D, 0.0);

  // Where each entry of A goes in L: A(r, c), r <= c, is L(c, r).
  const auto nnz = static_cast<std::size_t>(upper.nonZeros());
  scatter_.assign(nnz, -1);
  scatter_mirror_.assign(nnz, -1);
  for (int c = 0; c < static_cast<int>(upper.cols()); ++c) {
    for (int e = outer[c]; e < outer[c + 1]; ++e) {
      const int r = inner[e];
      const int br = r / D, bc = c / D;
      const auto first = rowind_.begin() + colptr_[static_cast<std::size_t>(br)];
      const auto last = rowind_.begin() + colptr_[static_cast<std::size_t>(br) + 1];
      const auto at = std::lower_bound(first, last, bc);
      const auto block = static_cast<int>(at - rowind_.begin());
      const auto base = block * D * D;
      scatter_[static_cast<std::size_t>(e)] = base + (r % D) * D + (c % D);
      if (br == bc && r != c) scatter_mirror_[static_cast<std::size_t>(e)] = base + (c % D) * D + (r % D);
    }
  }
  // Blocks that the scatter does not overwrite entry by entry: the fill-in,
  // and any block of A stored only in part. Only these are zeroed before a
  // factorization.
  std::vector<int> covered(rowind_.size(), 0);
  for (std::size_t e = 0; e < nnz; ++e) {
    ++covered[static_cast<std::size_t>(scatter_[e] / (D * D))];
    if (scatter_mirror_[e] >= 0) ++covered[static_cast<std::size_t>(scatter_mirror_[e] / (D * D))];
  }
  fill_blocks_.clear();
  for (std::size_t q = 0; q < covered.size(); ++q)
    if (covered[q] != D * D) fill_blocks_.push_back(static_cast<int>(q));
  head_.assign(n, -1);
  chain_.assign(n, -1);
  cursor_.assign(n, 0);
  position_.assign(n, 0);
}

template <int D>
std::optional<long> BlockCholesky<D>::factorize(const Matrix& upper) {
  ROVE_CHECK_EQ(static_cast<std::size_t>(upper.nonZeros()), scatter_.size());
  for (int q : fill_blocks_) std::fill_n(values_.begin() + static_cast<std::ptrdiff_t>(q) * D * D, D * D, 0.0);
  const double* a = upper.valuePtr();
  for (std::size_t e = 0; e < scatter_.size(); ++e) {
    values_[static_cast<std::size_t>(scatter_[e])] = a[e];
    if (scatter_mirror_[e] >= 0) values_[static_cast<std::size_t>(scatter_mirror_[e])] = a[e];
  }
  std::fill(head_.begin(), head_.end(), -1);
  double* v = values_.data();
  auto block = [v](int q) { return Map(v + static_cast<std::ptrdiff_t>(q) * D * D); };
  for (int j = 0; j < n_; ++j) {
    const int begin = colptr_[static_cast<std::size_t>(j)];
    const int end = colptr_[static_cast<std::size_t>(j) + 1];
    for (int q = begin; q < end; ++q) position_[static_cast<std::size_t>(rowind_[static_cast<std::size_t>(q)])] = q;
    // L(j:, j) −= L(j:, k) L(j, k)ᵀ for every earlier column k with L(j, k) ≠ 0.
    for (int k = head_[static_cast<std::size_t>(j)]; k != -1;) {
      const int k_next = chain_[static_cast<std::size_t>(k)];
      const int p = cursor_[static_cast<std::size_t>(k)];
      const int k_end = colptr_[static_cast<std::size_t>(k) + 1];
      const Block Ljk_t = block(p).transpose();
      for (int q = p; q < k_end; ++q) {
        const int target = position_[static_cast<std::size_t>(rowind_[static_cast<std::size_t>(q)])];
        block(target).noalias() -= block(q) * Ljk_t;
      }
      if (p + 1 < k_end) {
        const int r = rowind_[static_cast<std::size_t>(p) + 1];
        cursor_[static_cast<std::size_t>(k)] = p + 1;
        chain_[static_cast<std::size_t>(k)] = head_[static_cast<std::size_t>(r)];
        head_[static_cast<std::size_t>(r)] = k;
      }
      k = k_next;
    }
    // Diagonal block: L_jj L_jjᵀ = A_jj; kept as L_jj⁻¹ (what the column
    // below and the solves need).
    Map Ljj = block(begin);
    Block inv;
    if (!invert_cholesky_factor<D>(Block(Ljj), inv)) return static_cast<long>(j) * D;
    Ljj = inv;
    const Block inv_t = inv.transpose();
    for (int q = begin + 1; q < end; ++q) block(q) = block(q) * inv_t;
    if (begin + 1 < end) {
      const int r = rowind_[static_cast<std::size_t>(begin) + 1];
      cursor_[static_cast<std::size_t>(j)] = begin + 1;
      chain_[static_cast<std::size_t>(j)] = head_[static_cast<std::size_t>(r)];
      head_[static_cast<std::size_t>(r)] = j;
    }
  }
  return std::nullopt;
}

template <int D>
void BlockCholesky<D>::solve(const Vector& b, Vector& x) const {
  ROVE_CHECK_EQ(b.size(), static_cast<Eigen::Index>(n_) * D);
  x = b;
  using Seg = Eigen::Matrix<double, D, 1>;
  const double* v = values_.data();
  auto block = [v](int q) { return ConstMap(v + static_cast<std::ptrdiff_t>(q) * D * D); };
  // L y = b.
  for (int j = 0; j < n_; ++j) {
    const int begin = colptr_[static_cast<std::size_t>(j)];
    const int end = colptr_[static_cast<std::size_t>(j) + 1];
    const Seg y = block(begin) * x.template segment<D>(static_cast<Eigen::Index>(j) * D);
    x.template segment<D>(static_cast<Eigen::Index>(j) * D) = y;
    for (int q = begin + 1; q < end; ++q) {
      x.template segment<D>(static_cast<Eigen::Index>(rowind_[static_cast<std::size_t>(q)]) * D)
          .noalias() -= block(q) * y;
    }
  }
  // Lᵀ x = y.
  for (int j = n_ - 1; j >= 0; --j) {
    const int begin = colptr_[static_cast<std::size_t>(j)];
    const int end = colptr_[static_cast<std::size_t>(j) + 1];
    Seg t = x.template segment<D>(static_cast<Eigen::Index>(j) * D);
    for (int q = begin + 1; q < end; ++q) {
      t.noalias() -= block(q).transpose() *
                     x.template segment<D>(static_cast<Eigen::Index>(rowind_[static_cast<std::size_t>(q)]) * D);
    }
    x.template segment<D>(static_cast<Eigen::Index>(j) * D).noalias() = block(begin).transpose() * t;
  }
}

template class BlockCholesky<3>;
template class BlockCholesky<6>;

}  // namespace rove::detail
