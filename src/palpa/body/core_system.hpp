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
// Derivatives. With g the gradient over the 3N vertex DOFs:
//   ∂E/∂t = Σ_i g_i,   ∂E/∂ω = J_l(ω')ᵀ Σ_i b_i × g_i   (b_i = exp([ω'])a_i),
// exact at any x (J_l: the left Jacobian of SO(3)). The Hessian is
// Pᵀ H P + the rotational curvature Σ_i ½(g_i b_iᵀ + b_i g_iᵀ) − (g_i·b_i) I
// with P the coupling [I; B] at the current pose; it is exact at the committed
// pose (ω' = 0), where Newton evaluates it; away from it the curvature term
// uses b_i in place of the exact second derivative of the exponential map.
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
#include <vector>

#include "palpa/solve/system.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::body {

struct CoreSpec {
  std::vector<int> attached;                         // vertices moving with the core
  double mass = 0.0;                                 // m_c [kg] (beside the layer's)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // c0 [m]
  std::array<bool, 6> locked{false, false, false, false, false, false};  // t_x t_y t_z ω_x ω_y ω_z
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // external force on the core [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // external torque about c0 [N·m]
};

class CoreSystem final : public System {
 public:
  // model: the layer. Throws palpa::Error (Input) for no attached vertex, an
  // attached index out of range, every core DOF locked with no free vertex,
  // a negative or non-finite core mass.
  CoreSystem(const tet::ElasticModel& model, CoreSpec core);
  ~CoreSystem() override;

  const tet::ElasticModel& model() const noexcept { return *model_; }
  const CoreSpec& core() const noexcept { return core_; }
  void set_gravity(const Eigen::Vector3d& g);
  void add_term(tet::VertexTerm* term) { full_->add_term(term); }
  void set_regularization(double alpha) {
    alpha_ = alpha;
    full_->set_regularization(alpha);
  }
  void set_true_hessian(bool on) noexcept { full_->set_true_hessian(on); }
  bool regularizing() const;

  Eigen::Index num_vertex_dofs() const noexcept { return static_cast<Eigen::Index>(free_.size()); }
  Eigen::Index num_core_dofs() const noexcept { return static_cast<Eigen::Index>(core_dofs_.size()); }
  // Vertex DOF k of x (k < num_vertex_dofs()) is full DOF free_dofs()[k] of u.
  const std::vector<int>& free_dofs() const noexcept { return free_; }

  // u (3N) at x, with the attached vertices on the core; positions X + u.
  Eigen::VectorXd full_displacement(const Eigen::VectorXd& x) const;
  Eigen::VectorXd positions(const Eigen::VectorXd& x) const;
  // The core's pose at x: translation t [m] and rotation R (exp([ω'])·R_c).
  Eigen::Vector3d core_translation(const Eigen::VectorXd& x) const;
  Eigen::Matrix3d core_rotation(const Eigen::VectorXd& x) const;
  // The committed rotation R_c.
  const Eigen::Matrix3d& committed_rotation() const noexcept { return rotation_; }
  // The committed pose (R_c, ω_c): with x it is the whole state of the system,
  // so a state carried to another CoreSystem on the same body (a warm start)
  // takes both.
  struct Committed {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  };
  Committed committed() const { return {rotation_, omega_committed_}; }
  void set_committed(const Committed& c);

  // Chain rule through the coupling P(x) (3N vertex positions ← x):
  // pull_back(x, G) = Pᵀ G for G ∂f/∂(positions) (3N, entries of vertices no
  // tet uses ignored), the gradient of f over x; push_forward(x, z) = P z,
  // the vertex displacements (3N) of a change z of x.
  Eigen::VectorXd pull_back(const Eigen::VectorXd& x, const Eigen::VectorXd& G) const;
  Eigen::VectorXd push_forward(const Eigen::VectorXd& x, const Eigen::VectorXd& z) const;

  // System
  Eigen::Index num_dofs() const override { return num_vertex_dofs() + num_core_dofs(); }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  void prepare(const Eigen::VectorXd& x) override;

 private:
  Eigen::Vector3d omega_local(const Eigen::VectorXd& x) const;  // ω' = ω − ω_c
  Eigen::Vector3d omega_total(const Eigen::VectorXd& x) const;  // ω
  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* g) const;
  // P: 3N × n, the coupling of x to the vertex DOFs at x (columns of the core
  // from −[b_i]× J_l(ω')).
  Eigen::SparseMatrix<double> coupling(const Eigen::VectorXd& x) const;

  const tet::ElasticModel* model_;
  CoreSpec core_;
  std::unique_ptr<tet::StaticSystem> full_;  // all 3N DOFs free: energy, gradient, Hessian over u
  std::vector<int> free_;                    // free DOF k -> full DOF
  std::vector<char> is_attached_;
  std::vector<int> core_dofs_;               // free core DOF k -> pose component 0…5
  Eigen::Vector3d gravity_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation_ = Eigen::Matrix3d::Identity();  // R_c
  Eigen::Vector3d omega_committed_ = Eigen::Vector3d::Zero();  // ω_c
  double alpha_ = 0.0;
};

// Rotation matrix exp([ω]) (Rodrigues) and the left Jacobian J_l(ω) of SO(3).
Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w);
Eigen::Matrix3d left_jacobian_so3(const Eigen::Vector3d& w);

}  // namespace palpa::body
