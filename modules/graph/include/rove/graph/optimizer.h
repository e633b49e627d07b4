#pragma once
/// \file
/// Pose-graph optimization on the manifold: Gauss–Newton, Levenberg–
/// Marquardt and Powell's dog-leg, with a sparse block Cholesky (rove's own
/// on dense pose-sized blocks, Eigen's simplicial LLᵀ, or SuiteSparse
/// CHOLMOD's supernodal factorization when rove was built with it) under a
/// fill-reducing block ordering (AMD on the vertex graph).
///
/// The cost is χ² = Σ_edges ρ_e(e_eᵀ Ω_e e_e) with the error of
/// pose_graph.h, ρ_e the edge's robust kernel (identity for plain least
/// squares). Updates are on the right: X ← X·exp(δ). Robust kernels enter as
/// iteratively reweighted least squares with weight ρ'(s), as g2o does.
/// The gauge is fixed by the anchored vertices; a graph without any gets its
/// lowest-id optimized vertex anchored for the run (reported in the result).
///
///   rove::GraphOptimizerOptions options;            // LM, 100 iterations
///   auto result = rove::optimize(graph, options);   // poses updated in place
///   if (!result.ok()) std::cerr << result.message;  // names edges / vertices

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rove/graph/pose_graph.h"

namespace rove {

/// Nonlinear least-squares method.
enum class GraphSolver {
  GaussNewton,         ///< full steps, no damping (fails on a singular system)
  LevenbergMarquardt,  ///< Marquardt-scaled damping, Nielsen's update; χ² never increases
  DogLeg,              ///< Powell's dog-leg trust region; χ² never increases
};

/// Sparse Cholesky back-end.
enum class LinearSolverType {
  Auto,     ///< by the factor's density: Block when sparse, CHOLMOD when dense (if available)
  Eigen,    ///< Eigen's SimplicialLLT (scalar, up-looking)
  Cholmod,  ///< SuiteSparse CHOLMOD (supernodal); InvalidArgument if rove was built without it
  Block,    ///< rove's left-looking Cholesky on dense pose-sized blocks (3×3 or 6×6)
};

/// Why an optimization stopped.
enum class GraphTermination {
  Converged,         ///< a tolerance was met (the message says which)
  MaxIterations,     ///< max_iterations reached first
  NoProgress,        ///< no further decrease possible (damping / trust region exhausted)
  InvalidInput,      ///< the problem cannot be set up (see issues)
  NumericalFailure,  ///< NaN, or a rank-deficient system (see issues)
};

/// What is wrong with one edge or vertex when an optimization fails.
struct GraphIssue {
  enum class Kind {
    NonFiniteResidual,   ///< the edge's error is NaN/Inf
    NonFiniteJacobian,   ///< the edge's Jacobian has NaN/Inf
    DisconnectedVertex,  ///< not connected to an anchor through the edges used
    RankDeficientBlock,  ///< the vertex's block of the normal equations is singular
    NotPositiveDefinite, ///< the factorization broke down at this vertex
  };
  Kind kind;
  std::size_t edge = static_cast<std::size_t>(-1);  ///< edge index, or -1 for a vertex issue
  VertexId vertex = 0;                              ///< vertex concerned (edge: its `from`)
  std::string message;                              ///< one line naming edge/vertex and values
};

/// One iteration (one linear solve and one trial step).
struct GraphIteration {
  int iteration = 0;         ///< 1-based
  double chi2 = 0.0;         ///< χ² after the iteration (the trial's if it was rejected)
  double damping = 0.0;      ///< LM: λ; dog-leg: trust radius; GN: 0
  double step_norm = 0.0;    ///< ‖δ‖
  double gain_ratio = 0.0;   ///< actual / predicted decrease
  bool accepted = false;     ///< the step was taken
};

/// Wall-clock seconds spent in each phase.
struct GraphTiming {
  double setup = 0.0;       ///< indexing, ordering, symbolic analysis
  double linearize = 0.0;   ///< residuals, Jacobians, normal equations
  double factorize = 0.0;   ///< numeric Cholesky and triangular solves
  double evaluate = 0.0;    ///< χ² of trial steps
  double total = 0.0;       ///< everything in optimize()
};

/// Options of optimize(); defaults in the comments.
struct GraphOptimizerOptions {
  /// Method. Powell's dog-leg by default: it reaches the same χ² as LM
  /// (within 1e-9 relative on the seven benchmark graphs) in as many or
  /// fewer iterations, and a rejected step costs it no factorization (the
  /// Gauss–Newton step is kept, only the trust radius shrinks), where LM
  /// refactorizes with a larger λ (intel_carlone: 5 factorizations vs 61).
  GraphSolver solver = GraphSolver::DogLeg;
  /// Cholesky back-end. The first problem that uses CHOLMOD loads it (and
  /// its BLAS). optimize() changes no process-wide setting: the BLAS kernel
  /// choice and CHOLMOD's OpenMP threads are the caller's opt-in
  /// (rove/graph/blas_tuning.h).
  LinearSolverType linear_solver = LinearSolverType::Auto;
  int max_iterations = 100;          ///< linear solves at most (≥ 0)
  double function_tolerance = 1e-8;  ///< stop when a step changes χ² by ≤ this × χ² (an accepted
                                     ///< step is kept; as Ceres' function_tolerance)
  double gradient_tolerance = 1e-12; ///< stop when max |Jᵀ W e| ≤ this
  double step_tolerance = 1e-12;     ///< stop when ‖δ‖ ≤ this × (‖t‖ + this), t all translations
  double initial_lambda = 1e-5;      ///< LM: initial λ, relative to diag(JᵀWJ)
  double initial_trust_radius = 1e4; ///< dog-leg: initial radius of the trust region
  int level = 0;                     ///< only edges with this level are used
  int num_threads = 1;               ///< threads for linearization and χ² (0: all hardware
                                     ///< threads, at most rove::kMaxThreads); one team per
                                     ///< run; results do not depend on it (per-edge terms are
                                     ///< summed in edge order)
  std::optional<RobustKernel> robust_kernel;  ///< when set, replaces every edge's own kernel
  std::optional<VertexId> anchor;    ///< vertex to hold fixed for this run (besides fixed ones)
  /// Dog-leg and Gauss–Newton, on graphs whose factorization is dense
  /// (≥ 100 flops per factor entry: the 3D sets): when the last accepted
  /// step's gain ratio was within reuse_gain_window of 1 (the quadratic
  /// model held, so JᵀWJ changed little), solve for the next step by
  /// conjugate gradients preconditioned with the previous factorization
  /// instead of factorizing again. CG stops at ‖Hδ + g‖ ≤ reuse_tolerance·‖g‖;
  /// when its first iteration leaves over 20 % of the residual, or it has
  /// not converged within reuse_max_cg_iterations, the step is factorized as
  /// usual. The final χ² is the same as without reuse to ~1e-13 relative
  /// on the benchmark graphs (the last steps are solved to 1e-6 of ‖g‖).
  bool reuse_factorization = true;
  double reuse_gain_window = 0.5;
  double reuse_tolerance = 1e-6;
  int reuse_max_cg_iterations = 10;
};

/// What optimize() did.
struct GraphOptimizerResult {
  GraphTermination termination = GraphTermination::InvalidInput;
  std::string message;           ///< one line: the reason
  double initial_chi2 = 0.0;     ///< χ² before optimizing
  double final_chi2 = 0.0;       ///< χ² of the returned poses
  int iterations = 0;            ///< trial steps (LM: one factorization each)
  int factorizations = 0;        ///< numeric Cholesky factorizations
  int reused_factorizations = 0; ///< steps solved by CG on an earlier factorization
  int cg_iterations = 0;         ///< CG iterations of those solves (and of failed tries)
  int accepted_steps = 0;        ///< steps taken
  std::vector<GraphIteration> history;  ///< one entry per iteration
  GraphTiming timing;
  std::vector<GraphIssue> issues;       ///< offending edges/vertices on failure
  LinearSolverType linear_solver = LinearSolverType::Block;  ///< back-end used
  std::size_t num_edges_used = 0;       ///< edges of the chosen level
  std::size_t num_vertices_optimized = 0;
  std::size_t num_vertices_fixed = 0;   ///< anchors touching the edges used
  std::optional<VertexId> gauge_anchor; ///< vertex anchored because none was fixed
  std::size_t hessian_nonzeros = 0;     ///< stored entries of the upper triangle
  std::size_t factor_nonzeros = 0;      ///< entries of the Cholesky factor

