// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The linear (4-node) tetrahedron (thesis §7.3.3, Appendix of ch. 4 for the
// hyperelastic energy): the deformation gradient is constant over the element,
//   F = Σ_a x_a ⊗ ∇N_a,
// with ∇N_a the (constant) rest-space gradients of the shape functions, and the
// element energy is E = V Ψ(F), V the rest volume. Element DOFs are the
// deformed positions of the four corners, x = (x0, y0, z0, x1, …, z3) [m].
//
// Derivatives: ∂E/∂x = V Bᵀ vec(P), ∂²E/∂x² = V Bᵀ (∂P/∂F) B with
// B = ∂vec(F)/∂x (9×12, vec column-major as in material/kinematics.hpp). With a
// PSD-projected ∂P/∂F the element Hessian is PSD too.
//
// Admissibility: an element whose det F ≤ 0 (inverted or flat) has no finite
// energy here: tet_evaluate returns false and the caller reports +infinity, so
// line searches step back from inversions (the materials are defined there,
// but a body that turns inside out is never a physical answer).

#include <Eigen/Core>
#include <Eigen/LU>

#include "palpa/material/material.hpp"

namespace palpa::tet {

using Vec12 = Eigen::Matrix<double, 12, 1>;
using Mat12 = Eigen::Matrix<double, 12, 12>;
using Mat43 = Eigen::Matrix<double, 4, 3>;
using Mat34 = Eigen::Matrix<double, 3, 4>;

// Rest-state data of one element.
struct TetGeometry {
  Mat43 grad_n = Mat43::Zero();  // row a: ∇N_a [1/m]
  double volume = 0.0;           // V [m³], > 0 for a positively oriented tet
};

// Signed rest volume of a tet with corners X (columns) [m³]: positive when
// (X1−X0, X2−X0, X3−X0) is right-handed.
double signed_volume(const Mat34& X) noexcept;

// Rest geometry from corner positions X (columns) [m]. Requires volume > 0
// (the caller validates the mesh first); the result is undefined otherwise.
TetGeometry tet_geometry(const Mat34& X);

// F = Σ_a x_a ⊗ ∇N_a for deformed corners x (columns).
material::Mat3 deformation_gradient(const TetGeometry& g, const Mat34& x) noexcept;

struct TetResult {
  double energy = 0.0;            // V Ψ [J]
  Vec12 gradient = Vec12::Zero(); // ∂E/∂x [N]   (order ≥ Gradient)
  Mat12 hessian = Mat12::Zero();  // ∂²E/∂x² [N/m] (order == Hessian)
};

// Evaluates the element at deformed corners x (columns) [m]. Returns false
// (out untouched past that point) where det F ≤ 0 or is not finite.
bool tet_evaluate(const material::Material& m, const TetGeometry& g, const Mat34& x,
                  material::EvalOrder order, material::PsdProjection projection, TetResult& out);

// ∂(∂E/∂x)/∂θ (12 × p, p = m.num_params()) at x: the derivative of the element
// gradient with respect to the material parameters. work9 is 9 × p and work3
// is 3 × p scratch.
void tet_dgradient_dparam(const material::Material& m, const TetGeometry& g, const Mat34& x,
                          Eigen::Ref<Eigen::MatrixXd> work3, Eigen::Ref<Eigen::MatrixXd> work9,
                          Eigen::Ref<Eigen::MatrixXd> out);

// Shape derivative of the elastic forces (for shape optimization by the
// adjoint method): out = ∂/∂X [ Σ_a z_a · ∂E/∂x_a (x; X) ] with the DEFORMED
// corners x held fixed, X the rest corners (through g, which must be
// tet_geometry(X)), E = V(X) Ψ(F), F = D_s(x) D_m(X)⁻¹. z (columns): any 4
// corner vectors, e.g. the adjoint; out (columns): one 3-vector per rest
// corner [N/m × unit of z].
//
// With G = Z_s D_m⁻¹ = Σ_a z_a ⊗ ∇N_a, P = ∂Ψ/∂F and C:G = (∂P/∂F):G (the
// TRUE tangent, unprojected), Φ = V P:G has
//   ∂Φ/∂D_m = V [ (P:G) I − Fᵀ (C:G) − Gᵀ P ] D_m⁻ᵀ,
// so out = V [ (P:G) I − Fᵀ (C:G) − Gᵀ P ] [∇N_0 … ∇N_3] (columns 1..3 are
// those of ∂Φ/∂D_m, column 0 minus their sum). The derivative at fixed
// displacement u = x − X instead adds the element Hessian times z.
// Requires det F > 0 (the caller checks); allocation-free.
void tet_rest_gradient_product(const material::Material& m, const TetGeometry& g, const Mat34& x,
                               const Mat34& z, Mat34& out);

// Cauchy stress σ = P Fᵀ / det F [Pa] at x (det F > 0 required).
material::Mat3 cauchy_stress(const material::Material& m, const TetGeometry& g, const Mat34& x);

}  // namespace palpa::tet
