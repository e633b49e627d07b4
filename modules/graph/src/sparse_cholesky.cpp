// Sparse Cholesky back-ends for the pose-graph optimizer.
#include "sparse_cholesky.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include "rove/core/check.h"
#include "rove/core/error.h"

#ifdef ROVE_HAVE_CHOLMOD
#include <cholmod.h>
#endif

namespace rove::detail {

struct SparseCholesky::Impl {
  // Ordering is done by the caller (block AMD), so both back-ends factorize
  // in the natural order of the matrix they get.
  Eigen::SimplicialLLT<Matrix, Eigen::Upper, Eigen::NaturalOrdering<int>> eigen;
#ifdef ROVE_HAVE_CHOLMOD
  cholmod_common common;
  cholmod_factor* factor = nullptr;
  bool started = false;
#endif
};

namespace {
#ifdef ROVE_HAVE_CHOLMOD
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

SparseCholesky::SparseCholesky(LinearSolverType type) : impl_(std::make_unique<Impl>()) {
#ifdef ROVE_HAVE_CHOLMOD
  type_ = type == LinearSolverType::Auto ? LinearSolverType::Cholmod : type;
  if (type_ == LinearSolverType::Cholmod) {
    cholmod_start(&impl_->common);
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
  type_ = LinearSolverType::Eigen;
#endif
}

SparseCholesky::~SparseCholesky() {
#ifdef ROVE_HAVE_CHOLMOD
  if (impl_->factor) cholmod_free_factor(&impl_->factor, &impl_->common);
  if (impl_->started) cholmod_finish(&impl_->common);
#endif
}

void SparseCholesky::analyze(const Matrix& upper) {
#ifdef ROVE_HAVE_CHOLMOD
  if (type_ == LinearSolverType::Cholmod) {
    if (impl_->factor) cholmod_free_factor(&impl_->factor, &impl_->common);
    cholmod_sparse a = view_of(upper);
    impl_->factor = cholmod_analyze(&a, &impl_->common);
    if (!impl_->factor) {
      throw NumericError("CHOLMOD symbolic analysis failed (status " +
                         std::to_string(impl_->common.status) + ")");
    }
    return;
  }
#endif
  impl_->eigen.analyzePattern(upper);
}

std::optional<long> SparseCholesky::factorize(const Matrix& upper) {
#ifdef ROVE_HAVE_CHOLMOD
  if (type_ == LinearSolverType::Cholmod) {
    cholmod_sparse a = view_of(upper);
    cholmod_factorize(&a, impl_->factor, &impl_->common);
    if (impl_->common.status == CHOLMOD_NOT_POSDEF) return static_cast<long>(impl_->factor->minor);
    if (impl_->common.status < CHOLMOD_OK) {
      throw NumericError("CHOLMOD numeric factorization failed (status " +
                         std::to_string(impl_->common.status) + ")");
    }
    return std::nullopt;
  }
#endif
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
    cholmod_dense* xd = cholmod_solve(CHOLMOD_A, impl_->factor, &bd, &impl_->common);
    if (!xd) throw NumericError("CHOLMOD solve failed");
    x = Eigen::Map<const Eigen::VectorXd>(static_cast<const double*>(xd->x), b.size());
    cholmod_free_dense(&xd, &impl_->common);
    return;
  }
#endif
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
  return static_cast<std::size_t>(impl_->eigen.matrixL().nestedExpression().nonZeros());
}

std::vector<int> fill_reducing_order(const Eigen::SparseMatrix<int, Eigen::ColMajor, int>& pattern,
                                     bool use_cholmod) {
  const int n = static_cast<int>(pattern.rows());
  std::vector<int> perm(static_cast<std::size_t>(n));
#ifdef ROVE_HAVE_CHOLMOD
  if (use_cholmod && n > 0) {
    // Upper triangle of the pattern as a CHOLMOD matrix of ones.
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> upper =
        pattern.cast<double>().triangularView<Eigen::Upper>();
    upper.makeCompressed();
    cholmod_common c;
    cholmod_start(&c);
    c.print = 0;
    c.error_handler = nullptr;
    c.nmethods = 2;
    c.method[0].ordering = CHOLMOD_AMD;
    c.method[1].ordering = CHOLMOD_METIS;
    c.postorder = 1;
    cholmod_sparse a = view_of(upper);
    cholmod_factor* f = cholmod_analyze(&a, &c);
    const bool ok = f != nullptr;
    if (ok) {
      const int* p = static_cast<const int*>(f->Perm);
      std::copy(p, p + n, perm.begin());
      cholmod_free_factor(&f, &c);
    }
    cholmod_finish(&c);
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
  return true;
#else
  return false;
#endif
}

}  // namespace rove::detail