  /// True only when the optimization converged (GraphTermination::Converged),
  /// as ok() means for every rove result (registration included).
  bool ok() const noexcept { return termination == GraphTermination::Converged; }
  /// True when the returned poses are an optimum or at least an improvement
  /// on the start (Converged, MaxIterations, NoProgress): worth writing out,
  /// with the termination reported as an issue when not Converged.
  bool improved() const noexcept {
    return termination == GraphTermination::Converged ||
           termination == GraphTermination::MaxIterations ||
           termination == GraphTermination::NoProgress;
  }
};

/// Optimizes the non-fixed vertices touched by edges of options.level, in
/// place. On InvalidInput the graph is untouched; on NumericalFailure it
/// holds the last accepted poses. Throws InvalidArgument for bad options,
/// rove::Interrupted (graph untouched) when the command line's Ctrl-C handler
/// fired between two iterations. Thread-safety: calls on different graphs may
/// run at once on different threads (no process-wide state is changed).
GraphOptimizerResult optimize(PoseGraph2D& graph, const GraphOptimizerOptions& options = {});
/// 3D overload.
GraphOptimizerResult optimize(PoseGraph3D& graph, const GraphOptimizerOptions& options = {});

/// χ² of the graph with the edges of `level` (each edge's kernel, or
/// `robust_kernel` for all when given).
double compute_chi2(const PoseGraph2D& graph, int level = 0,
                    const std::optional<RobustKernel>& robust_kernel = std::nullopt);
/// 3D overload.
double compute_chi2(const PoseGraph3D& graph, int level = 0,
                    const std::optional<RobustKernel>& robust_kernel = std::nullopt);

/// True if rove was built with SuiteSparse CHOLMOD.
bool cholmod_available() noexcept;

/// "gn", "lm", "dogleg".
std::string_view to_string(GraphSolver solver);
/// Parses "gn"/"gauss-newton", "lm"/"levenberg-marquardt", "dogleg"/"dog-leg";
/// throws InvalidArgument otherwise.
GraphSolver parse_graph_solver(std::string_view text);
/// "converged", "max-iterations", "no-progress", "invalid-input", "numerical-failure".
std::string_view to_string(GraphTermination termination);
/// "auto", "eigen", "cholmod".
std::string_view to_string(LinearSolverType type);

}  // namespace rove
