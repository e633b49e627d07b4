#pragma once
// Internal: a symmetric positive-definite system stored as its lower band
// (the normal equations of the timed elastic band, whose variables couple
// only within a few neighbouring poses), factored in place by Cholesky in
// O(n·b²) (Golub & Van Loan, "Matrix Computations", 4th ed., Alg. 4.3.5).

#include <algorithm>
#include <cmath>
#include <vector>

namespace rove::detail {

class BandedSystem {
 public:
  BandedSystem(int n, int band) : n_(n), b_(band), a_(static_cast<std::size_t>(n) * (band + 1), 0.0) {}

  int size() const { return n_; }
  int band() const { return b_; }
  // Entry (i, j) of the lower triangle, j ≤ i ≤ j + band.
  double& at(int i, int j) { return a_[static_cast<std::size_t>(i) * (b_ + 1) + (i - j)]; }
  double at(int i, int j) const { return a_[static_cast<std::size_t>(i) * (b_ + 1) + (i - j)]; }
  void clear() { std::fill(a_.begin(), a_.end(), 0.0); }

  // A ← L (A = L·Lᵀ). False (A left partly factored) if A is not positive
  // definite enough to factor.
  bool factor() {
    for (int j = 0; j < n_; ++j) {
      double d = at(j, j);
      for (int k = std::max(0, j - b_); k < j; ++k) d -= at(j, k) * at(j, k);
      if (!(d > 1e-300) || !std::isfinite(d)) return false;
      const double l = std::sqrt(d);
      at(j, j) = l;
      for (int i = j + 1; i <= std::min(n_ - 1, j + b_); ++i) {
        double s = at(i, j);
        for (int k = std::max(0, i - b_); k < j; ++k) s -= at(i, k) * at(j, k);
        at(i, j) = s / l;
      }
    }
    return true;
  }

  // Solves L·Lᵀ·x = rhs in place, after factor().
  void solve(std::vector<double>& x) const {
    for (int i = 0; i < n_; ++i) {
      double s = x[static_cast<std::size_t>(i)];
      for (int k = std::max(0, i - b_); k < i; ++k) s -= at(i, k) * x[static_cast<std::size_t>(k)];
      x[static_cast<std::size_t>(i)] = s / at(i, i);
    }
    for (int i = n_ - 1; i >= 0; --i) {
      double s = x[static_cast<std::size_t>(i)];
      for (int k = i + 1; k <= std::min(n_ - 1, i + b_); ++k) s -= at(k, i) * x[static_cast<std::size_t>(k)];
      x[static_cast<std::size_t>(i)] = s / at(i, i);
    }
  }

 private:
  int n_, b_;
  std::vector<double> a_;
};

}  // namespace rove::detail
