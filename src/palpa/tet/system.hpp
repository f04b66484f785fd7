// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Static equilibrium and implicit dynamics of a tet body (thesis §4.4, §7.3.4)
// as palpa Systems (solve/system.hpp), so Newton and the line searches of the
// solve module find them.
//
// StaticSystem: x = the free DOFs of the nodal displacement u (3N); fixed DOFs
// take prescribed values (zero, or moved with set_prescribed). Energy =
// elastic + gravity potential − f_ext·u + the energies of the attached vertex
// terms (e.g. penalty contact with rigid obstacles, written by other modules).
//
// Vertex terms. A VertexTerm is an energy of deformed vertex positions whose
// Hessian has 3×3 blocks on single vertices and on the vertex pairs it names
// up front (vertex_pairs(): e.g. the corners of a skin triangle whose
// contact traction is integrated over it), each pair sharing a tet, so that
// it fits the elastic Hessian's pattern and the pattern never changes. Terms do their own collision detection at every call
// (so energy at a line-search trial sees the contacts of that trial); prepare()
// lets them commit what they found at an accepted iterate (for reporting and
// for active()).
//
// Regularization (§7.3.4): a body held by gravity and contact alone has no
// stiffness against rigid motion until it touches something; with
// set_regularization(α) the Hessian becomes K + αM (lumped M) while no term
// reports active contact. The energy is unchanged, so the equilibrium is too.
//
// BackwardEulerSystem: one implicit step of size h with Rayleigh damping
// C = a M + b K(x_n) (K PSD-projected at the start of the step):
//   E_h(x) = E(x) + ½ (x − x̂)ᵀ M (x − x̂)/h² + ½ (x − x_n)ᵀ C (x − x_n)/h,
// x̂ = x_n + h v_n; its minimizer is the backward-Euler update (§4.4).

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "palpa/solve/system.hpp"
#include "palpa/tet/model.hpp"

namespace palpa::tet {

// ∂²E/∂x_row∂x_col [N/m], a 3×3 block of a vertex term's Hessian.
struct VertexBlock {
  int row = -1;
  int col = -1;
  Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
};

class VertexTerm {
 public:
  virtual ~VertexTerm();
  // E at deformed positions x (3N, vertex-major) [J]; +infinity if inadmissible.
  virtual double energy(const Eigen::VectorXd& x) const = 0;
  // E, and adds ∂E/∂x into g (3N).
  virtual double add_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const = 0;
  // Adds the 3×3 blocks of ∂²E/∂x² at x into `blocks`: (v, v) blocks, and
  // (a, b) blocks of pairs among vertex_pairs(), each pair in both orders
  // (the system keeps the lower triangle).
  virtual void add_hessian(const Eigen::VectorXd& x, bool true_hessian, std::vector<VertexBlock>& blocks) const = 0;
  // The pairs of distinct vertices whose blocks add_hessian() may add, each
  // once in either order. Default: none.
  virtual std::vector<std::array<int, 2>> vertex_pairs() const;
  // Commits the state at an accepted iterate x. Default: nothing.
  virtual void prepare(const Eigen::VectorXd& x);
  // Whether the committed state has any contact (switches off the K + αM
  // regularization). Default: false.
  virtual bool active() const;

 protected:
  VertexTerm() = default;
  VertexTerm(const VertexTerm&) = default;
  VertexTerm& operator=(const VertexTerm&) = default;
};

class StaticSystem : public System {
 public:
  // fixed: 3N flags, true for DOFs held at their prescribed value (initially
  // 0). Vertices that no tet uses are fixed too.
  StaticSystem(const ElasticModel& model, std::vector<char> fixed);
  ~StaticSystem() override;

  const ElasticModel& model() const noexcept { return *model_; }
  const std::vector<char>& fixed() const noexcept { return fixed_; }
  const std::vector<int>& free_dofs() const noexcept { return free_dofs_; }

