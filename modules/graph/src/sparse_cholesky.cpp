// Sparse Cholesky back-ends for the pose-graph optimizer.
#include "sparse_cholesky.h"

#include "block_cholesky.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/graph/blas_tuning.h"

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>

#ifdef ROVE_HAVE_CHOLMOD
#include <dlfcn.h>

#include <cholmod.h>
#endif

namespace rove::detail {


namespace {
#ifdef ROVE_HAVE_CHOLMOD
// CHOLMOD is loaded when a problem first needs it, not when the process
// starts: with it come BLAS, LAPACK, libgfortran, METIS and an OpenMP
// runtime, whose symbol relocation costs 3-5 ms of CPU at every start
// (OpenBLAS alone ~15,000 relocations) — more than the whole solve of a
// 100-vertex graph. Programs that never meet a graph dense enough for
// CHOLMOD (see Engine: flops per factor entry) never pay for it.
struct CholmodApi {
  decltype(&::cholmod_start) start = nullptr;
  decltype(&::cholmod_finish) finish = nullptr;
  decltype(&::cholmod_analyze) analyze = nullptr;
  decltype(&::cholmod_factorize) factorize = nullptr;
  decltype(&::cholmod_solve) solve = nullptr;
  decltype(&::cholmod_free_factor) free_factor = nullptr;
  decltype(&::cholmod_free_dense) free_dense = nullptr;
  // The OpenMP runtime CHOLMOD is linked to (absent when it has none).
  void (*omp_set_max_active_levels)(int) = nullptr;
  void (*omp_set_dynamic)(int) = nullptr;
  void (*omp_set_num_threads)(int) = nullptr;
  bool omp = false;
  bool ok = false;
  std::string error;
};

template <class F>
void bind(void* handle, F& f, const char* name) {
  void* sym = dlsym(handle, name);
  static_assert(sizeof(f) == sizeof(sym));
  std::memcpy(&f, &sym, sizeof(f));  // object to function pointer (POSIX)
}

// The thread cap asked for by tune_blas_threads(), applied when CHOLMOD
// loads (0: none asked for; CHOLMOD's OpenMP keeps its defaults).
std::atomic<int> g_requested_blas_threads{0};
// CHOLMOD's numeric work runs one call at a time in the process: the BLAS
// under it need not be reentrant. Debian 12's serial OpenBLAS (0.3.21) is
// not: two optimizations factorizing at once on different threads corrupted
// each other's factors (a final χ² off by 1.85e3 in one run of ten), so the
// test "two optimize() calls at once equal serial runs" failed. A mutex here
// is rove's own state, not a process-wide setting of someone else's library.
std::mutex g_cholmod_mutex;

// Set once CHOLMOD's functions are bound (cholmod_api() has run).
std::atomic<const CholmodApi*> g_loaded_api{nullptr};

void apply_openmp_cap(const CholmodApi& api, int threads) {
  if (!api.omp || threads < 1) return;
  if (threads == 1) {
    api.omp_set_max_active_levels(0);
  } else {
    api.omp_set_dynamic(1);
    api.omp_set_num_threads(threads);
  }
}

const CholmodApi& cholmod_api() {
  static const CholmodApi api = [] {
    CholmodApi a;
    void* h = dlopen(ROVE_CHOLMOD_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
      const char* e = dlerror();
      a.error = e ? e : "dlopen failed";
      return a;
    }
    bind(h, a.start, "cholmod_start");
    bind(h, a.finish, "cholmod_finish");
    bind(h, a.analyze, "cholmod_analyze");
    bind(h, a.factorize, "cholmod_factorize");
    bind(h, a.solve, "cholmod_solve");
    bind(h, a.free_factor, "cholmod_free_factor");
    bind(h, a.free_dense, "cholmod_free_dense");
    a.ok = a.start && a.finish && a.analyze && a.factorize && a.solve && a.free_factor &&
           a.free_dense;
    if (!a.ok) a.error = std::string(ROVE_CHOLMOD_SONAME) + " lacks a cholmod_* function";
    // dlsym on the handle searches CHOLMOD and then its dependencies.
    bind(h, a.omp_set_max_active_levels, "omp_set_max_active_levels");
    bind(h, a.omp_set_dynamic, "omp_set_dynamic");
    bind(h, a.omp_set_num_threads, "omp_set_num_threads");
    a.omp = a.omp_set_max_active_levels && a.omp_set_dynamic && a.omp_set_num_threads;
    apply_openmp_cap(a, g_requested_blas_threads.load());
    return a;  // the library stays loaded for the life of the process
  }();
  g_loaded_api.store(&api);
  return api;
}

const CholmodApi& loaded_cholmod() {
  const CholmodApi& api = cholmod_api();
  if (!api.ok) throw NumericError("cannot load SuiteSparse CHOLMOD: " + api.error);
  return api;
}

cholmod_sparse view_of(const SparseCholesky::Matrix& m) {
  cholmod_sparse a{};
  a.nrow = static_cast<std::size_t>(m.rows());
  a.ncol = static_cast<std::size_t>(m.cols());
  a.nzmax = static_cast<std::size_t>(m.nonZeros());
  a.p = const_cast<int*>(m.outerIndexPtr());
  a.i = const_cast<int*>(m.innerIndexPtr());
  a.x = const_cast<double*>(m.valuePtr());
  a.stype = 1;  // upper triangle stored
  a.itype = CHOLMOD_INT;
  a.xtype = CHOLMOD_REAL;
  a.dtype = CHOLMOD_DOUBLE;
  a.sorted = 1;
  a.packed = 1;
  return a;
}
#endif
}  // namespace

struct SparseCholesky::Impl {
  // Ordering is done by the caller (block AMD), so both back-ends factorize
  // in the natural order of the matrix they get.
  Eigen::SimplicialLLT<Matrix, Eigen::Upper, Eigen::NaturalOrdering<int>> eigen;
  BlockCholesky<3> block3;
  BlockCholesky<6> block6;
  int block_size = 0;
#ifdef ROVE_HAVE_CHOLMOD
  const CholmodApi* api = nullptr;
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  bool started = false;
#endif
};

SparseCholesky::SparseCholesky(LinearSolverType type, int block_size)
    : impl_(std::make_unique<Impl>()) {
  impl_->block_size = block_size;
  if (type == LinearSolverType::Block) {
    ROVE_CHECK_MSG(block_size == 3 || block_size == 6,
                   "the block Cholesky takes 3x3 or 6x6 blocks, got {}", block_size);
  }
#ifdef ROVE_HAVE_CHOLMOD
  type_ = type == LinearSolverType::Auto
              ? (cholmod_api().ok ? LinearSolverType::Cholmod : LinearSolverType::Block)
              : type;
  if (type_ == LinearSolverType::Cholmod) {
    impl_->api = &loaded_cholmod();
    impl_->api->start(&impl_->common);
    impl_->started = true;
    impl_->common.nmethods = 1;
    impl_->common.method[0].ordering = CHOLMOD_NATURAL;
    impl_->common.postorder = 0;
    impl_->common.supernodal = CHOLMOD_AUTO;
    impl_->common.print = 0;
    impl_->common.error_handler = nullptr;
    impl_->common.quick_return_if_not_posdef = 1;
  }
#else
  ROVE_CHECK_MSG(type != LinearSolverType::Cholmod,
                 "this build of rove has no SuiteSparse CHOLMOD; use the Eigen solver");
  type_ = type == LinearSolverType::Auto ? LinearSolverType::Block : type;
#endif
  if (type_ == LinearSolverType::Block && block_size != 3 && block_size != 6)
    type_ = LinearSolverType::Eigen;
}

SparseCholesky::~SparseCholesky() {
#ifdef ROVE_HAVE_CHOLMOD
  if (impl_->factor) impl_->api->free_factor(&impl_->factor, &impl_->common);
  if (impl_->started) impl_->api->finish(&impl_->common);
#endif
}

void SparseCholesky::analyze(const Matrix& upper) {
#ifdef ROVE_HAVE_CHOLMOD
  if (type_ == LinearSolverType::Cholmod) {
    if (impl_->factor) impl_->api->free_factor(&impl_->factor, &impl_->common);
    cholmod_sparse a = view_of(upper);
    const std::lock_guard lock(g_cholmod_mutex);
    impl_->factor = impl_->api->analyze(&a, &impl_->common);
    if (!impl_->factor) {
      throw NumericError("CHOLMOD symbolic analysis failed (status " +
                         std::to_string(impl_->common.status) + ")");
    }
    return;
  }
#endif
  if (type_ == LinearSolverType::Block) {
    if (impl_->block_size == 3) impl_->block3.analyze(upper);
    else impl_->block6.analyze(upper);
    return;
  }
  impl_->eigen.analyzePattern(upper);
}

std::optional<long> SparseCholesky::factorize(const Matrix& upper) {
#ifdef ROVE_HAVE_CHOLMOD
  if (type_ == LinearSolverType::Cholmod) {
    cholmod_sparse a = view_of(upper);
    const std::lock_guard lock(g_cholmod_mutex);
    impl_->api->factorize(&a, impl_->factor, &impl_->common);
    if (impl_->common.status == CHOLMOD_NOT_POSDEF) return static_cast<long>(impl_->factor->minor);
    if (impl_->common.status < CHOLMOD_OK) {
      throw NumericError("CHOLMOD numeric factorization failed (status " +
                         std::to_string(impl_->common.status) + ")");
    }
    return std::nullopt;
  }
#endif
  if (type_ == LinearSolverType::Block) {
    return impl_->block_size == 3 ? impl_->block3.factorize(upper) : impl_->block6.factorize(upper);
  }
  impl_->eigen.factorize(upper);
  if (impl_->eigen.info() != Eigen::Success) return -1L;
  return std::nullopt;
}

void SparseCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
#ifdef ROVE_HAVE_CHOLMOD
  if (type_ == LinearSolverType::Cholmod) {
    cholmod_dense bd{};
    bd.nrow = static_cast<std::size_t>(b.size());
    bd.ncol = 1;
    bd.nzmax = bd.nrow;
    bd.d = bd.nrow;
    bd.x = const_cast<double*>(b.data());
    bd.xtype = CHOLMOD_REAL;
    bd.dtype = CHOLMOD_DOUBLE;
    const std::lock_guard lock(g_cholmod_mutex);
    cholmod_dense* xd = impl_->api->solve(CHOLMOD_A, impl_->factor, &bd, &impl_->common);
    if (!xd) throw NumericError("CHOLMOD solve failed");
    x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(xd->x), b.size());
    impl_->api->free_dense(&xd, &impl_->common);
    return;
  }
