// Gauss–Newton, Levenberg–Marquardt and dog-leg on 2D/3D pose graphs.
#include "rove/graph/optimizer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <unordered_map>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/OrderingMethods>
#include <fmt/format.h>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/interrupt.h"
#include "rove/core/parallel.h"
#include "rove/core/timer.h"
#include "rove/graph/edge_error.h"
#include "sparse_cholesky.h"

namespace rove {

namespace {

std::string vertex_list(const std::vector<VertexId>& ids, std::size_t max_shown = 10) {
  std::string s;
  for (std::size_t k = 0; k < ids.size() && k < max_shown; ++k) {
    if (k) s += ", ";
    s += std::to_string(ids[k]);
  }
  if (ids.size() > max_shown) s += fmt::format(", ... ({} in all)", ids.size());
  return s;
}

// Auto back-end: CHOLMOD (supernodal) from this many flops per factor entry.
constexpr double kSupernodalFlopsPerEntry = 40.0;
constexpr double kReuseFlopsPerEntry = 100.0;

template <class PoseT>
class Engine {
 public:
  static constexpr int D = PoseT::kDof;
  using Mat = Eigen::Matrix<double, D, D>;
  using Vec = Eigen::Matrix<double, D, 1>;
  using Graph = PoseGraph<PoseT>;

  Engine(Graph& graph, const GraphOptimizerOptions& options, int num_threads)
      : graph_(graph), options_(options), team_(std::make_unique<ThreadTeam>(num_threads)) {}

  GraphOptimizerResult run();

 private:
  struct Active {
    std::size_t index;       // edge index in the graph
    int si, sj;              // slots of the two vertices
    RobustKernel kernel;
    int block = -1;          // off-diagonal block, -1 if an end is fixed
    bool transposed = false; // block holds Hji (position of j < position of i)
  };
  struct Linear {
    Vec e;
    Mat Ji, Jj;
    double s = 0.0;   // eᵀΩe
    double w = 1.0;   // ρ'(s)
    double rho = 0.0; // ρ(s)
  };

  bool setup(GraphOptimizerResult& result);
  void build_structure();
  // Residuals, Jacobians and weights of every edge at `poses` (parallel).
  void linearize_edges(const std::vector<PoseT>& poses, bool jacobians);
  // χ² at `poses`; per-edge terms summed in edge order.
  double chi2_at(const std::vector<PoseT>& poses);
  // Normal equations from lin_ into H_ (values) and g_.
  bool assemble(GraphOptimizerResult& result);
  bool factorize_damped(double lambda);
  void diagnose_factorization(std::optional<long> column, GraphOptimizerResult& result);
  void apply_step(const Eigen::VectorXd& delta, std::vector<PoseT>& out) const;
  Eigen::VectorXd multiply_h(const Eigen::VectorXd& x) const;
  // Solves H x = −g by conjugate gradients preconditioned with the factor
  // still held by solver_ (an earlier, undamped H). False when that does
  // not reach the tolerance within the iteration budget.
  bool solve_with_stale_factor(Eigen::VectorXd& x, GraphOptimizerResult& result);
  double translation_norm() const;
  void write_back();
  bool check_edges_finite(GraphOptimizerResult& result);

  // What the step computation carries from one iteration to the next.
  struct StepState {
    double lambda = 0.0;  // Levenberg–Marquardt damping
    double nu = 2.0;      // its growth factor after a failure
    double radius = 0.0;  // dog-leg trust radius
    Eigen::VectorXd delta, gn_step, sd_step;
    double sd_alpha = 0.0, g_h_g = 0.0;  // dog-leg: sd_step = −sd_alpha·g; gᵀHg
    bool gn_exact = true;                // dog-leg: H δ_gn = −g (no damping was needed)
    bool have_gn = false;                // dog-leg: gn_step is the current H's
    double last_gain_ratio = 0.0;        // of the last accepted step
    double predicted = 0.0;              // model decrease of delta
  };
  // A step computation either produced delta (and its predicted decrease),
  // asks for another iteration (the damping grew), or ends the run (the
  // result holds why).
  enum class StepOutcome { Ready, Retry, Stop };
  StepOutcome levenberg_marquardt_step(StepState& st, GraphIteration& rec,
                                       GraphOptimizerResult& result, Stopwatch& phase);
  StepOutcome gauss_newton_step(StepState& st, bool try_reuse, GraphIteration& rec,
                                GraphOptimizerResult& result, Stopwatch& phase);
  StepOutcome dog_leg_step(StepState& st, bool try_reuse, GraphIteration& rec,
                           GraphOptimizerResult& result, Stopwatch& phase);
  // After a rejected step: true when the run ends (the result holds why),
  // false to try again with more damping or a smaller region.
  bool reject_step(StepState& st, const GraphIteration& rec, double new_chi2, double x_norm,
                   GraphOptimizerResult& result);
  void adapt_after_accepted_step(StepState& st, const GraphIteration& rec) const;

  Graph& graph_;
  const GraphOptimizerOptions& options_;
  // One team for the whole run: linearization and χ² passes reuse its
  // threads instead of starting new ones per pass.
  std::unique_ptr<ThreadTeam> team_;
  std::unique_ptr<detail::SparseCholesky> solver_;  // chosen in setup()

  std::vector<VertexId> slot_id_;
  std::vector<PoseT> poses_;
  std::vector<int> slot_pos_;  // block position (elimination order) or -1 if fixed
  std::vector<int> pos_slot_;
  std::vector<Active> edges_;
  std::vector<Linear> lin_;
  std::vector<const PoseGraphEdge<PoseT>*> edge_ptr_;
  std::vector<double> term_;

