// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The adjoint solve behind every sensitivity of an equilibrium (thesis
// 7.17–7.23, parametric_system.hpp): at a solved x*, factor the true,
// unshifted Hessian H(x*) with the Newton solver's factorization (its pattern
// analysis reused) and back-solve H z = rhs. The caller contracts z with
// ∂g/∂θ of its own parameters.

#include <Eigen/Core>
#include <string>

#include "palpa/solve/factorization.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/solve/system.hpp"

namespace palpa {

// Whether the adjoint could be solved; a numerical failure is a status, not an
// exception (the design optimizer treats it as a rejected step).
struct AdjointStatus {
  FactorStatus factor = FactorStatus::Ok;
  bool ok() const noexcept { return factor == FactorStatus::Ok; }
  // What went wrong, for a user (empty when ok()).
  std::string message() const;
};

// z = H(x)⁻¹ rhs with `newton`'s factorization (after newton.solve(system, x)).
// z is left untouched unless ok().
AdjointStatus solve_adjoint(NewtonSolver& newton, const System& system, const Eigen::VectorXd& x,
                            const Eigen::VectorXd& rhs, Eigen::VectorXd& z);

}  // namespace palpa
