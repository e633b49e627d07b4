#pragma once
// Sparse Cholesky of a symmetric positive definite matrix stored as its upper
// triangle (compressed columns, already in the elimination order): rove's
// block Cholesky (block_cholesky.h), Eigen's SimplicialLLT or SuiteSparse
// CHOLMOD. The pattern is analyzed once; the
// values are factorized again at every iteration.
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/SparseCore>

#include "rove/graph/optimizer.h"

namespace rove::detail {

/// Fill-reducing order of a symmetric pattern (n×n, both triangles or one):
/// perm[new] = old. With CHOLMOD: the best of AMD and METIS nested dissection
/// (fewest nonzeros in the factor); without: Eigen's AMD.
std::vector<int> fill_reducing_order(const Eigen::SparseMatrix<int, Eigen::ColMajor, int>& pattern,
                                     bool use_cholmod);

/// Size of the Cholesky factor of a block matrix with the symmetric block
/// `pattern` (n×n, both triangles) eliminated in the order `perm`
/// (perm[new] = old), each block `block_size`×`block_size` and dense.
struct CholeskyCost {
  double factor_nonzeros = 0.0;  ///< scalar entries of L
  double flops = 0.0;            ///< Σ (column length)², CHOLMOD's measure
};
CholeskyCost block_cholesky_cost(const Eigen::SparseMatrix<int, Eigen::ColMajor, int>& pattern,
                                 const std::vector<int>& perm, int block_size);

/// True when rove was compiled with CHOLMOD (does not load it).
constexpr bool cholmod_compiled() noexcept {
#ifdef ROVE_HAVE_CHOLMOD
  return true;
#else
  return false;
#endif
}
/// True when CHOLMOD can be used: compiled with it, and its library loads
/// (this loads it; it is loaded on first use, not at process start).
bool cholmod_built() noexcept;

class SparseCholesky {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  /// Chooses the back-end (Auto → CHOLMOD when it loads, else Block).
  /// `block_size` is the side of the dense blocks (3 or 6; Block needs it).
  /// CHOLMOD's own OpenMP threads are set once per process by the opt-in
  /// tune_blas_threads() (rove/graph/blas_tuning.h), never here.
  SparseCholesky(LinearSolverType type, int block_size);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Back-end in use.
  LinearSolverType type() const { return type_; }
  /// Symbolic analysis of the upper triangle `upper` (natural order).
  void analyze(const Matrix& upper);
  /// Numeric factorization. Returns std::nullopt on success, else the column
  /// where it broke down when the back-end knows it (-1 when it does not).
  std::optional<long> factorize(const Matrix& upper);
  /// Solves A x = b with the last successful factorization.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// Stored entries of the factor (after factorize()).
  std::size_t factor_nonzeros() const;

 private:
  struct Impl;
  LinearSolverType type_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rove::detail
