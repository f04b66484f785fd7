// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/sparse_cholesky.hpp"

#include <cholmod.h>
#include <fmt/format.h>

#include <algorithm>

#include "palpa/core/error.hpp"

namespace palpa {

namespace {

// Auto chooses a supernodal factor when the analysis predicts at least this many
// flops per nonzero of L. Measured with Debian's OpenBLAS (palpa_bench_solve,
// simplicial / supernodal factorization time): 2D elasticity-like (the
// axisymmetric pattern) fl/lnz 125 → 0.68, 221 → 1.52; 3D elasticity-like 109
// → 0.54, 280 → 2.06; both break even near 165–170. (The scalar 2D Laplacian
// breaks even near 240, but palpa factors vector problems.) With the
// reference BLAS the break-even was near 300.
constexpr double kSupernodalSwitch = 170.0;

// A non-owning CHOLMOD view of a compressed, sorted Eigen matrix.
cholmod_sparse view_of(const Eigen::SparseMatrix<double>& A, int stype) {
  cholmod_sparse s{};
  s.nrow = static_cast<std::size_t>(A.rows());
  s.ncol = static_cast<std::size_t>(A.cols());
  s.nzmax = static_cast<std::size_t>(A.nonZeros());
  // CHOLMOD takes non-const pointers but only reads the matrix it factors.
  s.p = const_cast<int*>(A.outerIndexPtr());
  s.i = const_cast<int*>(A.innerIndexPtr());
  s.nz = nullptr;
  s.x = const_cast<double*>(A.valuePtr());
  s.z = nullptr;
  s.stype = stype;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}

// Settings shared by every cholmod_common this file creates.
void start_common(cholmod_common& common, SparseCholesky::Method method) {
  cholmod_start(&common);
  // Failures are returned as statuses; CHOLMOD must not print.
  common.print = 0;
  // L Lᵀ also for simplicial factors, so that indefinite matrices are detected
  // (the simplicial LDLᵀ only fails on an exactly zero pivot).
  common.final_ll = 1;
  common.quick_return_if_not_posdef = 1;
  switch (method) {
    case SparseCholesky::Method::Auto:
      common.supernodal = CHOLMOD_AUTO;
      common.supernodal_switch = kSupernodalSwitch;
      break;
    case SparseCholesky::Method::Supernodal:
      common.supernodal = CHOLMOD_SUPERNODAL;
      break;
    case SparseCholesky::Method::Simplicial:
      common.supernodal = CHOLMOD_SIMPLICIAL;
      break;
  }
}

bool is_memory_failure(int status) {
  return status == CHOLMOD_OUT_OF_MEMORY || status == CHOLMOD_TOO_LARGE;
}

}  // namespace

struct SparseCholesky::Impl {
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  double lnz = 0.0;
  double flops = 0.0;

  explicit Impl(Method method) { start_common(common, method); }
  ~Impl() {
    free_factor();
    cholmod_finish(&common);
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  void free_factor() {
    if (factor != nullptr) cholmod_free_factor(&factor, &common);
    factor = nullptr;
  }
};

SparseCholesky::SparseCholesky(Method method)
    : method_(method), impl_(std::make_unique<Impl>(method)) {}

SparseCholesky::~SparseCholesky() = default;

std::string_view SparseCholesky::name() const noexcept {
  switch (method_) {
    case Method::Supernodal:
      return "cholmod-supernodal";
    case Method::Simplicial:
      return "cholmod-simplicial";
    case Method::Auto:
      break;
  }
  return "cholmod";
}

bool SparseCholesky::is_supernodal() const noexcept {
  return impl_->factor != nullptr && impl_->factor->is_super != 0;
}
double SparseCholesky::factor_nonzeros() const noexcept {
  return impl_->lnz;
}
double SparseCholesky::factor_flops() const noexcept {
  return impl_->flops;
}

FactorStatus SparseCholesky::do_analyze(const Eigen::SparseMatrix<double>& lower) {
  impl_->free_factor();
  cholmod_sparse A = view_of(lower, -1);
  impl_->factor = cholmod_analyze(&A, &impl_->common);
  const int st = impl_->common.status;
  if (impl_->factor == nullptr || st < CHOLMOD_OK) {
    impl_->free_factor();
    if (is_memory_failure(st)) return FactorStatus::OutOfMemory;
    throw Error(ErrorKind::Internal, fmt::format("CHOLMOD analysis failed (status {})", st));
  }
  impl_->lnz = impl_->common.lnz;
  impl_->flops = impl_->common.fl;
  return FactorStatus::Ok;
}

SymmetricFactorization::Triangle SparseCholesky::factor_triangle() const noexcept {
  // CHOLMOD permutes the matrix with one transpose when a supernodal factor gets
  // the upper triangle and a simplicial one the lower triangle (two otherwise).
  return is_supernodal() ? Triangle::Upper : Triangle::Lower;
}

FactorStatus SparseCholesky::do_factorize(const Eigen::SparseMatrix<double>& working) {
  cholmod_sparse A = view_of(working, factor_triangle() == Triangle::Upper ? 1 : -1);
  cholmod_factorize(&A, impl_->factor, &impl_->common);
  const int st = impl_->common.status;
  if (st == CHOLMOD_NOT_POSDEF) return FactorStatus::NotPositiveDefinite;
  if (st < CHOLMOD_OK) {
    if (is_memory_failure(st)) return FactorStatus::OutOfMemory;
    throw Error(ErrorKind::Internal, fmt::format("CHOLMOD factorization failed (status {})", st));
  }
  if (impl_->factor->minor < impl_->factor->n) return FactorStatus::NotPositiveDefinite;
  return FactorStatus::Ok;
}

void SparseCholesky::do_solve(Eigen::MatrixXd& B) const {
  // A cholmod_common of its own, so that concurrent solves share no workspace.
  cholmod_common common{};
  start_common(common, method_);
  cholmod_dense b{};
  b.nrow = static_cast<std::size_t>(B.rows());
  b.ncol = static_cast<std::size_t>(B.cols());
  b.nzmax = b.nrow * b.ncol;
  b.d = b.nrow;
  b.x = B.data();
  b.z = nullptr;
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, impl_->factor, &b, &common);
  const int st = common.status;
  if (X == nullptr) {
    cholmod_finish(&common);
    throw Error(ErrorKind::Internal, fmt::format("CHOLMOD solve failed (status {})", st));
  }
  const double* x = static_cast<const double*>(X->x);
  std::copy(x, x + b.nzmax, B.data());
  cholmod_free_dense(&X, &common);
  cholmod_finish(&common);
}

}  // namespace palpa