#endif
  if (type_ == LinearSolverType::Block) {
    if (impl_->block_size == 3) impl_->block3.solve(b, x);
    else impl_->block6.solve(b, x);
    return;
  }
  x = impl_->eigen.solve(b);
}

std::size_t SparseCholesky::factor_nonzeros() const {
#ifdef ROVE_HAVE_CHOLMOD
  if (type_ == LinearSolverType::Cholmod) {
    if (!impl_->factor) return 0;
    if (impl_->factor->is_super) return impl_->factor->xsize;
    return impl_->factor->nzmax;
  }
#endif
  if (type_ == LinearSolverType::Block) {
    return impl_->block_size == 3 ? impl_->block3.factor_nonzeros()
                                  : impl_->block6.factor_nonzeros();
  }
  return static_cast<std::size_t>(impl_->eigen.matrixL().nestedExpression().nonZeros());
}

std::vector<int> fill_reducing_order(const Eigen::SparseMatrix<int, Eigen::ColMajor, int>& pattern,
                                     bool use_cholmod) {
  const int n = static_cast<int>(pattern.rows());
  std::vector<int> perm(static_cast<std::size_t>(n));
#ifdef ROVE_HAVE_CHOLMOD
  if (use_cholmod && n > 0 && cholmod_api().ok) {
    const CholmodApi& api = cholmod_api();
    // Upper triangle of the pattern as a CHOLMOD matrix of ones.
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> upper =
        pattern.cast<double>().triangularView<Eigen::Upper>();
    upper.makeCompressed();
    cholmod_common c;
    api.start(&c);
    c.print = 0;
    c.error_handler = nullptr;
    c.nmethods = 2;
    c.method[0].ordering = CHOLMOD_AMD;
    c.method[1].ordering = CHOLMOD_METIS;
    c.postorder = 1;
    cholmod_sparse a = view_of(upper);
    cholmod_factor* f = api.analyze(&a, &c);
    const bool ok = f != nullptr;
    if (ok) {
      const int* p = static_cast<const int*>(f->Perm);
      std::copy(p, p + n, perm.begin());
      api.free_factor(&f, &c);
    }
    api.finish(&c);
    if (ok) return perm;
  }
#else
  (void)use_cholmod;
#endif
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> p;
  Eigen::AMDOrdering<int> amd;
  amd(pattern, p);  // p.indices()[new] = old
  for (int k = 0; k < n; ++k) perm[static_cast<std::size_t>(k)] = p.indices()[k];
  return perm;
}

