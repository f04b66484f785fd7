// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A System (system.hpp) that is a sum of terms (term.hpp) over a DOF map
// (dof_map.hpp):
//   E(x) = Σ_terms E_t(u(x)) + c·x,
// u(x) the map's vertex displacements and c an optional load on the unknowns
// themselves (the force and torque on a rigid core). Its gradient is Pᵀ ΣG_t
// + c and its Hessian Σ P_tᵀ H_t P_t (the Assembler) plus the rigid core's
// rotational curvature.
//
// Regularization (thesis §7.3.4): a body held by gravity and contact alone
// has no stiffness against rigid motion until it touches something; with
// set_regularization(α, …) the Hessian becomes K + αM (a lumped vertex mass
// through the map, plus a mass on chosen unknowns, e.g. the core's) while no
// term is active(). The energy is unchanged, so the equilibrium is too.
//
// Terms are not owned; they must outlive the system. Every call but
// add_term(), the setters and prepare() is const and safe from several
// threads at once.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

#include "palpa/solve/assembler.hpp"
#include "palpa/solve/dof_map.hpp"
#include "palpa/solve/system.hpp"
#include "palpa/solve/term.hpp"

namespace palpa {

class TermSystem : public System {
 public:
  // newton: the projection hessian() hands the terms (None: the true Hessian,
  // for systems whose Hessian also serves sensitivities).
  TermSystem(DofMap map, PsdProjection newton);
  ~TermSystem() override;
  TermSystem(const TermSystem&) = delete;
  TermSystem& operator=(const TermSystem&) = delete;

  const DofMap& dof_map() const noexcept { return map_; }
  // Non-owning; rebuilds the Hessian's pattern.
  void add_term(Term* term);
  const std::vector<Term*>& terms() const noexcept { return terms_; }

  // c over x [N or N·m]: E += c·x (empty: none).
  void set_dof_load(Eigen::VectorXd c) { dof_load_ = std::move(c); }
  // α [1/s²], the lumped vertex mass (N entries [kg], must outlive the
  // system) and a mass on the unknowns (num_dofs entries, or empty).
  void set_regularization(double alpha, const Eigen::VectorXd* vertex_mass, Eigen::VectorXd dof_mass = {});
  bool regularizing() const;

  // u (3N) at x, and deformed positions X + u.
  Eigen::VectorXd full_displacement(const Eigen::VectorXd& x) const { return map_.displacement(x); }
  Eigen::VectorXd positions(const Eigen::VectorXd& u) const { return map_.positions(u); }

  // E at x and its gradient over the vertices' positions, G (3N) [N]
  // (the terms' only: the load on x is not in it).
  double vertex_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& G) const;

  // The Hessian with the terms' blocks projected as asked, without the
  // regularization (H keeps the pattern, as hessian()).
  void hessian(const Eigen::VectorXd& x, PsdProjection projection, Eigen::SparseMatrix<double>& H) const;
  // The pattern every Hessian shares (lower triangle over x).
  const Eigen::SparseMatrix<double>& pattern() const { return assembler_->pattern(); }
  // H += s · Σ_v m_v P_vᵀ P_v, a lumped vertex mass m (N entries [kg])
  // through the map at x (H a matrix of this pattern).
  void add_vertex_mass(const Eigen::VectorXd& x, const Eigen::VectorXd& m, double s,
                       Eigen::SparseMatrix<double>& H) const {
    assembler_->add_vertex_mass(x, m, s, H);
  }
  // H += the regularization αM where it applies (see above).
  void regularize(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const;
  // The projection hessian() hands the terms.
  PsdProjection newton_projection() const noexcept { return newton_; }

  // System
  Eigen::Index num_dofs() const override { return map_.num_dofs(); }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;
  void prepare(const Eigen::VectorXd& x) override;

 protected:
  DofMap& mutable_dof_map() noexcept { return map_; }

 private:
  double evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* g) const;

  DofMap map_;
  PsdProjection newton_;
  std::vector<Term*> terms_;
  std::unique_ptr<Assembler> assembler_;
  Eigen::VectorXd dof_load_;
  double alpha_ = 0.0;
  const Eigen::VectorXd* vertex_mass_ = nullptr;
  Eigen::VectorXd dof_mass_;
};

}  // namespace palpa
