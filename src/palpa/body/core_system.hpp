// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A soft body on a rigid core (thesis §7.3.3, MODEL.md "Body + rigid core +
// support contact"): a tet layer whose attached vertices (its inner surface)
// move with a 6-DOF rigid core, under gravity, an external wrench on the core
// and vertex terms such as penalty contact with a support.
//
// Unknowns. x = (u_F, q): the displacements of the layer's other vertices
// [m], then the core's unlocked pose DOFs among (t_x, t_y, t_z [m], ω_x, ω_y,
// ω_z [rad]). An attached vertex sits at
//   x_i = c0 + t + exp([ω'])·a_i,   a_i = R_c (X_i − c0),
// c0 the core's centre of mass at rest, R_c the committed rotation and ω' the
// rotation since the last committed iterate (ω' = ω − ω_c). prepare(x)
// commits: R_c ← exp([ω'])·R_c, ω_c ← ω. So every Newton step is linearized
// at the current pose (the B of (7.1) with h_i recomputed) and the pose is
// updated by the exponential map, never by adding rotation vectors.
//
// A TermSystem (solve/term_system.hpp) over a DofMap with the core
// (solve/dof_map.hpp): the derivatives through the core, exact at any x, and
// the Hessian Pᵀ H P + the rotation's curvature, exact at the committed pose
// (ω' = 0), are the map's and the assembler's.
//
// External wrench: a force F on the core's centre of mass (potential −F·t) and
// a torque τ (potential −τ·ω, exact for rotation about a fixed axis such as a
// foot's pitch; with several free rotation axes the torque acts along the path
// the rotation vector takes). Core mass m_c adds −m_c g·t.
//
// Regularization: while no vertex term reports contact, K + α(Pᵀ M P + core
// mass) — the thesis's remedy for a body that has not landed yet (§7.3.4).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <vector>

#include "palpa/solve/so3.hpp"
#include "palpa/solve/term_system.hpp"
#include "palpa/tet/elastic_term.hpp"

namespace palpa::body {

struct CoreSpec {
  std::vector<int> attached;                         // vertices moving with the core
  double mass = 0.0;                                 // m_c [kg] (beside the layer's)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // c0 [m]
  std::array<bool, 6> locked{false, false, false, false, false, false};  // t_x t_y t_z ω_x ω_y ω_z
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // external force on the core [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // external torque about c0 [N·m]
};

class CoreSystem final : public TermSystem {
 public:
  // model: the layer. Throws palpa::Error (Input) for no attached vertex, an
  // attached index out of range, every core DOF locked with no free vertex,
  // a negative or non-finite core mass. newton: the projection of the element
  // Hessians that hessian() assembles (None: the true Hessian).
  CoreSystem(const tet::ElasticModel& model, CoreSpec core, PsdProjection newton = PsdProjection::Clamp);
  ~CoreSystem() override;

  const tet::ElasticModel& model() const noexcept { return *model_; }
  const CoreSpec& core() const noexcept { return core_; }
  void set_gravity(const Eigen::Vector3d& g);
  void set_regularization(double alpha);

  Eigen::Index num_vertex_dofs() const noexcept { return dof_map().num_vertex_dofs(); }
  Eigen::Index num_core_dofs() const noexcept { return dof_map().num_core_dofs(); }
  // Vertex DOF k of x (k < num_vertex_dofs()) is full DOF free_dofs()[k] of u.
  const std::vector<int>& free_dofs() const noexcept { return dof_map().free_dofs(); }

  // Deformed positions X + u(x) (3N).
  Eigen::VectorXd positions(const Eigen::VectorXd& x) const { return TermSystem::positions(full_displacement(x)); }
  // The core's pose at x: translation t [m] and rotation R (exp([ω'])·R_c).
  Eigen::Vector3d core_translation(const Eigen::VectorXd& x) const { return dof_map().core_translation(x); }
  Eigen::Matrix3d core_rotation(const Eigen::VectorXd& x) const { return dof_map().core_rotation(x); }
  // The committed rotation R_c.
  Eigen::Matrix3d committed_rotation() const { return dof_map().committed().rotation; }
  // The committed pose (R_c, ω_c): with x it is the whole state of the system,
  // so a state carried to another CoreSystem on the same body (a warm start)
  // takes both.
  using Committed = DofMap::Committed;
  Committed committed() const { return dof_map().committed(); }
  void set_committed(const Committed& c) { mutable_dof_map().set_committed(c); }

  // Chain rule through the coupling P(x) (3N vertex positions ← x):
  // pull_back(x, G) = Pᵀ G for G ∂f/∂(positions) (3N, entries of vertices no
  // tet uses ignored), the gradient of f over x; push_forward(x, z) = P z,
  // the vertex displacements (3N) of a change z of x.
  Eigen::VectorXd pull_back(const Eigen::VectorXd& x, const Eigen::VectorXd& G) const {
    return dof_map().pull_back(x, G);
  }
  Eigen::VectorXd push_forward(const Eigen::VectorXd& x, const Eigen::VectorXd& z) const {
    return dof_map().push_forward(x, z);
  }

 private:
  const tet::ElasticModel* model_;
  CoreSpec core_;
  std::vector<std::unique_ptr<Term>> elastic_;
  LinearTerm gravity_;
};

using palpa::exp_so3;
using palpa::left_jacobian_so3;

}  // namespace palpa::body
