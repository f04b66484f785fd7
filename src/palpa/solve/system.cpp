// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/system.hpp"

#include <algorithm>
#include <utility>

#include "palpa/solve/parametric_system.hpp"

namespace palpa {

System::~System() = default;

double System::energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  gradient(x, g);
  return energy(x);
}

void System::prepare(const Eigen::VectorXd& /*x*/) {}

bool System::projected_hessian(const Eigen::VectorXd& /*x*/, Eigen::SparseMatrix<double>& /*H*/) const {
  return false;
}

ParametricSystem::~ParametricSystem() = default;

Eigen::MatrixXd solution_param_jacobian(const SymmetricFactorization& hessian_factor,
                                        const Eigen::SparseMatrix<double>& dg_dtheta) {
  const Eigen::MatrixXd rhs = -Eigen::MatrixXd(dg_dtheta);
  return hessian_factor.solve(rhs);
}

int lower_slot(const Eigen::SparseMatrix<double>& pattern, int row, int col) {
  if (row < col) std::swap(row, col);
  const int* begin = pattern.innerIndexPtr() + pattern.outerIndexPtr()[col];
  const int* end = pattern.innerIndexPtr() + pattern.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  if (it == end || *it != row) return -1;
  return static_cast<int>(it - pattern.innerIndexPtr());
}

}  // namespace palpa
