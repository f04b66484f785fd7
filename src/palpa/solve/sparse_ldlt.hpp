// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Sparse LDLᵀ factorization with Eigen's SimplicialLDLT (AMD ordering, no
// pivoting), behind the SymmetricFactorization interface (see factorization.hpp).
// A fallback and a reference for SparseCholesky: slower on large or 3D
// problems, but it can also factor symmetric indefinite matrices whose leading
// minors are all nonsingular (e.g. some saddle-point systems), which Cholesky
// cannot. Without pivoting that is numerically fragile: prefer it only where the
// matrix is known to be well behaved.

#include <memory>

#include "palpa/solve/factorization.hpp"

namespace palpa {

class SparseLdlt final : public SymmetricFactorization {
 public:
  // RequirePositive: any pivot d_k ≤ 0 gives NotPositiveDefinite (the same
  // contract as SparseCholesky). AllowIndefinite: negative pivots are accepted;
  // only a zero pivot fails (Singular).
  enum class Definiteness { RequirePositive, AllowIndefinite };

  explicit SparseLdlt(Definiteness definiteness = Definiteness::RequirePositive);
  ~SparseLdlt() override;

  std::string_view name() const noexcept override;
  Definiteness definiteness() const noexcept { return definiteness_; }

  // After a successful factorize(): the number of negative pivots of D (the
  // number of negative eigenvalues of the factored matrix, by Sylvester's law).
  Eigen::Index negative_pivots() const noexcept;

 protected:
  FactorStatus do_analyze(const Eigen::SparseMatrix<double>& lower) override;
  Triangle factor_triangle() const noexcept override { return Triangle::Lower; }
  FactorStatus do_factorize(const Eigen::SparseMatrix<double>& working) override;
  void do_solve(Eigen::MatrixXd& B) const override;

 private:
  struct Impl;
  Definiteness definiteness_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace palpa
