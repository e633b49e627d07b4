// The block Cholesky against a dense LLᵀ of the same matrix (oracle), and
// its failure report on matrices that are not positive definite.
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "../src/block_cholesky.h"

namespace rove::detail {
namespace {

using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// Random SPD block matrix with n D×D blocks: a random block pattern (a chain
// plus `extra` random pairs), A = Σ over pairs of JᵀJ-like terms + μI.
template <int D>
Eigen::MatrixXd random_block_spd(std::mt19937_64& rng, int n, int extra) {
  std::normal_distribution<double> normal;
  std::uniform_int_distribution<int> pick(0, n - 1);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n * D, n * D);
  auto couple = [&](int i, int j) {
    Eigen::MatrixXd J(D, 2 * D);
    for (int r = 0; r < D; ++r)
      for (int c = 0; c < 2 * D; ++c) J(r, c) = normal(rng);
    const Eigen::MatrixXd H = J.transpose() * J;
    const int at[2] = {i, j};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) A.block(at[a] * D, at[b] * D, D, D) += H.block(a * D, b * D, D, D);
  };
  for (int k = 1; k < n; ++k) couple(k - 1, k);
  for (int e = 0; e < extra; ++e) {
    const int i = pick(rng), j = pick(rng);
    if (i != j) couple(i, j);
  }
  A += 0.1 * Eigen::MatrixXd::Identity(n * D, n * D);
  return A;
}

// Upper triangle in rove's block layout: whole off-diagonal blocks, the
// upper triangle of diagonal blocks, explicit zeros kept.
template <int D>
Sparse block_upper(const Eigen::MatrixXd& A) {
  const int n = static_cast<int>(A.cols()) / D;
  std::vector<Eigen::Triplet<double>> t;
  for (int bc = 0; bc < n; ++bc)
    for (int br = 0; br <= bc; ++br) {
      if (br < bc && A.block(br * D, bc * D, D, D).isZero(0.0)) continue;
      for (int c = 0; c < D; ++c)
        for (int r = 0; r < D; ++r) {
          if (br == bc && r > c) continue;
          t.emplace_back(br * D + r, bc * D + c, A(br * D + r, bc * D + c));
        }
    }
  Sparse S(A.rows(), A.cols());
  S.setFromTriplets(t.begin(), t.end());
  S.makeCompressed();
  return S;
}

template <int D>
void check_against_dense(int n, int extra, unsigned seed) {
  std::mt19937_64 rng(seed);
  const Eigen::MatrixXd A = random_block_spd<D>(rng, n, extra);
  const Sparse upper = block_upper<D>(A);
  BlockCholesky<D> chol;
  chol.analyze(upper);
  ASSERT_FALSE(chol.factorize(upper).has_value());
  Eigen::VectorXd b(A.rows());
  std::normal_distribution<double> normal;
  for (Eigen::Index k = 0; k < b.size(); ++k) b[k] = normal(rng);
  Eigen::VectorXd x;
  chol.solve(b, x);
  const Eigen::VectorXd expected = A.llt().solve(b);
  EXPECT_LT((x - expected).norm(), 1e-9 * expected.norm()) << "D " << D << " n " << n;
  EXPECT_LT((A * x - b).norm(), 1e-9 * b.norm());
  // Same pattern, new values: the analysis is reused.
  const Eigen::MatrixXd A2 = A + Eigen::MatrixXd::Identity(A.rows(), A.cols());
  const Sparse upper2 = block_upper<D>(A2);
  ASSERT_EQ(upper2.nonZeros(), upper.nonZeros());
  ASSERT_FALSE(chol.factorize(upper2).has_value());
  chol.solve(b, x);
  EXPECT_LT((A2 * x - b).norm(), 1e-9 * b.norm());
}

TEST(BlockCholesky, SolvesLikeDenseCholesky3x3) {
  check_against_dense<3>(1, 0, 1);
  check_against_dense<3>(2, 0, 2);
  check_against_dense<3>(40, 30, 3);
  check_against_dense<3>(120, 200, 4);
}

TEST(BlockCholesky, SolvesLikeDenseCholesky6x6) {
  check_against_dense<6>(1, 0, 5);
  check_against_dense<6>(30, 25, 6);
  check_against_dense<6>(80, 120, 7);
}

TEST(BlockCholesky, ReportsTheBlockWhereItIsNotPositiveDefinite) {
  std::mt19937_64 rng(8);
  Eigen::MatrixXd A = random_block_spd<3>(rng, 10, 5);
  // Make block 4 indefinite: a large negative entry on its diagonal.
  A(4 * 3 + 1, 4 * 3 + 1) = -1e6;
  const Sparse upper = block_upper<3>(A);
  BlockCholesky<3> chol;
  chol.analyze(upper);
  const auto failed = chol.factorize(upper);
  ASSERT_TRUE(failed.has_value());
  EXPECT_EQ(*failed, 12);
}

TEST(BlockCholesky, ReportsNonFiniteValues) {
  std::mt19937_64 rng(9);
  Eigen::MatrixXd A = random_block_spd<6>(rng, 5, 3);
  A(2 * 6, 2 * 6) = std::numeric_limits<double>::quiet_NaN();
  const Sparse upper = block_upper<6>(A);
  BlockCholesky<6> chol;
  chol.analyze(upper);
  const auto failed = chol.factorize(upper);
  ASSERT_TRUE(failed.has_value());
  EXPECT_EQ(*failed, 12);
}

}  // namespace
}  // namespace rove::detail
