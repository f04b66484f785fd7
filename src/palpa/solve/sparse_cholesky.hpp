// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Sparse Cholesky factorization A = L Lᵀ with CHOLMOD (SuiteSparse), behind the
// SymmetricFactorization interface (see factorization.hpp for the matrix
// convention, the automatic re-analysis and the statuses). No CHOLMOD type
// appears here: CHOLMOD is included only by sparse_cholesky.cpp.
//
// Both the supernodal and the simplicial factorization compute L Lᵀ, so a matrix
// that is not positive definite is always reported as NotPositiveDefinite (an
// LDLᵀ factorization would silently accept indefinite matrices). The supernodal
// factorization stops at the first bad pivot, so a failed attempt costs at most
// one factorization.
//
// Typical use (Newton loop):
//   SparseCholesky chol;
//   for (...) {
//     system.hessian(x, H);                       // same pattern every time
//     if (chol.factorize(H) != FactorStatus::Ok) { ... shift and retry ... }
//     dx = chol.solve(-g);
//   }

#include <memory>

#include "palpa/solve/factorization.hpp"

namespace palpa {

class SparseCholesky final : public SymmetricFactorization {
 public:
  // Supernodal factors use dense BLAS kernels on blocks of columns and win when
  // the factor is dense enough (large 3D meshes); simplicial wins on sparser
  // factors (small or 2D problems). Auto chooses from the analysis: supernodal
  // when it predicts ≥ 170 flops per nonzero of L (the break-even measured with
  // OpenBLAS, see sparse_cholesky.cpp).
  enum class Method { Auto, Supernodal, Simplicial };

  explicit SparseCholesky(Method method = Method::Auto);
  ~SparseCholesky() override;

  std::string_view name() const noexcept override;
  Method method() const noexcept { return method_; }

  // After an analysis: whether the factor is supernodal, the number of nonzeros
  // of L and the flop count of one numeric factorization (CHOLMOD's estimates).
  bool is_supernodal() const noexcept;
  double factor_nonzeros() const noexcept;
  double factor_flops() const noexcept;

 protected:
  FactorStatus do_analyze(const Eigen::SparseMatrix<double>& lower) override;
  Triangle factor_triangle() const noexcept override;
  FactorStatus do_factorize(const Eigen::SparseMatrix<double>& working) override;
  void do_solve(Eigen::MatrixXd& B) const override;

 private:
  struct Impl;
  Method method_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace palpa
