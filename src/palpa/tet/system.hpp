// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Static equilibrium and implicit dynamics of a tet body (thesis §4.4, §7.3.4)
// as palpa Systems (solve/system.hpp), so Newton and the line searches of the
// solve module find them.
//
// StaticSystem: x = the free DOFs of the nodal displacement u (3N); fixed DOFs
// take prescribed values (zero, or moved with set_prescribed). A TermSystem
// (solve/term_system.hpp) of the elastic energy, gravity's potential, −f_ext·u
// and the terms added to it (e.g. penalty contact with rigid obstacles,
// written by other modules).
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
#include <memory>
#include <vector>

#include "palpa/solve/term_system.hpp"
#include "palpa/tet/elastic_term.hpp"
#include "palpa/tet/model.hpp"

namespace palpa::tet {

// The terms of the body's elastic energy for its element (model.element()):
// an ElasticTerm, or the deviatoric and nodal-volume terms of
// nodal_pressure.hpp. The model must outlive them.
std::vector<std::unique_ptr<Term>> make_elastic_terms(const ElasticModel& model);

// The fixed flags (3N) with every DOF of a vertex that no tet uses set: such
// a vertex has no stiffness at all and is held where it is.
std::vector<char> hold_unused_vertices(const TetMesh& mesh, std::vector<char> fixed);

class StaticSystem : public TermSystem {
 public:
  // fixed: 3N flags, true for DOFs held at their prescribed value (initially
  // 0). Vertices that no tet uses are fixed too. newton: the projection of
  // the element Hessians that hessian() assembles (None: the true Hessian).
  StaticSystem(const ElasticModel& model, std::vector<char> fixed, PsdProjection newton = PsdProjection::Clamp);
  ~StaticSystem() override;

  const ElasticModel& model() const noexcept { return *model_; }
  const std::vector<char>& fixed() const noexcept { return dof_map().fixed(); }
  const std::vector<int>& free_dofs() const noexcept { return dof_map().free_dofs(); }

  // Prescribed displacement of the fixed DOFs: u_fixed (3N); only its fixed
  // entries are read.
  void set_prescribed(const Eigen::VectorXd& u_fixed) { mutable_dof_map().set_prescribed(u_fixed); }
  void set_gravity(const Eigen::Vector3d& gravity) { gravity_.set_coefficients(model_->gravity_gradient(gravity)); }
  // External nodal forces f (3N) [N]: energy −f·u.
  void set_external_forces(const Eigen::VectorXd& f);
  void set_regularization(double alpha) { TermSystem::set_regularization(alpha, &model_->lumped_mass()); }  // [1/s²]

  // x from u.
  Eigen::VectorXd free_part(const Eigen::VectorXd& u) const { return dof_map().free_part(u); }

  // The reaction forces at the fixed DOFs (3N, zero on free DOFs) at x: the
  // forces the supports exert on the body [N].
  Eigen::VectorXd reactions(const Eigen::VectorXd& x) const;

  // K(x): the Hessian without the regularization, the element Hessians
  // projected as asked (H keeps the pattern, as hessian()).
  void stiffness(const Eigen::VectorXd& x, PsdProjection projection, Eigen::SparseMatrix<double>& H) const {
    TermSystem::hessian(x, projection, H);
  }
  // Adds the lumped mass × s to the diagonal of H (a matrix of this pattern).
  void add_mass(double s, Eigen::SparseMatrix<double>& H) const;

 private:
  const ElasticModel* model_;
  std::vector<std::unique_ptr<Term>> elastic_;
  LinearTerm gravity_;
  LinearTerm external_;
};

// One backward-Euler step of a StaticSystem (see above).
class BackwardEulerSystem : public System {
 public:
  struct Damping {
    double mass = 0.0;       // a [1/s]
    double stiffness = 0.0;  // b [s]
  };
  // projection: of the element Hessians in hessian() (default: the statics' own).
  BackwardEulerSystem(StaticSystem& statics, double step, Damping damping);
  BackwardEulerSystem(StaticSystem& statics, double step, Damping damping, PsdProjection projection);

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
  PsdProjection projection_;
  Eigen::VectorXd mass_;  // lumped, per free DOF
  Eigen::VectorXd x_n_;
  Eigen::VectorXd x_hat_;
  Eigen::SparseMatrix<double> damping_matrix_;  // C, full symmetric, free DOFs
};

}  // namespace palpa::tet
