// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/rest/adjoint.hpp"

#include "palpa/rest/coupled.hpp"

namespace palpa::rest {

void contact_hessian_product(const RestSimulation& sim, const Eigen::Matrix3Xd& v_body,
                             const Eigen::Matrix3Xd& v_support, Eigen::Matrix3Xd& body, Eigen::Matrix3Xd& support) {
  if (const CoupledSystem* coupled = sim.coupled_system()) {
    coupled->contact_hessian_product(sim.coupled_dofs(), v_body, v_support, body, support);
    return;
  }
  const Eigen::VectorXd Y = sim.system().positions(sim.dofs());
  body = Eigen::Matrix3Xd::Zero(3, v_body.cols());
  support = Eigen::Matrix3Xd::Zero(3, v_support.cols());
  sim.contact_term().potential().add_hessian_product(sim.support(),
                                                     Eigen::Map<const Eigen::Matrix3Xd>(Y.data(), 3, Y.size() / 3),
                                                     v_body, v_support, body, support);
}

AdjointStatus shape_derivative(RestSimulation& sim, const Eigen::VectorXd& d_body, const Eigen::MatrixX3d& d_support,
                               Eigen::MatrixX3d& out) {
  body::CoreSystem& system = sim.system();
  const Eigen::VectorXd& x = sim.dofs();
  CoupledSystem* coupled = sim.coupled_system();
  if (coupled == nullptr) {
    // Y_support = X: the direct part, and the equilibrium's response through
    // the contacts' mixed blocks H_pq (K z = Pᵀ d_body, then −Σ H_qpᵀ P z).
    Eigen::VectorXd z;
    const AdjointStatus st = solve_adjoint(sim.newton(), system, x, system.pull_back(x, d_body), z);
    if (!st.ok()) return st;
    const Eigen::VectorXd w = system.push_forward(x, z);
    const Eigen::VectorXd Y = system.positions(x);
    const contact::Points points = Eigen::Map<const Eigen::Matrix3Xd>(Y.data(), 3, Y.size() / 3);
    const Eigen::Matrix3Xd none(3, 0);
    Eigen::Matrix3Xd on_points = Eigen::Matrix3Xd::Zero(3, points.cols());
    Eigen::Matrix3Xd on_support = Eigen::Matrix3Xd::Zero(3, sim.support_rest_vertices().rows());
    sim.contact_term().potential().add_hessian_product(
        sim.support(), points, Eigen::Map<const Eigen::Matrix3Xd>(w.data(), 3, w.size() / 3), none, on_points,
        on_support);
    out = d_support - on_support.transpose();
    return st;
  }
  // Deformable (7.21–7.23): f sees the deformed positions y only; X enters
  // the equilibrium through the support's elastic forces, so
  // df/dX = −(∂g/∂X)ᵀ z with K z = ∂f/∂y.
  const Eigen::VectorXd y = sim.coupled_dofs();
  Eigen::VectorXd rhs(y.size());
  rhs << system.pull_back(x, d_body), coupled->support_free_part(d_support);
  Eigen::VectorXd z;
  const AdjointStatus st = solve_adjoint(sim.newton(), *coupled, y, rhs, z);
  if (!st.ok()) return st;
  // z over the support's full DOFs (0 on its base).
  const tet::ElasticModel& support_model = *sim.support_model();
  const tet::StaticSystem& support_system = *sim.support_system();
  Eigen::VectorXd zs = Eigen::VectorXd::Zero(support_model.num_dofs());
  const std::vector<int>& free = support_system.free_dofs();
  for (std::size_t k = 0; k < free.size(); ++k) zs[free[k]] = z[x.size() + static_cast<Eigen::Index>(k)];
  const Eigen::MatrixX3d G = support_model.rest_gradient_product(support_system.full_displacement(sim.support_dofs()), zs);
  out = -G.topRows(sim.support_rest_vertices().rows());
  return st;
}

}  // namespace palpa::rest
