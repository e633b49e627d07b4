#include "rove/slam/data_association.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "rove/bayes/distributions.h"
#include "rove/core/check.h"
#include "rove/poses/angle.h"

namespace rove {
namespace {

constexpr double kLog2Pi = 1.8378770664093454836;  // log(2π)

// The innovation z_j ⊖ ŷ_i, angles wrapped.
Eigen::VectorXd innovation(const Eigen::MatrixXd& z, int j, const Eigen::MatrixXd& y, int i,
                           const std::vector<int>& angles) {
  Eigen::VectorXd v = z.row(j).transpose() - y.row(i).transpose();
  for (int c : angles) v[c] = wrap_to_pi(v[c]);
  return v;
}

void check_inputs(const Eigen::MatrixXd& z, const Eigen::MatrixXd& y, const Eigen::MatrixXd& S,
                  const std::vector<int>& angles) {
  ROVE_CHECK_MSG(z.cols() == y.cols() || z.rows() == 0 || y.rows() == 0,
                 "observations have {} columns, predictions {}", z.cols(), y.cols());
  const Eigen::Index m = std::max(z.cols(), y.cols());
  ROVE_CHECK_MSG(S.rows() == y.rows() * m && S.cols() == S.rows(),
                 "covariance is {} x {}, expected {} x {}", S.rows(), S.cols(), y.rows() * m,
                 y.rows() * m);
  ROVE_CHECK_FINITE(z);
  ROVE_CHECK_FINITE(y);
  ROVE_CHECK_FINITE(S);
  for (int c : angles) ROVE_CHECK_MSG(c >= 0 && c < m, "angle component {} outside [0, {})", c, m);
}

// d² and the log-likelihood of innovation v under S's factor.
void distances(const Eigen::LLT<Eigen::MatrixXd>& llt, const Eigen::VectorXd& v, double& d2,
               double& ll) {
  const Eigen::MatrixXd L = llt.matrixL();
  d2 = L.triangularView<Eigen::Lower>().solve(v).squaredNorm();
  ll = -0.5 * d2 - L.diagonal().array().log().sum() - 0.5 * static_cast<double>(v.size()) * kLog2Pi;
}

bool passes(const DataAssociationOptions& o, double d2, double ll, double chi2) {
  return o.ic_metric == DataAssociationMetric::Mahalanobis ? d2 < chi2 : ll > o.ml_threshold;
}

// Individual compatibility and distances of every (prediction, observation).
void individual(const Eigen::MatrixXd& z, const Eigen::MatrixXd& y, const Eigen::MatrixXd& S,
                const std::vector<int>& angles, const DataAssociationOptions& o,
                DataAssociationResult& r, Eigen::MatrixXd& log_lik) {
  const Eigen::Index k = z.rows(), n = y.rows(), m = z.cols();
  const double chi2 = chi_square_quantile(o.chi2_probability, static_cast<double>(m));
  r.compatible.setConstant(n, k, false);
  r.mahalanobis2.setConstant(n, k, std::numeric_limits<double>::infinity());
  log_lik.setConstant(n, k, -std::numeric_limits<double>::infinity());
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::LLT<Eigen::MatrixXd> llt(S.block(i * m, i * m, m, m));
    if (llt.info() != Eigen::Success) continue;
    for (Eigen::Index j = 0; j < k; ++j) {
      double d2 = 0.0, ll = 0.0;
      distances(llt, innovation(z, static_cast<int>(j), y, static_cast<int>(i), angles), d2, ll);
      r.mahalanobis2(i, j) = d2;
      log_lik(i, j) = ll;
      r.compatible(i, j) = passes(o, d2, ll, chi2);
    }
  }
}

// Greedy NN as MRPT: observations by their best compatible distance, each
// takes its best prediction still free.
void nearest_neighbor(const DataAssociationOptions& o, const Eigen::MatrixXd& log_lik,
                      DataAssociationResult& r) {
  const Eigen::Index n = r.compatible.rows(), k = r.compatible.cols();
  const auto cost = [&](Eigen::Index i, Eigen::Index j) {
    return o.metric == DataAssociationMetric::Mahalanobis ? r.mahalanobis2(i, j) : -log_lik(i, j);
  };
  std::vector<std::pair<double, Eigen::Index>> order;  // (best cost, observation)
  for (Eigen::Index j = 0; j < k; ++j) {
    double best = std::numeric_limits<double>::infinity();
    bool any = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (r.compatible(i, j)) best = std::min(best, cost(i, j)), any = true;
    }
    if (any) order.emplace_back(best, j);
  }
  std::stable_sort(order.begin(), order.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<bool> taken(static_cast<std::size_t>(n), false);
  for (const auto& [unused, j] : order) {
    Eigen::Index best_i = -1;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!r.compatible(i, j) || taken[static_cast<std::size_t>(i)]) continue;
      if (best_i < 0 || cost(i, j) < cost(best_i, j)) best_i = i;
    }
    if (best_i >= 0) {
      taken[static_cast<std::size_t>(best_i)] = true;
      r.pairing[static_cast<std::size_t>(j)] = static_cast<int>(best_i);
    }
  }
}

