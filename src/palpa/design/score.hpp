// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The ergonomic score of a resting contact and the smoothness of a support
// (thesis §7.4.1, MODEL.md "Body + rigid core + support contact").
//
// Ergonomic score (7.11–7.12):
//   ζ = Σ_i s_i p̄_i^e  over the body's skin vertices and the support's vertices,
// p the contact pressures of the equilibrium on both sides (bidirectional,
// Fig. 7.4), both from one set of nodal contact forces (both passes on a
// deformable support, rest/coupled.hpp): p_i = ‖f_i‖/s_i, s_i the vertex's
// area (the body's ContactTerm::pressure_areas(); the support vertex's rest
// area, a third of its triangles, a function of the support's shape). So
// what the body feels and what the support sees carry the same load, and a
// support vertex cannot lower ζ by missing the skin. p̄ = S p, one Laplacian
// smoothing step on each surface's own mesh:
//   p̄_i = (1 − λ) p_i + λ · mean_{j ∈ N(i)} p_j,   λ = ½,
// i.e. (I + λL) p with the umbrella L = W − I (W: the mean of the
// neighbours), the sign that smooths: a lone spike is spread over its ring,
// a constant field is kept. e (exponent) is 2, 3 or 4 (Fig. 7.5). Units:
// ζ [Pa^e·m²].
//
// Partial derivatives (for the adjoint, design/optimizer.hpp): with the
// contact set, each contact's feature and the spring areas held, ζ is a
// smooth function of the body's vertex positions Y and the support's
// vertices (where they are, and at rest through their areas). Since
// f = −∂E_c/∂y, ∂p_i/∂y = −f̂_iᵀ H_c(i, ·)/s_i and ∂ζ/∂y = −H_c v with H_c
// the contact energy's Hessian and v_i = (∂ζ/∂p_i / s_i) f̂_i: one product
// with the contact Hessian. Areas differentiate as ∂A/∂a = ½ n̂ × (c − b)
// for triangle (a, b, c).
//
// Smoothness (7.14): ψ(X) = Σ_{v ∈ D} ‖X_v − (T X)_v‖², T = ((I + μL)(I + λL))^m
// Taubin smoothing (λ = 0.5, μ = −0.53) on the support's mesh, D the design
// vertices (so a fixed outline does not weigh). Units: ψ [m²].

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

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
  // support's vertex positions where they are, #V×3: through the forces) and
  // ∂ζ/∂X (the support's rest positions, #V×3: through its vertex areas).
  // For a rigid support Y_s = X and the explicit gradient is their sum.
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
  // Smooths s's pressures and sums ζ; wb, ws: ∂ζ/∂p̄ on the body and the
  // support (support_area: the support's vertex areas).
  void sum(const rest::RestSimulation& sim, const Eigen::VectorXd& support_area, Score& s, Eigen::VectorXd& wb,
           Eigen::VectorXd& ws) const;
  ScoreOptions options_;
  Eigen::SparseMatrix<double> body_smoothing_;     // S over the body's vertices (skin rows)
  Eigen::SparseMatrix<double> support_smoothing_;  // S over the support's vertices
};

// Vertex areas of a triangle mesh and, if wanted, Σ_v w_v ∂A_v/∂X (#V×3).
void add_area_gradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::VectorXd& w,
                       Eigen::MatrixX3d& grad);

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
