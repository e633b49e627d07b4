#pragma once
// Sparse Cholesky A = L Lᵀ of a symmetric positive definite block matrix
// whose blocks are dense D×D (one per pose of a pose graph), already in the
// elimination order. Left-looking, one block column at a time, every
// operation a fixed-size D×D product: the scalar simplicial factorization
// spends most of its time on index arithmetic per scalar entry, this one
// per block (D² entries). The pattern is analyzed once; the values are
// factorized again at every iteration. Serial and deterministic.
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace rove::detail {

template <int D>
class BlockCholesky {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  using Vector = Eigen::VectorXd;

  /// Symbolic analysis of the scalar upper triangle `upper` (N×N, N a
  /// multiple of D; block (r, c) stored whole for r < c, its upper triangle
  /// for r = c). Precondition: N % D == 0.
  void analyze(const Matrix& upper);
  /// Numeric factorization of `upper` (same pattern as analyze()). Returns
  /// std::nullopt on success, else the first scalar column of the block
  /// column where A was found not positive definite (or not finite).
  std::optional<long> factorize(const Matrix& upper);
  /// Solves A x = b with the last successful factorization (x may alias b).
  void solve(const Vector& b, Vector& x) const;
  /// Scalar entries of L stored (whole D×D blocks, diagonal ones included).
  std::size_t factor_nonzeros() const { return values_.size(); }

 private:
  using Block = Eigen::Matrix<double, D, D>;
  using Map = Eigen::Map<Block>;
  using ConstMap = Eigen::Map<const Block>;

  int n_ = 0;                    // block columns
  std::vector<int> colptr_;      // per block column: first block (the diagonal one)
  std::vector<int> rowind_;      // per block: block row (ascending within a column)
  std::vector<double> values_;   // per block: D×D column-major; diagonal blocks hold L_jj⁻¹
  std::vector<int> scatter_;     // per entry of `upper`: its index in values_ (of Lᵀ's side)
  std::vector<int> scatter_mirror_;  // same for the mirrored entry of a diagonal block, or -1
  std::vector<int> fill_blocks_;     // blocks of L that A's entries do not cover whole (zeroed)
  // Factorization workspace, per block column: first of the columns waiting
  // to update it, the next in that list, the next block of a column still to
  // be applied, and the block of the current column holding a given row.
  std::vector<int> head_, chain_, cursor_, position_;
};

extern template class BlockCholesky<3>;
extern template class BlockCholesky<6>;

}  // namespace rove::detail