  // Prescribed displacement of the fixed DOFs: u_fixed (3N); only its fixed
  // entries are read.
  void set_prescribed(const Eigen::VectorXd& u_fixed);
  void set_gravity(const Eigen::Vector3d& gravity) { gravity_gradient_ = model_->gravity_gradient(gravity); }
  // External nodal forces f (3N) [N]: energy −f·u.
  void set_external_forces(const Eigen::VectorXd& f);
  // Non-owning; the term must outlive the system. Throws palpa::Error
  // (Internal) if one of its vertex_pairs() shares no tet.
  void add_term(VertexTerm* term);
  void set_regularization(double alpha) noexcept { alpha_ = alpha; }  // [1/s²]
  void set_true_hessian(bool on) noexcept { true_hessian_ = on; }
  bool regularizing() const;

  // u (3N) from x (free DOFs), and x from u.
  Eigen::VectorXd full_displacement(const Eigen::VectorXd& x) const;
  Eigen::VectorXd free_part(const Eigen::VectorXd& u) const;
  // Deformed positions X + u (3N).
  Eigen::VectorXd positions(const Eigen::VectorXd& u) const;

  // The reaction forces at the fixed DOFs (3N, zero on free DOFs) at x: the
  // forces the supports exert on the body [N].
  Eigen::VectorXd reactions(const Eigen::VectorXd& x) const;

  // System
  Eigen::Index num_dofs() const override { return static_cast<Eigen::Index>(free_dofs_.size()); }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  void prepare(const Eigen::VectorXd& x) override;

  // K(x): the Hessian without the regularization, PSD-projected unless
  // true_hessian (H keeps the pattern, as hessian()).
  void stiffness(const Eigen::VectorXd& x, bool true_hessian, Eigen::SparseMatrix<double>& H) const;

  // The pattern all Hessians share (lower triangle, free DOFs).
  const Eigen::SparseMatrix<double>& pattern() const noexcept { return pattern_; }
  // Adds the lumped mass × s to the diagonal of H (a matrix of this pattern).
  void add_mass(double s, Eigen::SparseMatrix<double>& H) const;

 private:
  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* g) const;
  void add_vertex_block(const VertexBlock& b, double* values) const;

  const ElasticModel* model_;
  std::vector<char> fixed_;
  std::vector<int> free_dofs_;    // free index -> full DOF
  std::vector<int> full_to_free_; // full DOF -> free index or −1
  Eigen::VectorXd prescribed_;    // 3N
  Eigen::VectorXd gravity_gradient_;
  Eigen::VectorXd external_;
  std::vector<VertexTerm*> terms_;
  double alpha_ = 0.0;
  bool true_hessian_ = false;
  Eigen::SparseMatrix<double> pattern_;
  std::vector<std::array<int, 144>> element_slots_;
  std::vector<std::array<int, 9>> vertex_slots_;
  // Slots of the (a, b) blocks of the terms' vertex pairs, both orders
  // (entry 3j + i is row i, column j; −1 where upper or fixed).
  std::unordered_map<std::uint64_t, std::array<int, 9>> pair_slots_;
};

// One backward-Euler step of a StaticSystem (see above).
class BackwardEulerSystem : public System {
 public:
  struct Damping {
    double mass = 0.0;       // a [1/s]
    double stiffness = 0.0;  // b [s]
  };
  BackwardEulerSystem(StaticSystem& statics, double step, Damping damping);

  // Starts a step from (x_n, v_n) (free DOFs): fixes x̂ and C = aM + bK(x_n).
  void begin_step(const Eigen::VectorXd& x, const Eigen::VectorXd& v);
  double step() const noexcept { return h_; }

  Eigen::Index num_dofs() const override { return statics_->num_dofs(); }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  void prepare(const Eigen::VectorXd& x) override { statics_->prepare(x); }

 private:
  double inertia(const Eigen::VectorXd& x, Eigen::VectorXd* g) const;

  StaticSystem* statics_;
  double h_;
  Damping damping_;
  Eigen::VectorXd mass_;  // lumped, per free DOF
  Eigen::VectorXd x_n_;
  Eigen::VectorXd x_hat_;
  Eigen::SparseMatrix<double> damping_matrix_;  // C, full symmetric, free DOFs
};

}  // namespace palpa::tet
