// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/sparse_ldlt.hpp"

#include <Eigen/SparseCholesky>
#include <cmath>

namespace palpa {

struct SparseLdlt::Impl {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  Eigen::Index negative = 0;
};

SparseLdlt::SparseLdlt(Definiteness definiteness)
    : definiteness_(definiteness), impl_(std::make_unique<Impl>()) {}

SparseLdlt::~SparseLdlt() = default;

std::string_view SparseLdlt::name() const noexcept {
  return definiteness_ == Definiteness::RequirePositive ? "eigen-ldlt" : "eigen-ldlt-indefinite";
}

Eigen::Index SparseLdlt::negative_pivots() const noexcept {
  return impl_->negative;
}

FactorStatus SparseLdlt::do_analyze(const Eigen::SparseMatrix<double>& lower) {
  impl_->ldlt.analyzePattern(lower);
  impl_->negative = 0;
  return FactorStatus::Ok;
}

FactorStatus SparseLdlt::do_factorize(const Eigen::SparseMatrix<double>& working) {
  impl_->ldlt.factorize(working);
  impl_->negative = 0;
  // Eigen reports an exactly zero pivot as NumericalIssue.
  if (impl_->ldlt.info() != Eigen::Success) {
    return definiteness_ == Definiteness::RequirePositive ? FactorStatus::NotPositiveDefinite
                                                          : FactorStatus::Singular;
  }
  const Eigen::VectorXd& D = impl_->ldlt.vectorD();
  for (Eigen::Index k = 0; k < D.size(); ++k) {
    if (!std::isfinite(D[k])) return FactorStatus::Singular;
    if (D[k] < 0.0) ++impl_->negative;
  }
  if (definiteness_ == Definiteness::RequirePositive && impl_->negative > 0) {
    return FactorStatus::NotPositiveDefinite;
  }
  return FactorStatus::Ok;
}

void SparseLdlt::do_solve(Eigen::MatrixXd& B) const {
  Eigen::MatrixXd X = impl_->ldlt.solve(B);
  B.swap(X);
}

}  // namespace palpa
