// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Derivatives of a resting equilibrium with respect to the support's shape
// (thesis 7.17–7.23), for the design (design/score.hpp, design/optimizer.hpp).

#include <Eigen/Core>

#include "palpa/rest/rest.hpp"
#include "palpa/solve/adjoint.hpp"

namespace palpa::rest {

// H_c v, H_c the Hessian of the contact energy (both passes on a deformable
// support) over the vertex positions of the body (3×N) and the support's
// surface, at the current state.
void contact_hessian_product(const RestSimulation& sim, const Eigen::Matrix3Xd& v_body,
                             const Eigen::Matrix3Xd& v_support, Eigen::Matrix3Xd& body, Eigen::Matrix3Xd& support);

// The derivative with respect to the support's rest vertices X (#V×3) of a
// function f(Y_body, Y_support) of the body's vertex positions (3N) and the
// support's surface positions (#V×3) at the equilibrium, given its partial
// derivatives d_body and d_support there: the adjoint, one factorization of
// the equilibrium's Hessian and one back-solve. A Hessian that cannot be
// factored is a returned status (out untouched).
AdjointStatus shape_derivative(RestSimulation& sim, const Eigen::VectorXd& d_body, const Eigen::MatrixX3d& d_support,
                               Eigen::MatrixX3d& out);

}  // namespace palpa::rest
