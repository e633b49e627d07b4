#include "rove/slam/data_association.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <random>

#include "rove/bayes/distributions.h"
#include "rove/core/error.h"

namespace rove {
namespace {

// A random joint covariance: a shared component (the robot's uncertainty,
// correlating every prediction) plus independent blocks.
Eigen::MatrixXd random_covariance(std::mt19937_64& rng, Eigen::Index n, Eigen::Index m) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd A(n * m, m + 2);
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    for (Eigen::Index c = 0; c < A.cols(); ++c) A(r, c) = 0.3 * g(rng);
  }
  Eigen::MatrixXd S = A * A.transpose();
  for (Eigen::Index i = 0; i < n * m; ++i) S(i, i) += 0.05;
  return S;
}

// Brute force: every hypothesis (each observation paired with a distinct
// individually compatible prediction, or none) whose partial hypotheses
// over the observations in order are all jointly compatible; the most
// pairings, ties to the smaller joint D².
DataAssociationResult brute_force(const Eigen::MatrixXd& z, const Eigen::MatrixXd& y,
                                  const Eigen::MatrixXd& S, const DataAssociationOptions& o) {
  const DataAssociationResult ic = associate(z, y, S, {}, [&] {
    DataAssociationOptions nn = o;
    nn.method = DataAssociationMethod::NearestNeighbor;
    return nn;
  }());
  const Eigen::Index k = z.rows(), n = y.rows(), m = z.cols();
  DataAssociationResult best;
  best.pairing.assign(static_cast<std::size_t>(k), -1);
  std::size_t best_count = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  std::vector<int> h(static_cast<std::size_t>(k), -1);
  std::function<void(Eigen::Index)> rec = [&](Eigen::Index j) {
    // The partial hypothesis over observations < j must be jointly compatible.
    std::size_t count = 0;
    for (Eigen::Index a = 0; a < j; ++a) count += h[static_cast<std::size_t>(a)] >= 0 ? 1 : 0;
    double d2 = 0.0;
    if (count > 0) {
      if (!joint_distance(z, y, S, {}, h, &d2, nullptr)) return;
      if (!(d2 < chi_square_quantile(o.chi2_probability, static_cast<double>(count * m)))) return;
    }
    if (j == k) {
      if (count > best_count || (count == best_count && count > 0 && d2 < best_d2)) {
        best_count = count, best_d2 = d2, best.pairing = h;
      }
      return;
    }
    for (Eigen::Index i = -1; i < n; ++i) {
      if (i >= 0) {
        if (!ic.compatible(i, j)) continue;
        if (std::find(h.begin(), h.begin() + j, static_cast<int>(i)) != h.begin() + j) continue;
      }
      h[static_cast<std::size_t>(j)] = static_cast<int>(i);
      rec(j + 1);
      h[static_cast<std::size_t>(j)] = -1;
    }
  };
  rec(0);
  best.joint_mahalanobis2 = best_count ? best_d2 : 0.0;
  return best;
}

TEST(DataAssociation, JcbbEqualsBruteForceOnSmallSets) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> g(0.0, 1.0);
  int with_pairs = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Index m = 2, n = 2 + trial % 4, k = 1 + trial % 5;
    const Eigen::MatrixXd S = random_covariance(rng, n, m);
    Eigen::MatrixXd y(n, m), z(k, m);
    for (Eigen::Index i = 0; i < n; ++i) y.row(i) = Eigen::RowVector2d(2.0 * g(rng), 2.0 * g(rng));
    for (Eigen::Index j = 0; j < k; ++j) {
      // Most observations near a prediction, some far from every one.
      const Eigen::Index i = static_cast<Eigen::Index>(rng() % static_cast<std::uint64_t>(n));
      z.row(j) = y.row(i) + 0.4 * Eigen::RowVector2d(g(rng), g(rng));
      if (rng() % 5 == 0) z.row(j) += Eigen::RowVector2d(20.0, 0.0);
    }
    DataAssociationOptions o;
    o.method = DataAssociationMethod::Jcbb;
    const DataAssociationResult r = associate(z, y, S, {}, o);
    const DataAssociationResult b = brute_force(z, y, S, o);
    ASSERT_EQ(r.termination, DataAssociationTermination::Completed);
    ASSERT_EQ(r.paired(), b.paired()) << "trial " << trial;
    EXPECT_NEAR(r.joint_mahalanobis2, b.joint_mahalanobis2, 1e-9) << "trial " << trial;
    EXPECT_EQ(r.pairing, b.pairing) << "trial " << trial;
    with_pairs += r.paired() > 1 ? 1 : 0;
  }
  EXPECT_GT(with_pairs, 50);
}