  int n_ = 0;  // optimized vertices
  detail::SparseCholesky::Matrix H_;
  std::vector<int> block_base_;  // per off-diagonal block: D column offsets
  std::vector<int> diag_base_;   // per position: D column offsets of the diagonal block
  std::vector<int> diag_index_;  // per scalar column: index of the diagonal entry
  std::vector<double> diag_;     // undamped diagonal
  Eigen::VectorXd g_;
  double chi2_ = 0.0;
  std::optional<long> last_failure_column_;
  int factorizations_ = 0;
  bool stale_factor_ok_ = false;  // solver_ holds an undamped factor of an earlier H
  bool reuse_pays_ = false;       // a factorization costs many CG iterations
};

template <class PoseT>
bool Engine<PoseT>::setup(GraphOptimizerResult& result) {
  std::unordered_map<VertexId, int> slot_of;
  slot_of.reserve(graph_.num_vertices());
  const auto& all = graph_.edges();
  for (std::size_t k = 0; k < all.size(); ++k) {
    const auto& e = all[k];
    if (e.level != options_.level) continue;
    int s[2];
    const VertexId ends[2] = {e.from, e.to};
    for (int m = 0; m < 2; ++m) {
      auto [it, inserted] = slot_of.emplace(ends[m], static_cast<int>(slot_id_.size()));
      if (inserted) {
        slot_id_.push_back(ends[m]);
        poses_.push_back(graph_.pose(ends[m]));
      }
      s[m] = it->second;
    }
    Active a;
    a.index = k;
    a.si = s[0];
    a.sj = s[1];
    a.kernel = options_.robust_kernel ? *options_.robust_kernel : e.kernel;
    edges_.push_back(a);
    edge_ptr_.push_back(&e);
  }
  result.num_edges_used = edges_.size();
  const int slots = static_cast<int>(slot_id_.size());
  std::vector<char> fixed(static_cast<std::size_t>(slots), 0);
  bool any_fixed = false;
  for (int s = 0; s < slots; ++s) {
    fixed[s] = graph_.is_fixed(slot_id_[s]) ? 1 : 0;
    any_fixed = any_fixed || fixed[s];
  }
  if (options_.anchor) {
    auto it = slot_of.find(*options_.anchor);
    if (it == slot_of.end()) {
      result.termination = GraphTermination::InvalidInput;
      result.message = fmt::format("anchor vertex {} is not touched by any edge of level {}",
                                   *options_.anchor, options_.level);
      return false;
    }
    fixed[it->second] = 1;
    any_fixed = true;
  }
  if (!any_fixed && slots > 0) {
    // Gauge freedom: hold the lowest-id vertex where it is.
    int lowest = 0;
    for (int s = 1; s < slots; ++s)
      if (slot_id_[s] < slot_id_[lowest]) lowest = s;
    fixed[lowest] = 1;
    result.gauge_anchor = slot_id_[lowest];
  }
  // Connectivity: every component must hold an anchor.
  std::vector<int> parent(static_cast<std::size_t>(slots));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& a : edges_) parent[find(a.si)] = find(a.sj);
  std::vector<char> anchored(static_cast<std::size_t>(slots), 0);
  for (int s = 0; s < slots; ++s)
    if (fixed[s]) anchored[find(s)] = 1;
  std::vector<VertexId> loose;
  for (int s = 0; s < slots; ++s)
    if (!anchored[find(s)]) loose.push_back(slot_id_[s]);
  if (!loose.empty()) {
    std::sort(loose.begin(), loose.end());
    for (std::size_t k = 0; k < loose.size() && k < 20; ++k) {
      result.issues.push_back({GraphIssue::Kind::DisconnectedVertex, static_cast<std::size_t>(-1),
                               loose[k],
                               fmt::format("vertex {} is not connected to an anchored vertex "
                                           "through edges of level {}",
                                           loose[k], options_.level)});
    }
    result.termination = GraphTermination::InvalidInput;
    result.message = fmt::format(
        "{} vertices are not connected to an anchored vertex (gauge undetermined): {}; anchor "
        "one vertex of each component (FIX) or add edges",
        loose.size(), vertex_list(loose));
    return false;
  }
  slot_pos_.assign(static_cast<std::size_t>(slots), -1);
  std::vector<int> var_slot;
  for (int s = 0; s < slots; ++s) {
    if (!fixed[s]) {
      slot_pos_[s] = static_cast<int>(var_slot.size());
      var_slot.push_back(s);
    } else {
      ++result.num_vertices_fixed;
    }
  }
  n_ = static_cast<int>(var_slot.size());
  result.num_vertices_optimized = static_cast<std::size_t>(n_);
  if (n_ == 0) return true;