// JCBB over observations in order, with the joint test kept incrementally:
// the Cholesky factor L of the paired predictions' joint covariance C_H
// grows by one block row per pairing (its top-left block is unchanged), and
// w = L⁻¹ ν_H gives D² = ‖w‖² (Neira & Tardós 2001, §IV).
class Jcbb {
 public:
  Jcbb(const Eigen::MatrixXd& z, const Eigen::MatrixXd& y, const Eigen::MatrixXd& S,
       const std::vector<int>& angles, const DataAssociationOptions& o, DataAssociationResult& r)
      : z_(z), y_(y), S_(S), angles_(angles), o_(o), r_(r), m_(z.cols()), k_(z.rows()) {
    L_.setZero(k_ * m_, k_ * m_);
    w_.setZero(k_ * m_);
    log_diag_.assign(static_cast<std::size_t>(k_ + 1), 0.0);
    d2_.assign(static_cast<std::size_t>(k_ + 1), 0.0);
    current_.assign(static_cast<std::size_t>(k_), -1);
    paired_preds_.reserve(static_cast<std::size_t>(k_));
    potential_.assign(static_cast<std::size_t>(k_ + 1), 0);
    chi2_.assign(static_cast<std::size_t>(k_ + 1), 0.0);
    for (Eigen::Index h = 1; h <= k_; ++h) {
      chi2_[static_cast<std::size_t>(h)] =
          chi_square_quantile(o.chi2_probability, static_cast<double>(h * m_));
    }
    for (Eigen::Index j = k_ - 1; j >= 0; --j) {
      potential_[static_cast<std::size_t>(j)] =
          potential_[static_cast<std::size_t>(j + 1)] + (r.compatible.col(j).any() ? 1 : 0);
    }
  }

  void run() { visit(0); }
  bool stopped() const { return stopped_; }
  double best_d2() const { return best_d2_; }

 private:
  double score(std::size_t h) const {  // smaller is better
    if (o_.metric == DataAssociationMetric::Mahalanobis) return d2_[h];
    const double ll = -0.5 * d2_[h] - log_diag_[h] - 0.5 * static_cast<double>(h * m_) * kLog2Pi;
    return -ll;
  }

  void visit(Eigen::Index j) {
    if (stopped_) return;
    if (++r_.nodes > o_.max_jcbb_nodes) {
      stopped_ = true;
      return;
    }
    const std::size_t h = paired_preds_.size();
    if (j == k_) {
      const double s = score(h);
      if (h > best_count_ || (h == best_count_ && h > 0 && s < best_score_)) {
        best_count_ = h;
        best_score_ = s;
        best_d2_ = d2_[h];
        r_.pairing = current_;
      }
      return;
    }
    const std::size_t bound = h + potential_[static_cast<std::size_t>(j)];
    if (bound < best_count_) return;
    for (Eigen::Index i = 0; i < y_.rows() && !stopped_; ++i) {
      if (!r_.compatible(i, j)) continue;
      if (std::find(paired_preds_.begin(), paired_preds_.end(), i) != paired_preds_.end()) continue;
      if (!extend(j, i)) continue;
      paired_preds_.push_back(i);
      current_[static_cast<std::size_t>(j)] = static_cast<int>(i);
      visit(j + 1);
      current_[static_cast<std::size_t>(j)] = -1;
      paired_preds_.pop_back();
    }
    if (h + potential_[static_cast<std::size_t>(j + 1)] >= best_count_) visit(j + 1);
  }

