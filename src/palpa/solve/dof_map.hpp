// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The map from a system's unknowns x to the displacement of every vertex of
// its body (3N, vertex-major): which vertex DOFs are free, which are held at
// prescribed values, and which vertices ride on a rigid core (thesis §7.3.3,
// MODEL.md "Body + rigid core + support contact").
//
// x = (free vertex DOFs, in increasing full-DOF order; then the core's
// unlocked pose DOFs among t_x, t_y, t_z [m], ω_x, ω_y, ω_z [rad]). A vertex
// attached to the core sits at
//   p_i = c0 + t + exp([ω'])·a_i,   a_i = R_c (X_i − c0),
// c0 the core's centre, R_c the committed rotation and ω' = ω − ω_c the
// rotation since the last commit; commit(x) sets R_c ← exp([ω'])·R_c,
// ω_c ← ω. So every Newton step is linearized at the current pose and the
// pose is updated by the exponential map, never by adding rotation vectors.
//
// The map is linear in the free vertex DOFs and the core's translation, and
// its Jacobian P = ∂u/∂x at x has the columns −[b_i]× J_l(ω') for the
// rotation (b_i = exp([ω'])·a_i). The chain rule through it:
//   gradient over x = Pᵀ G (pull_back), G = ∂E/∂p over the vertices;
//   Hessian over x  = Pᵀ H P + the curvature of the rotation,
//     Σ_i ½(g_i b_iᵀ + b_i g_iᵀ) − (g_i·b_i) I over (ω, ω),
// exact at the committed pose (ω' = 0), where Newton evaluates it. The
// Assembler (assembler.hpp) forms Pᵀ H P stencil by stencil, never as a sparse
// product.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <vector>

namespace palpa {

struct RigidCore {
  std::vector<int> attached;                         // vertices that move with the core
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // c0 [m]
  std::array<bool, 6> locked{false, false, false, false, false, false};  // t_x t_y t_z ω_x ω_y ω_z
};

class DofMap {
 public:
  // rest: the vertices' rest positions (#V×3) [m], read at every call (it
  // must outlive the map; a model's new rest positions are seen). fixed: 3N
  // flags, true for DOFs held at their prescribed value (0 until
  // set_prescribed). core: the rigid core, if any; its attached vertices are
  // neither free nor fixed. Throws palpa::Error (Internal) for flags of the
  // wrong size or an attached vertex out of range.
  DofMap(const Eigen::MatrixX3d& rest, std::vector<char> fixed, std::optional<RigidCore> core = std::nullopt);

  Eigen::Index num_vertices() const noexcept { return rest_->rows(); }
  Eigen::Index num_vertex_dofs() const noexcept { return static_cast<Eigen::Index>(free_.size()); }
  Eigen::Index num_core_dofs() const noexcept { return static_cast<Eigen::Index>(core_dofs_.size()); }
  Eigen::Index num_dofs() const noexcept { return num_vertex_dofs() + num_core_dofs(); }
  // Vertex DOF k of x is full DOF free_dofs()[k]; dof(d) is the inverse (−1
  // for a fixed DOF or one of an attached vertex).
  const std::vector<int>& free_dofs() const noexcept { return free_; }
  int dof(Eigen::Index full) const { return full_to_free_[static_cast<std::size_t>(full)]; }
  const std::vector<char>& fixed() const noexcept { return fixed_; }
  bool has_core() const noexcept { return core_.has_value(); }
  const RigidCore& core() const { return *core_; }
  bool attached(Eigen::Index v) const { return is_attached_[static_cast<std::size_t>(v)] != 0; }
  // Core DOF k of x (x[num_vertex_dofs() + k]) is pose component core_dofs()[k].
  const std::vector<int>& core_dofs() const noexcept { return core_dofs_; }

  // Values of the fixed DOFs: u_fixed (3N), only its fixed entries read.
  void set_prescribed(const Eigen::VectorXd& u_fixed);

  // u (3N) at x, and the deformed positions X + u.
  Eigen::VectorXd displacement(const Eigen::VectorXd& x) const;
  Eigen::VectorXd positions(const Eigen::VectorXd& u) const;
  // The free vertex DOFs of u (no core: x itself).
  Eigen::VectorXd free_part(const Eigen::VectorXd& u) const;

  // The core's pose at x: translation t [m], rotation vector ω and
  // rotation exp([ω'])·R_c.
  Eigen::Vector3d core_translation(const Eigen::VectorXd& x) const;
  Eigen::Vector3d core_omega(const Eigen::VectorXd& x) const;
  Eigen::Matrix3d core_rotation(const Eigen::VectorXd& x) const;

  // The linearization of the core at x: p_i's derivatives by the core DOFs.
  struct Frame {
    Eigen::Matrix3d turn = Eigen::Matrix3d::Identity();      // exp([ω'])·R_c
    Eigen::Matrix3d jacobian = Eigen::Matrix3d::Identity();  // J_l(ω')
  };
  Frame frame(const Eigen::VectorXd& x) const;
  // b_i = exp([ω'])·R_c (X_i − c0) [m] of vertex v.
  Eigen::Vector3d lever(const Frame& f, Eigen::Index v) const;
  // ∂p_v/∂(core DOFs) (3 × num_core_dofs()) of an attached vertex into B.
  void core_jacobian(const Frame& f, Eigen::Index v, Eigen::Ref<Eigen::MatrixXd> B) const;

  // Pᵀ G: the gradient over x of a function of the positions with gradient
  // G (3N) [N]; P z: the vertex displacements (3N) of a change z of x.
  Eigen::VectorXd pull_back(const Eigen::VectorXd& x, const Eigen::VectorXd& G) const;
  Eigen::VectorXd push_forward(const Eigen::VectorXd& x, const Eigen::VectorXd& z) const;
  // The rotation's curvature (3×3 over ω) at x for the vertex gradient G.
  Eigen::Matrix3d curvature(const Eigen::VectorXd& x, const Eigen::VectorXd& G) const;

  // The committed pose (R_c, ω_c): with x it is the whole state of the map,
  // so a state carried to another map of the same body takes both.
  struct Committed {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  };
  Committed committed() const { return committed_; }
  // Throws palpa::Error (Input) for a rotation that is not one.
  void set_committed(const Committed& c);
  void commit(const Eigen::VectorXd& x);

 private:
  Eigen::Vector3d omega_local(const Eigen::VectorXd& x) const { return core_omega(x) - committed_.omega; }

  const Eigen::MatrixX3d* rest_;
  std::vector<char> fixed_;
  std::optional<RigidCore> core_;
  std::vector<char> is_attached_;
  std::vector<int> free_;          // free vertex DOF k -> full DOF
  std::vector<int> full_to_free_;  // full DOF -> free vertex DOF or −1
  std::vector<int> core_dofs_;     // core DOF k -> pose component 0…5
  Eigen::VectorXd prescribed_;     // 3N
  Committed committed_;
};

}  // namespace palpa
