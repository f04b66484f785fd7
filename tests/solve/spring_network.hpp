// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A 2D network of nonlinear springs with pinned nodes and nodal loads: the
// smallest realistic System (geometrically nonlinear, sparse, indefinite when
// springs are compressed) for the Newton tests and the solve benchmark.
//
//   E(x) = Σ_springs k/2 (l − L)² − Σ_free nodes f·p        [J]
// l = |p_a − p_b| (current length), L rest length, k stiffness [N/m], f nodal
// load [N]. DOFs: (x, y) of every free node in node order [m].
// Also a ParametricSystem: θ = the spring stiffnesses [N/m].

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

#include "palpa/solve/parametric_system.hpp"
#include "palpa/solve/system.hpp"

namespace palpa::test {

struct Spring {
  int a = 0;
  int b = 0;
  double rest_length = 0.0;  // [m]
  double stiffness = 0.0;    // [N/m]
};

class SpringNetwork final : public System, public ParametricSystem {
 public:
  // nodes: #nodes×2 reference positions [m] (pinned nodes stay there);
  // pinned: indices of the pinned nodes.
  SpringNetwork(Eigen::MatrixX2d nodes, std::vector<Spring> springs,
                const std::vector<int>& pinned);

  // nx×ny nodes at spacing h [m]; springs (stiffness k [N/m], at rest) along the
  // grid lines and both diagonals of every cell; the nodes with x = 0 are pinned.
  // Node (i, j) has index i + nx·j.
  static SpringNetwork grid(int nx, int ny, double h, double k);

  // A chain along +x from a pinned node 0 at the origin: spring i joins nodes i
  // and i+1, at rest.
  static SpringNetwork chain(const std::vector<double>& rest_lengths,
                             const std::vector<double>& stiffnesses);

  int num_nodes() const noexcept { return static_cast<int>(nodes_.rows()); }
  int num_springs() const noexcept { return static_cast<int>(springs_.size()); }
  // First DOF of a node (x; y is the next one), or -1 for a pinned node.
  int dof_of(int node) const { return dof_[static_cast<std::size_t>(node)]; }

  // External load on a free node [N].
  void set_force(int node, const Eigen::Vector2d& f);
  void set_stiffness(int spring, double k);

  // x of the reference configuration.
  Eigen::VectorXd reference_dofs() const;
  // Positions of all nodes (#nodes×2) for DOFs x.
  Eigen::MatrixX2d positions(const Eigen::VectorXd& x) const;
  // Total force the pins exert on the network [N]; equals minus the total load
  // at equilibrium.
  Eigen::Vector2d support_reaction(const Eigen::VectorXd& x) const;

  Eigen::Index num_dofs() const override { return num_dofs_; }
  double energy(const Eigen::VectorXd& x) const override;
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const override;

  Eigen::Index num_params() const override { return num_springs(); }
  void gradient_param_jacobian(const Eigen::VectorXd& x,
                               Eigen::SparseMatrix<double>& J) const override;

 private:
  Eigen::Vector2d node_position(const Eigen::VectorXd& x, int node) const;
  // The four DOFs of a spring (a.x, a.y, b.x, b.y), -1 where pinned.
  std::array<int, 4> spring_dofs(const Spring& s) const;

  Eigen::MatrixX2d nodes_;
  std::vector<Spring> springs_;
  std::vector<int> dof_;
  Eigen::Index num_dofs_ = 0;
  Eigen::VectorXd force_;  // per free DOF [N]
  // The Hessian's lower-triangle pattern, built once, and for each spring the
  // index into its values of each of the 16 entries of the spring's 4×4 block
  // (-1: upper triangle or pinned).
  Eigen::SparseMatrix<double> pattern_;
  std::vector<std::array<int, 16>> slots_;
};

}  // namespace palpa::test