  // Extends L and w by pairing observation j with prediction i; false if
  // the joint covariance is not positive definite or the joint test fails.
  bool extend(Eigen::Index j, Eigen::Index i) {
    const std::size_t h = paired_preds_.size();
    const Eigen::Index at = static_cast<Eigen::Index>(h) * m_;
    Eigen::MatrixXd c(at, m_);  // cross-covariance with the paired predictions
    for (std::size_t a = 0; a < h; ++a) {
      c.middleRows(static_cast<Eigen::Index>(a) * m_, m_) =
          S_.block(paired_preds_[a] * m_, i * m_, m_, m_);
    }
    Eigen::MatrixXd l = c;  // l = L⁻¹ c, then the new block row is [lᵀ, L_s]
    if (at > 0) L_.topLeftCorner(at, at).triangularView<Eigen::Lower>().solveInPlace(l);
    const Eigen::MatrixXd schur = S_.block(i * m_, i * m_, m_, m_) - l.transpose() * l;
    const Eigen::LLT<Eigen::MatrixXd> llt(schur);
    if (llt.info() != Eigen::Success) return false;
    const Eigen::MatrixXd Ls = llt.matrixL();
    const Eigen::VectorXd v =
        innovation(z_, static_cast<int>(j), y_, static_cast<int>(i), angles_);
    Eigen::VectorXd tail = v;
    if (at > 0) tail -= l.transpose() * w_.head(at);
    tail = Ls.triangularView<Eigen::Lower>().solve(tail);
    const double d2 = d2_[h] + tail.squaredNorm();
    if (!(d2 < chi2_[h + 1])) return false;
    L_.block(at, 0, m_, at) = l.transpose();
    L_.block(at, at, m_, m_) = Ls;
    w_.segment(at, m_) = tail;
    d2_[h + 1] = d2;
    log_diag_[h + 1] = log_diag_[h] + Ls.diagonal().array().log().sum();
    return true;
  }

  const Eigen::MatrixXd& z_;
  const Eigen::MatrixXd& y_;
  const Eigen::MatrixXd& S_;
  const std::vector<int>& angles_;
  const DataAssociationOptions& o_;
  DataAssociationResult& r_;
  Eigen::Index m_, k_;
  Eigen::MatrixXd L_;
  Eigen::VectorXd w_;
  std::vector<double> log_diag_, d2_, chi2_;
  std::vector<int> current_;
  std::vector<Eigen::Index> paired_preds_;
  std::vector<std::size_t> potential_;
  std::size_t best_count_ = 0;
  double best_score_ = std::numeric_limits<double>::infinity();
  double best_d2_ = 0.0;
  bool stopped_ = false;
};

}  // namespace

std::string_view to_string(DataAssociationMethod method) noexcept {
  return method == DataAssociationMethod::Jcbb ? "jcbb" : "nearest-neighbor";
}

std::string_view to_string(DataAssociationMetric metric) noexcept {
  return metric == DataAssociationMetric::Mahalanobis ? "mahalanobis" : "maximum-likelihood";
}

DataAssociationOptions DataAssociationOptions::from_config(const ConfigSection& s) {
  DataAssociationOptions o;
  const std::initializer_list<IniEnumName<DataAssociationMetric>> metrics = {
      {"metricMaha", DataAssociationMetric::Mahalanobis},
      {"metricML", DataAssociationMetric::MaximumLikelihood}};
  o.method = s.get_enum<DataAssociationMethod>(
      "data_assoc_method", o.method,
      {{"assocNN", DataAssociationMethod::NearestNeighbor},
       {"assocJCBB", DataAssociationMethod::Jcbb}});
  o.metric = s.get_enum<DataAssociationMetric>("data_assoc_metric", o.metric, metrics);
  o.ic_metric = s.get_enum<DataAssociationMetric>("data_assoc_IC_metric", o.ic_metric, metrics);
  o.chi2_probability = s.get<double>("data_assoc_IC_chi2_thres", o.chi2_probability);
  if (!(o.chi2_probability > 0.0 && o.chi2_probability < 1.0)) {
    s.fail("data_assoc_IC_chi2_thres",
           fmt::format("{} is not a probability in (0, 1)", o.chi2_probability));
  }
  o.ml_threshold = s.get<double>("data_assoc_IC_ml_threshold", o.ml_threshold);
  const auto nodes = s.get<std::int64_t>("data_assoc_JCBB_max_nodes",
                                         static_cast<std::int64_t>(o.max_jcbb_nodes));
  if (nodes < 1) s.fail("data_assoc_JCBB_max_nodes", "give at least 1");
  o.max_jcbb_nodes = static_cast<std::size_t>(nodes);
  return o;
}

void DataAssociationOptions::check() const {
  ROVE_CHECK_MSG(chi2_probability > 0.0 && chi2_probability < 1.0,
                 "chi2_probability {} outside (0, 1)", chi2_probability);
  ROVE_CHECK_MSG(std::isfinite(ml_threshold), "ml_threshold {} not finite", ml_threshold);
  ROVE_CHECK_GE(max_jcbb_nodes, std::size_t{1});
}

