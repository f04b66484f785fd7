// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Systems whose energy depends on parameters θ ∈ Rᵖ (material spline control
// points, support vertex positions, ...), and the sensitivity of an equilibrium
// to them.
//
// At an equilibrium x*(θ) the gradient vanishes, g(x*(θ), θ) = 0, so
//   H dx*/dθ = −∂g/∂θ            (the thesis's (6.17) with g = −f).
// With H(x*) factored once (NewtonSolver::factor_hessian), every parameter
// costs one back-solve: solution_param_jacobian() does all p at once as a
// multiple right-hand-side solve. The adjoint form (one solve for a scalar
// objective φ(x*): λ = H⁻¹ ∂φ/∂x, dφ/dθ = ∂φ/∂θ − λᵀ ∂g/∂θ) uses the same pieces.
//
// Kept apart from System: only systems with parameters implement it, next to
// System (class Layer : public System, public ParametricSystem).

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "palpa/solve/factorization.hpp"

namespace palpa {

class ParametricSystem {
 public:
  virtual ~ParametricSystem();

  // p: the number of parameters.
  virtual Eigen::Index num_params() const = 0;

  // J = ∂g/∂θ at x, for the current parameter values: n×p (n = num_dofs() of
  // the System), column j = ∂g/∂θ_j in [gradient units / units of θ_j]
  // (e.g. N/Pa for a modulus). Sparse, because for shape parameters p is large
  // and each parameter touches few DOFs; for a handful of material parameters
  // the columns are simply dense. The pattern may be rebuilt on every call.
  virtual void gradient_param_jacobian(const Eigen::VectorXd& x,
                                       Eigen::SparseMatrix<double>& J) const = 0;

 protected:
  ParametricSystem() = default;
  ParametricSystem(const ParametricSystem&) = default;
  ParametricSystem& operator=(const ParametricSystem&) = default;
};

// dx*/dθ = −H⁻¹ ∂g/∂θ at an equilibrium x*.
//  hessian_factor: a factorization of the true (unshifted, unprojected) H(x*),
//                  status Ok (NewtonSolver::factor_hessian gives one);
//  dg_dtheta:      n×p, from gradient_param_jacobian(x*, J).
// Returns n×p [units of x / units of θ]. One multi-column back-solve.
Eigen::MatrixXd solution_param_jacobian(const SymmetricFactorization& hessian_factor,
                                        const Eigen::SparseMatrix<double>& dg_dtheta);

}  // namespace palpa
