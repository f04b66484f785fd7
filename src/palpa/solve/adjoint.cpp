// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/adjoint.hpp"

#include <fmt/format.h>

namespace palpa {

std::string AdjointStatus::message() const {
  if (ok()) return {};
  return fmt::format("the equilibrium's Hessian could not be factored for the adjoint ({})", to_string(factor));
}

AdjointStatus solve_adjoint(NewtonSolver& newton, const System& system, const Eigen::VectorXd& x,
                            const Eigen::VectorXd& rhs, Eigen::VectorXd& z) {
  AdjointStatus st;
  st.factor = newton.factor_hessian(system, x);
  if (st.ok()) z = newton.factorization().solve(rhs);
  return st;
}

}  // namespace palpa
