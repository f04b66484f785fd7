// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The ergonomic score of a resting contact and the smoothness of a support
// (thesis §7.4.1, MODEL.md "Body + rigid core + support contact").
//
// Ergonomic score (7.11–7.12):
//   ζ = Σ_i A_i p̄_i^e  over the body's skin vertices and the support's vertices,
// p the contact pressures of the equilibrium on both sides (bidirectional,
// Fig. 7.4): the traction per deformed area a mat would read, recovered from
// one set of nodal contact forces (rest/measurements.hpp: both passes on a
// deformable support), with the footprints of the contacts when the score
// is built (so that ζ stays one smooth function of the shape); A_i the
// vertex's area where the surface is now. So ζ_body is ∫ p̄^e over the
// deformed skin, what the body feels and what the support sees carry the
// same load, and a support vertex cannot lower ζ by missing the skin. p̄ = S p,
// one Laplacian smoothing step on each surface's own mesh:
//   p̄_i = (1 − λ) p_i + λ · mean_{j ∈ N(i)} p_j,   λ = ½ (the thesis's; 0: p itself),
// i.e. (I + λL) p with the umbrella L = W − I (W: the mean of the
// neighbours), the sign that smooths: a lone spike is spread over its ring,
// a constant field is kept. e (exponent) is 2, 3 or 4 (Fig. 7.5). Units:
// ζ [Pa^e·m²].
//
// Partial derivatives (for the adjoint, design/optimizer.hpp): with the
// contact set, each contact's feature and the footprints held, ζ is a smooth
// function of the body's vertex positions Y and of the support's where they
// are. Since f = −∂E_c/∂y and p = R(y)|f| (contact::TractionRecovery),
// ∂ζ/∂y = −H_c v + ∂ζ/∂y|_f with H_c the contact energy's Hessian and
// v_i = (∂ζ/∂|f_i|) f̂_i (one product with the contact Hessian), and the
// explicit part the recovery's pullback and the areas' gradient.
//
// Smoothness (7.14): ψ(X) = Σ_{v ∈ D} ‖X_v − (T X)_v‖², T = ((I + μL)(I + λL))^m
// Taubin smoothing (λ = 0.5, μ = −0.53) on the support's mesh, D the design
// vertices (so a fixed outline does not weigh). Units: ψ [m²].

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "palpa/rest/measurements.hpp"
#include "palpa/rest/rest.hpp"

namespace palpa::design {

struct ScoreOptions {
  int exponent = 3;               // e: 2, 3 or 4
  double pressure_smoothing = 0.5;  // λ of the smoothing step p̄ = (I + λL) p
};

struct Score {
  double zeta = 0.0;          // [Pa^e·m²]
  double zeta_body = 0.0;
  double zeta_support = 0.0;
  Eigen::VectorXd body_pressure;       // p per body vertex [Pa]
  Eigen::VectorXd support_pressure;    // p per support vertex [Pa]
  Eigen::VectorXd body_smoothed;       // p̄
  Eigen::VectorXd support_smoothed;
  int body_contacts = 0;
  int support_contacts = 0;
  // With gradients: ∂ζ/∂Y (3N, the body's vertex positions), ∂ζ/∂Y_s (the
  // support's surface vertices where they are, #V×3) and ∂ζ/∂X (the
  // support's rest positions, #V×3, explicitly: a deformable support's held
  // base; 0 for a rigid one, where Y_s = X and the explicit gradient is
  // d_support).
  Eigen::VectorXd d_body;
  Eigen::MatrixX3d d_support;
  Eigen::MatrixX3d d_support_area;
};

class ErgonomicScore {
 public:
  // Builds the smoothing operators of the body's skin and the support.
  // Throws palpa::Error (Input) for an exponent other than 2, 3, 4 or a
  // smoothing λ outside [0, 1].
  ErgonomicScore(const rest::RestSimulation& sim, ScoreOptions options);
  const ScoreOptions& options() const noexcept { return options_; }
  // ζ of the simulation's current (solved) state.
  Score evaluate(const rest::RestSimulation& sim, bool gradient) const;

 private:
  // Smooths s's pressures and sums ζ over cp's areas; wb, ws: ∂ζ/∂p̄ on the
  // body and the support.
  void sum(const rest::ContactPressures& cp, Score& s, Eigen::VectorXd& wb, Eigen::VectorXd& ws) const;
  ScoreOptions options_;
  rest::PressureRecovery recovery_;                // footprints of the contacts when built
  Eigen::SparseMatrix<double> body_smoothing_;     // S over the body's vertices (skin rows)
  Eigen::SparseMatrix<double> support_smoothing_;  // S over the support's vertices
};

class Smoothness {
 public:
  // F: the support's triangles; n its vertex count; design: the rows of D.
  // Throws palpa::Error (Input) for iterations < 1.
  Smoothness(const Eigen::MatrixX3i& F, Eigen::Index n, std::vector<int> design, int iterations,
             double lambda = 0.5, double mu = -0.53);
  // ψ(X) [m²] and, if grad is given, ∂ψ/∂X (#V×3, zero off D's reach).
  double evaluate(const Eigen::MatrixX3d& X, Eigen::MatrixX3d* grad = nullptr) const;
  // T X (the smoothed shape; all vertices).
  Eigen::MatrixX3d smoothed(const Eigen::MatrixX3d& X) const;

 private:
  Eigen::SparseMatrix<double> step_lambda_, step_mu_;  // I + λL, I + μL
  std::vector<int> design_;
  int iterations_;
};

}  // namespace palpa::design
