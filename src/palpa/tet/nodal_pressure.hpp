// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The linear tetrahedron with nodally averaged volume change (average nodal
// pressure, after Bonet & Burton 1998): a tet mesh that does not lock as
// ν → 0.5.
//
// A linear tet has one volume ratio J_e = det F_e; with three displacement
// DOFs per vertex and about five tets per vertex, asking every tet to keep its
// volume over-constrains the mesh, and the body locks. Here the part of the
// energy that resists volume change is evaluated with the volume ratio of each
// vertex's patch of tets instead,
//   J_a = v̂_a / V̂_a,   v̂_a = Σ_{e∋a} v_e/4,  V̂_a = Σ_{e∋a} V_e/4
// (v, V: current and rest tet volumes), one constraint per vertex:
//   E = Σ_e V_e [Ψ_e(F_e) − U_e(J_e)] + Σ_a Σ_{e∋a} (V_e/4) U_e(J_a),
// with U(J) = Ψ(J^{1/3}, J^{1/3}, J^{1/3}) the material's own energy of a
// pure dilatation, so it works for every material (and per-tet materials:
// each tet's share of a vertex uses its own U). Under a homogeneous
// deformation J_a = J_e and E is the linear tet's energy exactly (the patch
// test holds); the first sum keeps the shear stiffness, which does not lock.
//
// Stabilized (ElasticModel::stabilization() = β > 0): a share β of the
// volumetric energy stays on each tet's own J_e,
//   E = Σ_e V_e [Ψ_e(F_e) − (1−β) U_e(J_e)] + (1−β) Σ_a Σ_{e∋a} (V_e/4) U_e(J_a),
// which stiffens the modes that nodal averaging leaves too soft (a patch's
// tets may trade volume among themselves at no cost) and brings back a
// fraction β of the locking; the patch test still holds.
//
// Two terms (solve/term.hpp), with exact derivatives:
//  * DeviatoricTerm: per tet, V(Ψ(F) − U(J)); its 12×12 Hessian, projected
//    to PSD by its eigenvalues when a projection is asked.
//  * NodalVolumeTerm: per vertex a, W_a(J_a) with W_a = (1−β) Σ_{e∋a} (V_e/4) U_e;
//    its stencil is the vertex's patch (every vertex of its tets). Gradient
//    W_a' ∂J_a; Hessian W_a'' ∂J_a ∂J_aᵀ + W_a' ∂²J_a. With a projection
//    asked, the Gauss–Newton part max(W_a'', 0) ∂J_a ∂J_aᵀ alone (PSD; the
//    curvature of the volume is indefinite).
// A vertex's patch couples the vertices of its tets' tets: the Hessian has
// about twice the linear tet's nonzeros.

#include <Eigen/Core>
#include <vector>

#include "palpa/solve/term.hpp"
#include "palpa/tet/elastic_term.hpp"
#include "palpa/tet/model.hpp"

namespace palpa::tet {

// U(J) = Ψ(s, s, s), s = J^{1/3}, and its derivatives U', U'' [Pa], J > 0.
struct Dilatation {
  double u = 0.0;
  double du = 0.0;
  double d2u = 0.0;
};
Dilatation dilatation(const material::Material& m, double J);

// Signed volume of the tet with corners x (columns) [m³], its gradient
// (12, corner-major) and Hessian (12×12).
double tet_volume(const Mat34& x, Vec12* gradient = nullptr, Mat12* hessian = nullptr);

class DeviatoricTerm final : public Term {
 public:
  explicit DeviatoricTerm(const ElasticModel& model) : model_(&model), nodal_share_(1.0 - model.stabilization()) {}

  double energy(const VertexState& s) const override;
  double add_gradient(const VertexState& s, Eigen::VectorXd& g) const override;
  int stencil_size() const noexcept override { return 4; }
  Eigen::Index num_stencils() const noexcept override { return model_->num_elements(); }
  int stencil(Eigen::Index e, int* vertices) const override { return tet_corners(*model_, e, vertices); }
  bool stencil_hessian(const VertexState& s, Eigen::Index e, PsdProjection projection, double* h) const override;

 private:
  // E_e and, if asked, its gradient; false where det F ≤ 0.
  bool element(const VertexState& s, Eigen::Index e, double& energy, Vec12* gradient) const;

  const ElasticModel* model_;
  double nodal_share_;  // 1 − β
};

class NodalVolumeTerm final : public Term {
 public:
  // model: must outlive the term (its topology and rest volumes are read
  // once, here).
  explicit NodalVolumeTerm(const ElasticModel& model);

  double energy(const VertexState& s) const override;
  double add_gradient(const VertexState& s, Eigen::VectorXd& g) const override;
  int stencil_size() const noexcept override { return max_patch_; }
  Eigen::Index num_stencils() const noexcept override { return model_->num_vertices(); }
  int stencil(Eigen::Index a, int* vertices) const override;
  bool stencil_hessian(const VertexState& s, Eigen::Index a, PsdProjection projection, double* h) const override;

  // The volume ratio J_a of every vertex's patch at displacement u (N; 1 at
  // rest; 1 for a vertex no tet uses).
  Eigen::VectorXd nodal_jacobians(const Eigen::VectorXd& u) const;

 private:
  // Current tet volumes at u (#T), and their gradients if asked; false if
  // one is not positive.
  bool volumes(const Eigen::VectorXd& u, std::vector<double>& v, std::vector<Vec12>* gradients = nullptr) const;
  // J_a of every vertex from the tet volumes.
  Eigen::VectorXd jacobians(const std::vector<double>& v) const;
  // W_a and its derivatives at J (J > 0).
  Dilatation nodal(Eigen::Index a, double J) const;

  const ElasticModel* model_;
  Eigen::VectorXd rest_;                 // V̂_a [m³]
  std::vector<int> tet_start_, tets_;    // CSR: the tets of vertex a
  std::vector<int> patch_start_, patch_; // CSR: the vertices of a's patch (sorted)
  std::vector<int> corner_local_;        // per (a, tet) entry: its 4 corners' places in a's patch
  std::vector<int> share_start_;         // CSR: a's materials and their weights Σ V_e/4
  std::vector<int> share_material_;
  std::vector<double> share_weight_;
  int max_patch_ = 0;
};

}  // namespace palpa::tet