// Two observations each close enough to their own prediction, but displaced
// in opposite directions while the predictions move together (a robot-pose
// error shifts every landmark alike): individually compatible, jointly not.
// NN pairs both; JCBB keeps only one.
TEST(DataAssociation, JcbbRejectsJointlyIncompatiblePairs) {
  Eigen::MatrixXd y(2, 1), z(2, 1), S(2, 2);
  y << 0.0, 10.0;
  z << 2.0, 8.0;          // innovations +2 and −2
  S << 1.0, 0.99, 0.99, 1.0;  // nearly perfectly correlated
  DataAssociationOptions o;
  const DataAssociationResult nn = associate(z, y, S, {}, o);
  EXPECT_EQ(nn.paired(), 2u);
  o.method = DataAssociationMethod::Jcbb;
  const DataAssociationResult jc = associate(z, y, S, {}, o);
  EXPECT_EQ(jc.paired(), 1u);
}

TEST(DataAssociation, NearestNeighborIsGreedyByBestDistance) {
  // Both observations prefer prediction 0; observation 1 is closer, so it
  // takes it and observation 0 falls back to prediction 1.
  Eigen::MatrixXd y(2, 1), z(2, 1);
  y << 0.0, 1.5;
  z << 0.6, 0.1;
  const Eigen::MatrixXd S = Eigen::MatrixXd::Identity(2, 2);
  const DataAssociationResult r = associate(z, y, S, {}, {});
  EXPECT_EQ(r.pairing, (std::vector<int>{1, 0}));
}

TEST(DataAssociation, AnglesAreWrapped) {
  Eigen::MatrixXd y(1, 2), z(1, 2);
  y << 5.0, 3.1;
  z << 5.0, -3.1;  // 0.08 rad apart across ±π
  Eigen::MatrixXd S = Eigen::MatrixXd::Identity(2, 2) * 0.01;
  EXPECT_EQ(associate(z, y, S, {1}, {}).paired(), 1u);
  EXPECT_EQ(associate(z, y, S, {}, {}).paired(), 0u);
}

// Maximum likelihood prefers the tighter prediction at equal Mahalanobis
// distance; the ML compatibility test uses the log-likelihood threshold.
TEST(DataAssociation, MaximumLikelihoodMetric) {
  Eigen::MatrixXd y(2, 1), z(1, 1), S = Eigen::MatrixXd::Zero(2, 2);
  y << -1.0, 0.2;
  z << 0.0;
  S(0, 0) = 1.0;    // d² = 1
  S(1, 1) = 0.04;   // d² = 1, much tighter
  DataAssociationOptions o;
  o.metric = DataAssociationMetric::MaximumLikelihood;
  EXPECT_EQ(associate(z, y, S, {}, o).pairing[0], 1);
  o.ic_metric = DataAssociationMetric::MaximumLikelihood;
  o.ml_threshold = 5.0;  // log-likelihood of the tight one ≈ 0.19: below
  EXPECT_EQ(associate(z, y, S, {}, o).paired(), 0u);
}

TEST(DataAssociation, NodeLimitReturnsBestSoFar) {
  std::mt19937_64 rng(7);
  const Eigen::Index n = 8, k = 8, m = 2;
  const Eigen::MatrixXd S = random_covariance(rng, n, m) * 50.0;  // everything compatible
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(n, m), z = Eigen::MatrixXd::Zero(k, m);
  DataAssociationOptions o;
  o.method = DataAssociationMethod::Jcbb;
  o.max_jcbb_nodes = 50;
  const DataAssociationResult r = associate(z, y, S, {}, o);
  EXPECT_EQ(r.termination, DataAssociationTermination::NodeLimit);
  EXPECT_GT(r.paired(), 0u);
}

TEST(DataAssociation, RejectsMismatchedSizes) {
  EXPECT_THROW(associate(Eigen::MatrixXd(1, 2), Eigen::MatrixXd::Zero(2, 2),
                         Eigen::MatrixXd::Identity(3, 3), {}, {}),
               InvalidArgument);
}

}  // namespace
}  // namespace rove