  // Fill-reducing order of the vertex blocks (AMD or METIS on the vertex graph):
    // ordering blocks rather than scalars keeps each vertex contiguous.
  {
    std::vector<Eigen::Triplet<int>> trip;
    trip.reserve(edges_.size() * 2 + static_cast<std::size_t>(n_));
    for (int v = 0; v < n_; ++v) trip.emplace_back(v, v, 1);
    for (const auto& a : edges_) {
      const int vi = slot_pos_[a.si], vj = slot_pos_[a.sj];
      if (vi >= 0 && vj >= 0) {
        trip.emplace_back(vi, vj, 1);
        trip.emplace_back(vj, vi, 1);
      }
    }
    Eigen::SparseMatrix<int, Eigen::ColMajor, int> pattern(n_, n_);
    pattern.setFromTriplets(trip.begin(), trip.end());
    // Back-end. Auto: CHOLMOD's supernodal factorization pays when the
    // factor is dense enough for BLAS-3 (the 3D sets), Eigen's simplicial
    // one when it is not (the 2D sets: 15-20 % less time than CHOLMOD, and
    // no CHOLMOD/BLAS to load). The line is CHOLMOD's own
    // (Common->supernodal_switch): ≥ 40 flops per factor entry, estimated
    // from the block pattern in its AMD order.
    LinearSolverType type = options_.linear_solver;
    std::vector<int> perm;
    if (type == LinearSolverType::Auto) {
      type = LinearSolverType::Block;
      if (detail::cholmod_compiled()) {
        perm = detail::fill_reducing_order(pattern, false);
        const detail::CholeskyCost cost = detail::block_cholesky_cost(pattern, perm, D);
        if (cost.flops >= kSupernodalFlopsPerEntry * cost.factor_nonzeros &&
            detail::cholmod_built()) {
          type = LinearSolverType::Cholmod;
          perm.clear();
        }
      }
    }
    solver_ = std::make_unique<detail::SparseCholesky>(type, D);
    result.linear_solver = solver_->type();
    if (perm.empty())
      perm = detail::fill_reducing_order(pattern, solver_->type() == LinearSolverType::Cholmod);
    // A CG iteration on a reused factor reads the factor twice (two
    // triangular solves) and H once; a factorization costs `flops`. Reuse
    // only where a factorization buys many CG iterations: the dense
    // factors of the 3D graphs (sphere2500, torus3D: ~200 flops per factor
    // entry), not the 2D ones (~20), where it measured no faster.
    if (options_.reuse_factorization) {
      const detail::CholeskyCost cost = detail::block_cholesky_cost(pattern, perm, D);
      reuse_pays_ = cost.flops >= kReuseFlopsPerEntry * cost.factor_nonzeros;
    }
    pos_slot_.resize(static_cast<std::size_t>(n_));
    for (int p = 0; p < n_; ++p) {
      const int old_var = perm[static_cast<std::size_t>(p)];
      pos_slot_[p] = var_slot[old_var];
      slot_pos_[var_slot[old_var]] = p;
    }
  }
  build_structure();
  return true;
}

template <class PoseT>
void Engine<PoseT>::build_structure() {
  // Off-diagonal blocks (row position < column position), per column.
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(n_));
  for (const auto& a : edges_) {
    const int pi = slot_pos_[a.si], pj = slot_pos_[a.sj];
    if (pi < 0 || pj < 0) continue;
    rows[std::max(pi, pj)].push_back(std::min(pi, pj));
  }
  std::vector<int> block_start(static_cast<std::size_t>(n_) + 1, 0);
  for (int c = 0; c < n_; ++c) {
    auto& r = rows[c];
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    block_start[c + 1] = block_start[c] + static_cast<int>(r.size());
  }
  const int nblocks = block_start[n_];
  const int N = n_ * D;
  // Column pointers of the scalar upper triangle.
  std::vector<int> colptr(static_cast<std::size_t>(N) + 1, 0);
  for (int c = 0; c < n_; ++c) {
    const int off = static_cast<int>(rows[c].size()) * D;
    for (int k = 0; k < D; ++k) colptr[c * D + k + 1] = colptr[c * D + k] + off + k + 1;
  }
  const int nnz = colptr[N];
  H_.resize(N, N);
  H_.resizeNonZeros(nnz);
  std::copy(colptr.begin(), colptr.end(), H_.outerIndexPtr());
  int* inner = H_.innerIndexPtr();
  block_base_.assign(static_cast<std::size_t>(nblocks) * D, 0);
  diag_base_.assign(static_cast<std::size_t>(n_) * D, 0);
  diag_index_.assign(static_cast<std::size_t>(N), 0);
  for (int c = 0; c < n_; ++c) {
    for (int k = 0; k < D; ++k) {
      int at = colptr[c * D + k];
      for (std::size_t b = 0; b < rows[c].size(); ++b) {
        block_base_[(block_start[c] + static_cast<int>(b)) * D + k] = at;
        for (int m = 0; m < D; ++m) inner[at++] = rows[c][b] * D + m;
      }
      diag_base_[c * D + k] = at;
      for (int m = 0; m <= k; ++m) inner[at++] = c * D + m;
      diag_index_[c * D + k] = at - 1;
    }
  }
  std::fill(H_.valuePtr(), H_.valuePtr() + nnz, 0.0);
  for (auto& a : edges_) {
    const int pi = slot_pos_[a.si], pj = slot_pos_[a.sj];
    if (pi < 0 || pj < 0) continue;
    const int c = std::max(pi, pj), r = std::min(pi, pj);
    const auto it = std::lower_bound(rows[c].begin(), rows[c].end(), r);
    a.block = block_start[c] + static_cast<int>(it - rows[c].begin());
    a.transposed = pj < pi;
  }
  diag_.assign(static_cast<std::size_t>(N), 0.0);
  g_.resize(N);
}

template <class PoseT>
void Engine<PoseT>::linearize_edges(const std::vector<PoseT>& poses, bool jacobians) {
  lin_.resize(edges_.size());
  parallel_for(edges_.size(), *team_, [&](std::size_t k) {
    const Active& a = edges_[k];
    const auto& edge = *edge_ptr_[k];
    Linear& l = lin_[k];
    l.e = edge_error(poses[a.si], poses[a.sj], edge.measurement, jacobians ? &l.Ji : nullptr,
                     jacobians ? &l.Jj : nullptr);
    l.s = l.e.dot(edge.information * l.e);
    if (std::isfinite(l.s) && l.s >= 0.0) {
      const KernelValues kv = a.kernel.evaluate(l.s);
      l.rho = kv.rho;
      l.w = kv.d1;
    } else {
      l.rho = std::numeric_limits<double>::quiet_NaN();
      l.w = 0.0;
    }
  });
}

