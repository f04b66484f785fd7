// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// From the deformation gradient F to stress and tangent, for any Material.
//
// Signed SVD (invertible FEM, Irving et al. 2004): F = U diag(σ) Vᵀ with U, V
// rotations; if det F < 0 the smallest singular value carries the sign.
// First Piola–Kirchhoff stress P = U diag(∂Ψ/∂σ) Vᵀ (thesis 1.4).
//
// Tangent dP/dF: in the SVD frame it splits into the 3×3 stretch Hessian
// ∂²Ψ/∂σ² (acting on u_k v_kᵀ) and, for each pair i < j, a flip mode
// (u_i v_jᵀ + u_j v_iᵀ)/√2 with stiffness (ψi − ψj)/(σi − σj) and a twist mode
// (u_i v_jᵀ − u_j v_iᵀ)/√2 with stiffness (ψi + ψj)/(σi + σj). Where σi → σj
// the flip stiffness uses its limit ½(Ψ_ii + Ψ_jj) − Ψ_ij (exact to O((σi−σj)²),
// so no perturbation of σ is needed); where σi + σj → 0 (inversion) the twist
// denominator is bounded away from zero. PSD projection acts on these
// eigenvalues, so the projected tangent is positive semi-definite by
// construction, and so is every element Hessian built from it.
//
// Matrices are flattened column-major: vec(F)[a + 3b] = F(a, b).

#include <Eigen/Core>

#include "palpa/material/material.hpp"

namespace palpa::material {

using Mat2 = Eigen::Matrix2d;
using Vec2 = Eigen::Vector2d;
using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;
using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

struct Svd3 {
  Mat3 U;
  Vec3 sigma;  // descending |σ|, σ(2) < 0 iff det F < 0
  Mat3 V;
};
struct Svd2 {
  Mat2 U;
  Vec2 sigma;  // σ(0) >= |σ(1)|, σ(1) < 0 iff det F < 0
  Mat2 V;
};

Svd3 signed_svd(const Mat3& F);
// Closed form, no iteration.
Svd2 signed_svd(const Mat2& F);

// ---------------------------------------------------------------- 3D

struct Stress3 {
  double psi = 0.0;            // Ψ [Pa]
  Mat3 P = Mat3::Zero();       // ∂Ψ/∂F [Pa]
  Mat9 dPdF = Mat9::Zero();    // ∂vec(P)/∂vec(F) [Pa]
};

// Ψ, and P (order >= Gradient), and dP/dF (order == Hessian).
void stress(const Material& m, const Mat3& F, EvalOrder order, PsdProjection projection,
            Stress3& out);

// ∂vec(P)/∂θ: out is 9 × p (p = m.num_params()); work is 3 × p scratch.
void dP_dparam(const Material& m, const Mat3& F, Eigen::Ref<Eigen::MatrixXd> work,
               Eigen::Ref<Eigen::MatrixXd> out);

// ---------------------------------------------------------------- axisymmetric
// F = [[F_rr, 0, F_rz], [0, F_θθ, 0], [F_zr, 0, F_zz]] in the (r, θ, z) basis
// (thesis 4.5): the (r, z) block F2 and the hoop stretch F_θθ = 1 + u_r/r. Only a
// 2×2 SVD is needed. Stress and tangent are over the five non-zero entries
// x = (F_rr, F_zr, F_rz, F_zz, F_θθ) (F2 column-major, then the hoop).

struct StressAxisym {
  double psi = 0.0;
  Vec5 P = Vec5::Zero();      // ∂Ψ/∂x [Pa]
  Mat5 dPdF = Mat5::Zero();   // ∂²Ψ/∂x² [Pa]
};

void stress_axisymmetric(const Material& m, const Mat2& F2, double hoop, EvalOrder order,
                         PsdProjection projection, StressAxisym& out);

// ∂(∂Ψ/∂x)/∂θ: out is 5 × p; work is 3 × p scratch.
void dP_dparam_axisymmetric(const Material& m, const Mat2& F2, double hoop,
                            Eigen::Ref<Eigen::MatrixXd> work, Eigen::Ref<Eigen::MatrixXd> out);

// ---------------------------------------------------------------- helpers

// Stiffness of the flip mode of pair (i, j): (ψi − ψj)/(σi − σj), or its limit.
double flip_stiffness(const Vec3& sigma, const StretchEnergy& e, int i, int j) noexcept;
// Stiffness of the twist mode of pair (i, j): (ψi + ψj)/(σi + σj), bounded.
double twist_stiffness(const Vec3& sigma, const StretchEnergy& e, int i, int j) noexcept;

}  // namespace palpa::material