std::size_t DataAssociationResult::paired() const {
  return static_cast<std::size_t>(std::count_if(pairing.begin(), pairing.end(),
                                                [](int p) { return p >= 0; }));
}

bool individually_compatible(const Eigen::VectorXd& v, const Eigen::MatrixXd& S,
                             const DataAssociationOptions& o, double chi2) {
  ROVE_CHECK_MSG(S.rows() == v.size() && S.cols() == v.size(), "S is {} x {} for {} values",
                 S.rows(), S.cols(), v.size());
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) return false;
  double d2 = 0.0, ll = 0.0;
  distances(llt, v, d2, ll);
  return passes(o, d2, ll, chi2);
}

bool joint_distance(const Eigen::MatrixXd& z, const Eigen::MatrixXd& y, const Eigen::MatrixXd& S,
                    const std::vector<int>& angles, const std::vector<int>& pairing,
                    double* mahalanobis2, double* log_likelihood) {
  check_inputs(z, y, S, angles);
  ROVE_CHECK_EQ(pairing.size(), static_cast<std::size_t>(z.rows()));
  const Eigen::Index m = z.cols();
  std::vector<std::pair<Eigen::Index, Eigen::Index>> pairs;  // (obs, pred)
  for (std::size_t j = 0; j < pairing.size(); ++j) {
    ROVE_CHECK_MSG(pairing[j] < y.rows(), "pairing {} beyond {} predictions", pairing[j], y.rows());
    if (pairing[j] >= 0) pairs.emplace_back(static_cast<Eigen::Index>(j), pairing[j]);
  }
  const Eigen::Index h = static_cast<Eigen::Index>(pairs.size());
  Eigen::MatrixXd C(h * m, h * m);
  Eigen::VectorXd v(h * m);
  for (Eigen::Index a = 0; a < h; ++a) {
    v.segment(a * m, m) = innovation(z, static_cast<int>(pairs[static_cast<std::size_t>(a)].first),
                                     y, static_cast<int>(pairs[static_cast<std::size_t>(a)].second),
                                     angles);
    for (Eigen::Index b = 0; b < h; ++b) {
      C.block(a * m, b * m, m, m) = S.block(pairs[static_cast<std::size_t>(a)].second * m,
                                            pairs[static_cast<std::size_t>(b)].second * m, m, m);
    }
  }
  if (h == 0) {
    if (mahalanobis2) *mahalanobis2 = 0.0;
    if (log_likelihood) *log_likelihood = 0.0;
    return true;
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(C);
  if (llt.info() != Eigen::Success) return false;
  const double d2 = llt.matrixL().solve(v).squaredNorm();
  if (mahalanobis2) *mahalanobis2 = d2;
  if (log_likelihood) {
    const Eigen::MatrixXd L = llt.matrixL();
    *log_likelihood = -0.5 * d2 - L.diagonal().array().log().sum() -
                      0.5 * static_cast<double>(h * m) * kLog2Pi;
  }
  return true;
}

DataAssociationResult associate(const Eigen::MatrixXd& z, const Eigen::MatrixXd& y,
                                const Eigen::MatrixXd& S, const std::vector<int>& angles,
                                const DataAssociationOptions& o) {
  o.check();
  check_inputs(z, y, S, angles);
  DataAssociationResult r;
  r.pairing.assign(static_cast<std::size_t>(z.rows()), -1);
  Eigen::MatrixXd log_lik;
  individual(z, y, S, angles, o, r, log_lik);
  if (o.method == DataAssociationMethod::NearestNeighbor) {
    nearest_neighbor(o, log_lik, r);
    if (r.paired() > 0) joint_distance(z, y, S, angles, r.pairing, &r.joint_mahalanobis2, nullptr);
  } else if (z.rows() > 0 && y.rows() > 0) {
    Jcbb search(z, y, S, angles, o, r);
    search.run();
    r.joint_mahalanobis2 = search.best_d2();
    if (search.stopped()) r.termination = DataAssociationTermination::NodeLimit;
  }
  r.message = fmt::format("{}: {} of {} observations paired with {} predictions, joint D2 {:.3f}{}",
                          to_string(o.method), r.paired(), z.rows(), y.rows(),
                          r.joint_mahalanobis2,
                          o.method == DataAssociationMethod::Jcbb
                              ? fmt::format(", {} nodes{}", r.nodes,
                                            r.termination == DataAssociationTermination::NodeLimit
                                                ? " (node limit reached)"
                                                : "")
                              : std::string());
  return r;
}

}  // namespace rove