template <class PoseT>
double Engine<PoseT>::chi2_at(const std::vector<PoseT>& poses) {
  term_.resize(edges_.size());
  parallel_for(edges_.size(), *team_, [&](std::size_t k) {
    const Active& a = edges_[k];
    const auto& edge = *edge_ptr_[k];
    const Vec err = edge_error(poses[a.si], poses[a.sj], edge.measurement);
    const double s = err.dot(edge.information * err);
    term_[k] = (std::isfinite(s) && s >= 0.0) ? a.kernel.rho(s)
                                              : std::numeric_limits<double>::quiet_NaN();
  });
  double sum = 0.0;
  for (double t : term_) sum += t;
  return sum;
}

template <class PoseT>
bool Engine<PoseT>::check_edges_finite(GraphOptimizerResult& result) {
  bool ok = true;
  for (std::size_t k = 0; k < edges_.size(); ++k) {
    const Linear& l = lin_[k];
    const auto& edge = *edge_ptr_[k];
    const bool fe = l.e.allFinite() && std::isfinite(l.s);
    const bool fj = l.Ji.allFinite() && l.Jj.allFinite();
    if (fe && fj) continue;
    ok = false;
    if (result.issues.size() >= 50) continue;
    result.issues.push_back(
        {fe ? GraphIssue::Kind::NonFiniteJacobian : GraphIssue::Kind::NonFiniteResidual,
         edges_[k].index, edge.from,
         fmt::format("edge {} ({} -> {}): {} is not finite", edges_[k].index, edge.from, edge.to,
                     fe ? "Jacobian" : "residual")});
  }
  return ok;
}

template <class PoseT>
bool Engine<PoseT>::assemble(GraphOptimizerResult& result) {
  if (!check_edges_finite(result)) return false;
  double* val = H_.valuePtr();
  std::fill(val, val + H_.nonZeros(), 0.0);
  g_.setZero();
  chi2_ = 0.0;
  for (std::size_t k = 0; k < edges_.size(); ++k) {
    const Active& a = edges_[k];
    const Linear& l = lin_[k];
    chi2_ += l.rho;
    if (l.w == 0.0) continue;
    const Mat W = l.w * edge_ptr_[k]->information;
    const int pi = slot_pos_[a.si], pj = slot_pos_[a.sj];
    const Vec We = W * l.e;
    const Mat WJi = W * l.Ji;
    const Mat WJj = W * l.Jj;
    auto add_diag = [&](int p, const Mat& J, const Mat& WJ) {
      const Mat B = J.transpose() * WJ;
      for (int c = 0; c < D; ++c) {
        double* col = val + diag_base_[p * D + c];
        for (int r = 0; r <= c; ++r) col[r] += B(r, c);
      }
      g_.template segment<D>(p * D).noalias() += J.transpose() * We;
    };
    if (pi >= 0) add_diag(pi, l.Ji, WJi);
    if (pj >= 0) add_diag(pj, l.Jj, WJj);
    if (a.block >= 0) {
      // Block (min pos, max pos): Jiᵀ W Jj, or its transpose.
      const Mat B = a.transposed ? Mat(l.Jj.transpose() * WJi) : Mat(l.Ji.transpose() * WJj);
      const int* base = &block_base_[static_cast<std::size_t>(a.block) * D];
      for (int c = 0; c < D; ++c) {
        double* col = val + base[c];
        for (int r = 0; r < D; ++r) col[r] += B(r, c);
      }
    }
  }
  for (std::size_t s = 0; s < diag_.size(); ++s) diag_[s] = val[diag_index_[s]];
  return true;
}

template <class PoseT>
bool Engine<PoseT>::factorize_damped(double lambda) {
  ++factorizations_;
  double* val = H_.valuePtr();
  for (std::size_t s = 0; s < diag_.size(); ++s) {
    val[diag_index_[s]] = diag_[s] + lambda * std::clamp(diag_[s], 1e-6, 1e32);
  }
  const auto failed = solver_->factorize(H_);
  for (std::size_t s = 0; s < diag_.size(); ++s) val[diag_index_[s]] = diag_[s];
  last_failure_column_ = failed;
  return !failed.has_value();
}

template <class PoseT>
void Engine<PoseT>::diagnose_factorization(std::optional<long> column,
                                           GraphOptimizerResult& result) {
  // Vertices whose own block of JᵀWJ is singular.
  const double* val = H_.valuePtr();
  for (int p = 0; p < n_ && result.issues.size() < 50; ++p) {
    Mat B;
    for (int c = 0; c < D; ++c)
      for (int r = 0; r <= c; ++r) B(r, c) = B(c, r) = val[diag_base_[p * D + c] + r];
    Eigen::LLT<Mat> llt(B);
    Eigen::SelfAdjointEigenSolver<Mat> eig(B);
    const double lo = eig.eigenvalues()(0), hi = eig.eigenvalues()(D - 1);
    if (llt.info() != Eigen::Success || !(lo > 1e-12 * std::max(hi, 1e-300))) {
      const VertexId id = slot_id_[pos_slot_[p]];
      result.issues.push_back({GraphIssue::Kind::RankDeficientBlock, static_cast<std::size_t>(-1),
                               id,
                               fmt::format("vertex {}: its block of the normal equations is rank "
                                           "deficient (eigenvalues {} .. {})",
                                           id, lo, hi)});
    }
  }
  if (result.issues.empty() && column && *column >= 0 && *column < static_cast<long>(D) * n_) {
    const VertexId id = slot_id_[pos_slot_[static_cast<std::size_t>(*column / D)]];
    result.issues.push_back({GraphIssue::Kind::NotPositiveDefinite, static_cast<std::size_t>(-1),
                             id,
                             fmt::format("the normal equations are not positive definite: the "
                                         "factorization broke down at vertex {} (component {})",
                                         id, *column % D)});
  }
}