bool cholmod_built() noexcept {
#ifdef ROVE_HAVE_CHOLMOD
  return cholmod_api().ok;
#else
  return false;
#endif
}

CholeskyCost block_cholesky_cost(const Eigen::SparseMatrix<int, Eigen::ColMajor, int>& pattern,
                                 const std::vector<int>& perm, int block_size) {
  // Elimination tree and row subtrees (Liu 1986; Davis, "Direct Methods for
  // Sparse Linear Systems", 2006, §4.1 and §4.4): for every row k of L, walk
  // up the tree from each entry A(i, k), i < k, until a node already marked
  // for k; each node passed is a nonzero L(k, j). O(nnz(L)) over blocks.
  const int n = static_cast<int>(pattern.rows());
  std::vector<int> pinv(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) pinv[static_cast<std::size_t>(perm[static_cast<std::size_t>(k)])] = k;
  std::vector<std::vector<int>> upper(static_cast<std::size_t>(n));
  for (int c = 0; c < pattern.outerSize(); ++c) {
    for (Eigen::SparseMatrix<int, Eigen::ColMajor, int>::InnerIterator it(pattern, c); it; ++it) {
      const int i = pinv[static_cast<std::size_t>(it.index())], k = pinv[static_cast<std::size_t>(c)];
      if (i < k) upper[static_cast<std::size_t>(k)].push_back(i);
    }
  }
  std::vector<int> parent(static_cast<std::size_t>(n), -1), ancestor(static_cast<std::size_t>(n), -1),
      mark(static_cast<std::size_t>(n), -1);
  std::vector<long> count(static_cast<std::size_t>(n), 1);  // the diagonal block
  for (int k = 0; k < n; ++k) {
    for (int i : upper[static_cast<std::size_t>(k)]) {  // elimination tree, path compression
      while (i != -1 && i < k) {
        const int next = ancestor[static_cast<std::size_t>(i)];
        ancestor[static_cast<std::size_t>(i)] = k;
        if (next == -1) parent[static_cast<std::size_t>(i)] = k;
        i = next;
      }
    }
    mark[static_cast<std::size_t>(k)] = k;
    for (int i : upper[static_cast<std::size_t>(k)]) {  // row subtree of k
      for (int j = i; mark[static_cast<std::size_t>(j)] != k; j = parent[static_cast<std::size_t>(j)]) {
        mark[static_cast<std::size_t>(j)] = k;
        ++count[static_cast<std::size_t>(j)];
      }
    }
  }
  CholeskyCost cost;
  const double b = block_size;
  for (long c : count) {
    // Scalar column m of the block column: b·c − m entries, and about as
    // many squared multiply-adds to apply it (the count CHOLMOD uses).
    for (int m = 0; m < block_size; ++m) {
      const double len = b * static_cast<double>(c) - m;
      cost.factor_nonzeros += len;
      cost.flops += len * len;
    }
  }
  return cost;
}

}  // namespace rove::detail

namespace rove {

void configure_blas_for_this_cpu() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (std::getenv("OPENBLAS_CORETYPE") != nullptr) return;
  __builtin_cpu_init();
  const char* core = nullptr;
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl")) {
    core = "SkylakeX";
  } else if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    core = "Haswell";
  }
  if (core) setenv("OPENBLAS_CORETYPE", core, 0);
#endif
}

void tune_blas_threads(int num_threads) {
  ROVE_CHECK_MSG(num_threads >= 1, "tune_blas_threads: num_threads must be >= 1, got {}",
                 num_threads);
#ifdef ROVE_HAVE_CHOLMOD
  detail::g_requested_blas_threads.store(num_threads);
  if (const auto* api = detail::g_loaded_api.load()) detail::apply_openmp_cap(*api, num_threads);
#endif
}

}  // namespace rove