template <class PoseT>
void Engine<PoseT>::apply_step(const Eigen::VectorXd& delta, std::vector<PoseT>& out) const {
  out = poses_;
  for (int p = 0; p < n_; ++p) {
    const int s = pos_slot_[p];
    out[s] = poses_[s] * PoseT::exp(delta.template segment<D>(p * D));
  }
}

template <class PoseT>
Eigen::VectorXd Engine<PoseT>::multiply_h(const Eigen::VectorXd& x) const {
  // H holds the upper triangle with the undamped diagonal.
  Eigen::VectorXd y = Eigen::VectorXd::Zero(x.size());
  const int* outer = H_.outerIndexPtr();
  const int* inner = H_.innerIndexPtr();
  const double* val = H_.valuePtr();
  for (int c = 0; c < H_.cols(); ++c) {
    for (int k = outer[c]; k < outer[c + 1]; ++k) {
      const int r = inner[k];
      y[r] += val[k] * x[c];
      if (r != c) y[c] += val[k] * x[r];
    }
  }
  return y;
}

template <class PoseT>
bool Engine<PoseT>::solve_with_stale_factor(Eigen::VectorXd& x, GraphOptimizerResult& result) {
  // M = L Lᵀ of an earlier H; near the optimum H changes little between
  // steps, M⁻¹H is close to I and CG converges in a few iterations, each
  // one product with H and one pair of triangular solves: a fraction of a
  // factorization where the factor is dense (the 3D graphs).
  const Eigen::VectorXd b = -g_;
  const double b_norm = b.norm();
  x.setZero(b.size());
  if (!(b_norm > 0.0)) return true;
  Eigen::VectorXd r = b, z, p, hp;
  solver_->solve(r, z);
  p = z;
  double rz = r.dot(z);
  const double tol = options_.reuse_tolerance * b_norm;
  for (int k = 1; k <= options_.reuse_max_cg_iterations; ++k) {
    hp = multiply_h(p);
    const double php = p.dot(hp);
    if (!(php > 0.0) || !std::isfinite(rz)) break;
    const double alpha = rz / php;
    x.noalias() += alpha * p;
    r.noalias() -= alpha * hp;
    ++result.cg_iterations;
    const double r_norm = r.norm();
    if (r_norm <= tol) return x.allFinite();
    // The first iteration tells whether M⁻¹H is near I: when it removes
    // less than 80 % of the residual, the factor is too stale to pay.
    if (k == 1 && r_norm > 0.2 * b_norm) break;
    solver_->solve(r, z);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  return false;
}

template <class PoseT>
double Engine<PoseT>::translation_norm() const {
  double sq = 0.0;
  for (int p = 0; p < n_; ++p) sq += poses_[pos_slot_[p]].translation().squaredNorm();
  return std::sqrt(sq);
}

template <class PoseT>
void Engine<PoseT>::write_back() {
  for (int p = 0; p < n_; ++p) {
    const int s = pos_slot_[p];
    graph_.set_pose(slot_id_[s], poses_[s]);
  }
}

template <class PoseT>
auto Engine<PoseT>::levenberg_marquardt_step(StepState& st, GraphIteration& rec,
                                             GraphOptimizerResult& result, Stopwatch& phase)
    -> StepOutcome {
  rec.damping = st.lambda;
  const bool ok = factorize_damped(st.lambda);
  stale_factor_ok_ = false;
  if (ok) solver_->solve(-g_, st.delta);
  result.timing.factorize += phase.lap();
  if (!ok || !st.delta.allFinite()) {
    st.lambda *= st.nu;
    st.nu *= 2.0;
    rec.chi2 = chi2_;
    result.history.push_back(rec);
    if (st.lambda > 1e32) {
      result.termination = GraphTermination::NumericalFailure;
      result.message = "the damped normal equations stay singular even at λ = 1e32";
      diagnose_factorization(last_failure_column_, result);
      return StepOutcome::Stop;
    }
    return StepOutcome::Retry;
  }
  const Eigen::VectorXd& delta = st.delta;
  Eigen::VectorXd Dd(delta.size());
  for (Eigen::Index s = 0; s < delta.size(); ++s)
    Dd[s] = st.lambda * std::clamp(diag_[static_cast<std::size_t>(s)], 1e-6, 1e32) * delta[s];
  st.predicted = delta.dot(Dd - g_);
  return StepOutcome::Ready;
}

template <class PoseT>
auto Engine<PoseT>::gauss_newton_step(StepState& st, bool try_reuse, GraphIteration& rec,
                                      GraphOptimizerResult& result, Stopwatch& phase)
    -> StepOutcome {
  const bool reused = try_reuse && solve_with_stale_factor(st.delta, result);
  bool ok = reused;
  if (reused) {
    ++result.reused_factorizations;
  } else {
    ok = factorize_damped(0.0);
    stale_factor_ok_ = ok;
    if (ok) solver_->solve(-g_, st.delta);
  }
  result.timing.factorize += phase.lap();
  if (!ok || !st.delta.allFinite()) {
    result.termination = GraphTermination::NumericalFailure;
    result.message = "the normal equations are singular (Gauss-Newton has no damping)";
    diagnose_factorization(last_failure_column_, result);
    if (!result.issues.empty()) result.message += ": " + result.issues.front().message;
    rec.chi2 = chi2_;
    result.history.push_back(rec);
    return StepOutcome::Stop;
  }
  // Model decrease −(2gᵀδ + δᵀHδ); Hδ = −g when δ came from a factor.
  const Eigen::VectorXd& delta = st.delta;
  st.predicted =
      reused ? -(2.0 * g_.dot(delta) + delta.dot(multiply_h(delta))) : -delta.dot(g_);
  return StepOutcome::Ready;
}

template <class PoseT>
auto Engine<PoseT>::dog_leg_step(StepState& st, bool try_reuse, GraphIteration& rec,
                                 GraphOptimizerResult& result, Stopwatch& phase) -> StepOutcome {
  if (!st.have_gn) {
    if (try_reuse && solve_with_stale_factor(st.gn_step, result)) {
      // H δ_gn = −g only to the CG tolerance: the model decrease of each
      // step is then formed with H itself (below).
      ++result.reused_factorizations;
      st.gn_exact = false;
    } else {
      bool ok = factorize_damped(0.0);
      st.gn_exact = ok;
      stale_factor_ok_ = ok;
      for (double mu = 1e-10; !ok && mu <= 1e-2; mu *= 100.0) ok = factorize_damped(mu);
      if (ok) solver_->solve(-g_, st.gn_step);
      if (!ok || !st.gn_step.allFinite()) {
        result.timing.factorize += phase.lap();
        result.termination = GraphTermination::NumericalFailure;
        result.message = "the normal equations are singular";
        diagnose_factorization(last_failure_column_, result);
        if (!result.issues.empty()) result.message += ": " + result.issues.front().message;
        return StepOutcome::Stop;
      }
    }
    st.g_h_g = g_.dot(multiply_h(g_));
    st.sd_alpha = st.g_h_g > 0.0 ? g_.squaredNorm() / st.g_h_g : 0.0;
    st.sd_step = -st.sd_alpha * g_;
    st.have_gn = true;
    result.timing.factorize += phase.lap();
  }
  rec.damping = st.radius;
  // Model decrease −(2gᵀδ + δᵀHδ). Every candidate δ is a combination
  // of g and the Gauss–Newton step (H δ_gn = −g), so δᵀHδ follows from
  // gᵀHg, formed once per factorization: no product with H per step
  // (unless δ_gn came from a damped system, where H δ_gn ≠ −g).
  const Eigen::VectorXd& gn_step = st.gn_step;
  const Eigen::VectorXd& sd_step = st.sd_step;
  const double radius = st.radius;
  const double gn_norm = gn_step.norm();
  const double sd_coef = -st.sd_alpha;  // sd_step = sd_coef·g
  if (gn_norm <= radius) {
    st.delta = gn_step;
    st.predicted = -g_.dot(gn_step);
  } else if (sd_step.norm() >= radius) {
    const double t = -radius / g_.norm();  // δ = t·g
    st.delta = t * g_;
    st.predicted = -(2.0 * t * g_.squaredNorm() + t * t * st.g_h_g);
  } else {
    const Eigen::VectorXd d = gn_step - sd_step;
    const double c = sd_step.dot(d), dd = d.squaredNorm();
    const double beta =
        (-c + std::sqrt(c * c + dd * (radius * radius - sd_step.squaredNorm()))) / dd;
    st.delta = sd_step + beta * d;
    // δ = (1 − β)·sd_coef·g + β·δ_gn, Hδ = (1 − β)·sd_coef·Hg − β·g.
    const double a = (1.0 - beta) * sd_coef;
    const double dHd = a * a * st.g_h_g - 2.0 * a * beta * g_.squaredNorm() +
                       beta * beta * (-g_.dot(gn_step));
    st.predicted = -(2.0 * g_.dot(st.delta) + dHd);
  }
  if (!st.gn_exact) st.predicted = -(2.0 * g_.dot(st.delta) + st.delta.dot(multiply_h(st.delta)));
  result.timing.factorize += phase.lap();
  return StepOutcome::Ready;
}

template <class PoseT>
bool Engine<PoseT>::reject_step(StepState& st, const GraphIteration& rec, double new_chi2,
                                double x_norm, GraphOptimizerResult& result) {
  const GraphSolver method = options_.solver;
  if (std::isfinite(new_chi2) && method != GraphSolver::GaussNewton &&
      new_chi2 - chi2_ <= options_.function_tolerance * chi2_) {
    // The step raised χ² by less than the function tolerance: the
    // quadratic model has nothing left to give. Stop here, as Ceres
    // does, rather than shrink the region (LM: refactorize) for a
    // change the tolerance calls nothing.
    result.termination = GraphTermination::Converged;
    result.message =
        fmt::format("function tolerance: a rejected step changed χ² by {:.3g} (relative) <= {:.3g}",
                    (new_chi2 - chi2_) / std::max(chi2_, 1e-300), options_.function_tolerance);
    return true;
  }
  if (method == GraphSolver::GaussNewton) {
    result.termination = GraphTermination::NumericalFailure;
    result.message = "the Gauss-Newton step gave a non-finite χ²";
    return true;
  }
  if (method == GraphSolver::LevenbergMarquardt) {
    st.lambda *= st.nu;
    st.nu *= 2.0;
    if (st.lambda > 1e32) {
      result.termination = GraphTermination::NoProgress;
      result.message = "no decrease of χ² even at λ = 1e32";
      return true;
    }
    return false;
  }
  st.radius = 0.5 * std::min(st.radius, rec.step_norm);
  if (st.radius <= options_.step_tolerance * (x_norm + options_.step_tolerance)) {
    result.termination = GraphTermination::NoProgress;
    result.message =
        fmt::format("trust region shrank to {:.3g} without a decrease of χ²", st.radius);
    return true;
  }
  return false;
}

template <class PoseT>
void Engine<PoseT>::adapt_after_accepted_step(StepState& st, const GraphIteration& rec) const {
  if (options_.solver == GraphSolver::LevenbergMarquardt) {
    const double r = 2.0 * rec.gain_ratio - 1.0;
    st.lambda *= std::max(1.0 / 3.0, 1.0 - r * r * r);
    st.lambda = std::max(st.lambda, 1e-30);
    st.nu = 2.0;
  } else if (options_.solver == GraphSolver::DogLeg) {
    if (rec.gain_ratio > 0.75) {
      st.radius = std::max(st.radius, 3.0 * rec.step_norm);
    } else if (rec.gain_ratio < 0.25) {
      st.radius = 0.5 * std::min(st.radius, rec.step_norm);
    }
    st.have_gn = false;
  }
}

template <class PoseT>
GraphOptimizerResult Engine<PoseT>::run() {
  GraphOptimizerResult result;
  Stopwatch total;
  Stopwatch phase;
  // Until setup() chooses (it loads CHOLMOD only if it chooses it).
  result.linear_solver = options_.linear_solver == LinearSolverType::Auto
                             ? LinearSolverType::Block
                             : options_.linear_solver;
  if (!setup(result)) {
    result.timing.setup = phase.lap();
    result.timing.total = total.elapsed();
    return result;
  }
  if (n_ > 0) solver_->analyze(H_);
  result.hessian_nonzeros = static_cast<std::size_t>(H_.nonZeros());
  result.timing.setup = phase.lap();

  linearize_edges(poses_, true);
  if (!assemble(result)) {
    result.timing.linearize = phase.lap();
    result.termination = GraphTermination::NumericalFailure;
    result.message = fmt::format("{} edges have a non-finite residual or Jacobian at the initial "
                                 "guess (first: {})",
                                 result.issues.size(), result.issues.front().message);
    result.timing.total = total.elapsed();
    return result;
  }
  result.timing.linearize += phase.lap();
  result.initial_chi2 = result.final_chi2 = chi2_;
  if (n_ == 0) {
    result.termination = GraphTermination::Converged;
    result.message = "nothing to optimize: every vertex touched by the edges is fixed";
    result.timing.total = total.elapsed();
    return result;
  }

  const GraphSolver method = options_.solver;
  StepState st;
  st.lambda = options_.initial_lambda;
  st.radius = options_.initial_trust_radius;
  std::vector<PoseT> trial;
  result.termination = GraphTermination::MaxIterations;
  result.message = fmt::format("reached the maximum of {} iterations", options_.max_iterations);

  for (int it = 1; it <= options_.max_iterations; ++it) {
    // Ctrl-C between iterations: the graph is left untouched (the poses are
    // written back only at the end).
    throw_if_interrupted();
    const double gmax = g_.cwiseAbs().maxCoeff();
    if (gmax <= options_.gradient_tolerance) {
      result.termination = GraphTermination::Converged;
      result.message = fmt::format("gradient tolerance: max |g| = {:.3g} <= {:.3g}", gmax,
                                   options_.gradient_tolerance);
      break;
    }
    GraphIteration rec;
    rec.iteration = it;
    result.iterations = it;
    // Reuse the last factorization (dog-leg, Gauss–Newton) when the last
    // step landed where the quadratic model said: H has barely changed.
    // (reuse_pays_ is false when options_.reuse_factorization is.)
    const bool try_reuse = stale_factor_ok_ && reuse_pays_ &&
                           std::abs(st.last_gain_ratio - 1.0) <= options_.reuse_gain_window;
    StepOutcome outcome;
    if (method == GraphSolver::LevenbergMarquardt) {
      outcome = levenberg_marquardt_step(st, rec, result, phase);
    } else if (method == GraphSolver::GaussNewton) {
      outcome = gauss_newton_step(st, try_reuse, rec, result, phase);
    } else {
      outcome = dog_leg_step(st, try_reuse, rec, result, phase);
    }
    if (outcome == StepOutcome::Stop) break;
    if (outcome == StepOutcome::Retry) continue;

    const Eigen::VectorXd& delta = st.delta;
    if (!delta.allFinite()) {
      // A finite but huge measurement (1e88 m) can overflow the dogleg
      // combination of the steps; stop honestly instead of applying NaN.
      rec.chi2 = chi2_;
      result.history.push_back(rec);
      result.termination = GraphTermination::NumericalFailure;
      result.message = "the step is not finite (measurements or states too large to solve)";
      break;
    }
    rec.step_norm = delta.norm();
    const double x_norm = translation_norm();
    if (rec.step_norm <= options_.step_tolerance * (x_norm + options_.step_tolerance)) {
      rec.chi2 = chi2_;
      result.history.push_back(rec);
      result.termination = GraphTermination::Converged;
      result.message = fmt::format("step tolerance: |step| = {:.3g}", rec.step_norm);
      break;
    }
    apply_step(delta, trial);
    const double new_chi2 = chi2_at(trial);
    result.timing.evaluate += phase.lap();
    const double actual = chi2_ - new_chi2;
    rec.chi2 = new_chi2;
    rec.gain_ratio = st.predicted > 0.0 ? actual / st.predicted : 0.0;
    const bool finite = std::isfinite(new_chi2);
    const bool accept = finite && (method == GraphSolver::GaussNewton || new_chi2 < chi2_);
    rec.accepted = accept;
    result.history.push_back(rec);

    if (!accept) {
      if (reject_step(st, rec, new_chi2, x_norm, result)) break;
      continue;
    }

    // Accepted step.
    ++result.accepted_steps;
    st.last_gain_ratio = rec.gain_ratio;
    const double old_chi2 = chi2_;
    poses_.swap(trial);
    if (std::abs(old_chi2 - new_chi2) <= options_.function_tolerance * old_chi2) {
      // Converged: keep the step (χ² is already known), skip the
      // linearization that no further iteration would use.
      chi2_ = new_chi2;
      result.termination = GraphTermination::Converged;
      result.message = fmt::format("function tolerance: relative decrease {:.3g} <= {:.3g}",
                                   std::abs(old_chi2 - new_chi2) / std::max(old_chi2, 1e-300),
                                   options_.function_tolerance);
      break;
    }
    adapt_after_accepted_step(st, rec);
    linearize_edges(poses_, true);
    if (!assemble(result)) {
      result.timing.linearize += phase.lap();
      result.termination = GraphTermination::NumericalFailure;
      result.message = fmt::format("edges became non-finite during the optimization (first: {})",
                                   result.issues.front().message);
      break;
    }
    result.timing.linearize += phase.lap();
  }
  result.final_chi2 = chi2_;
  result.factorizations = factorizations_;
  write_back();
  result.factor_nonzeros = solver_ ? solver_->factor_nonzeros() : 0;
  result.timing.total = total.elapsed();
  return result;
}

template <class PoseT>
GraphOptimizerResult optimize_impl(PoseGraph<PoseT>& graph, const GraphOptimizerOptions& options) {
  ROVE_CHECK_GE(options.max_iterations, 0);
  const int threads = resolve_thread_count(options.num_threads, "GraphOptimizerOptions::num_threads");
  ROVE_CHECK_MSG(options.function_tolerance >= 0.0 && options.gradient_tolerance >= 0.0 &&
                     options.step_tolerance >= 0.0,
                 "tolerances must be >= 0");
  ROVE_CHECK_MSG(std::isfinite(options.initial_lambda) && options.initial_lambda > 0.0,
                 "initial_lambda must be finite and > 0, got {}", options.initial_lambda);
  ROVE_CHECK_MSG(std::isfinite(options.initial_trust_radius) && options.initial_trust_radius > 0.0,
                 "initial_trust_radius must be finite and > 0, got {}",
                 options.initial_trust_radius);
  Engine<PoseT> engine(graph, options, threads);
  return engine.run();
}

template <class PoseT>
double chi2_impl(const PoseGraph<PoseT>& graph, int level,
                 const std::optional<RobustKernel>& robust_kernel) {
  double sum = 0.0;
  for (const auto& e : graph.edges()) {
    if (e.level != level) continue;
    const auto err = edge_error(graph.pose(e.from), graph.pose(e.to), e.measurement);
    const double s = err.dot(e.information * err);
    if (!(std::isfinite(s) && s >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
    sum += (robust_kernel ? *robust_kernel : e.kernel).rho(s);
  }
  return sum;
}

}  // namespace

GraphOptimizerResult optimize(PoseGraph2D& graph, const GraphOptimizerOptions& options) {
  return optimize_impl(graph, options);
}
GraphOptimizerResult optimize(PoseGraph3D& graph, const GraphOptimizerOptions& options) {
  return optimize_impl(graph, options);
}

double compute_chi2(const PoseGraph2D& graph, int level,
                    const std::optional<RobustKernel>& robust_kernel) {
  return chi2_impl(graph, level, robust_kernel);
}
double compute_chi2(const PoseGraph3D& graph, int level,
                    const std::optional<RobustKernel>& robust_kernel) {
  return chi2_impl(graph, level, robust_kernel);
}

bool cholmod_available() noexcept { return detail::cholmod_built(); }

std::string_view to_string(GraphSolver solver) {
  switch (solver) {
    case GraphSolver::GaussNewton: return "gn";
    case GraphSolver::LevenbergMarquardt: return "lm";
    case GraphSolver::DogLeg: return "dogleg";
  }
  return "?";
}

GraphSolver parse_graph_solver(std::string_view text) {
  if (text == "gn" || text == "gauss-newton") return GraphSolver::GaussNewton;
  if (text == "lm" || text == "levenberg-marquardt" || text == "levmarq")
    return GraphSolver::LevenbergMarquardt;
  if (text == "dogleg" || text == "dog-leg") return GraphSolver::DogLeg;
  ROVE_CHECK_MSG(false, "unknown solver '{}' (expected gn, lm or dogleg)", text);
  return GraphSolver::LevenbergMarquardt;
}

std::string_view to_string(GraphTermination termination) {
  switch (termination) {
    case GraphTermination::Converged: return "converged";
    case GraphTermination::MaxIterations: return "max-iterations";
    case GraphTermination::NoProgress: return "no-progress";
    case GraphTermination::InvalidInput: return "invalid-input";
    case GraphTermination::NumericalFailure: return "numerical-failure";
  }
  return "?";
}

std::string_view to_string(LinearSolverType type) {
  switch (type) {
    case LinearSolverType::Auto: return "auto";
    case LinearSolverType::Eigen: return "eigen";
    case LinearSolverType::Cholmod: return "cholmod";
    case LinearSolverType::Block: return "block";
  }
  return "?";
}

}  // namespace rove
