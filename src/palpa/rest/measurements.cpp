// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/rest/measurements.hpp"

#include <Eigen/Geometry>
#include <algorithm>

#include "palpa/rest/coupled.hpp"

namespace palpa::rest {

ContactPressures contact_pressures(const RestSimulation& sim) {
  ContactPressures out;
  const contact::Obstacle& support = sim.support();
  if (const CoupledSystem* coupled = sim.coupled_system()) {
    coupled->contact_forces(sim.coupled_dofs(), out.body_force, out.support_force);
  } else {
    const Eigen::VectorXd Y = sim.system().positions(sim.dofs());
    out.body_force = Eigen::Matrix3Xd::Zero(3, Y.size() / 3);
    out.support_force = Eigen::Matrix3Xd::Zero(3, support.vertices().rows());
    sim.contact_term().potential().add_forces(support, Eigen::Map<const Eigen::Matrix3Xd>(Y.data(), 3, Y.size() / 3),
                                              out.body_force, out.support_force);
  }
  out.body = Eigen::VectorXd::Zero(out.body_force.cols());
  out.support = Eigen::VectorXd::Zero(out.support_force.cols());
  const Eigen::VectorXd& area = sim.contact_term().pressure_areas();
  for (int v : sim.surface_vertices()) {
    if (area[v] > 0.0) out.body[v] = out.body_force.col(v).norm() / area[v];
  }
  const Eigen::VectorXd& support_area = sim.support_area();
  for (Eigen::Index j = 0; j < out.support.size(); ++j) {
    if (support_area[j] > 0.0) out.support[j] = out.support_force.col(j).norm() / support_area[j];
  }
  return out;
}

void measure(const RestSimulation& sim, RestResult& r) {
  const body::CoreSystem& system = sim.system();
  const Eigen::VectorXd& x = sim.dofs();
  const contact::PenaltyContact& potential = sim.contact_term().potential();
  const Eigen::VectorXd p = system.positions(x);
  r.core_translation = system.core_translation(x);
  r.core_rotation = system.core_rotation(x);
  // One set of nodal contact forces (both passes on a deformable support)
  // gives the balance and both pressure maps.
  const ContactPressures cp = contact_pressures(sim);
  const Eigen::Matrix3Xd& f = cp.body_force;
  if (const CoupledSystem* coupled = sim.coupled_system()) {
    r.reverse_contacts = static_cast<int>(coupled->reverse_contacts().size());
  }
  const Eigen::Vector3d c = system.core().centre + r.core_translation;
  r.contact_force.setZero();
  r.contact_torque.setZero();
  for (Eigen::Index v = 0; v < f.cols(); ++v) {
    if (f.col(v).squaredNorm() == 0.0) continue;
    r.contact_force += f.col(v);
    r.contact_torque += (p.segment<3>(3 * v) - c).cross(f.col(v));
  }
  const body::CoreSpec& core = system.core();
  r.load = sim.options().gravity * (sim.model().total_mass() + core.mass) + core.force;
  Eigen::Vector3d imbalance = r.contact_force + r.load;
  for (int a = 0; a < 3; ++a) {
    if (core.locked[static_cast<std::size_t>(a)]) imbalance[a] = 0.0;
  }
  r.balance_error = r.load.norm() > 0.0 ? imbalance.norm() / r.load.norm() : imbalance.norm();
  r.max_penetration = potential.max_depth();
  r.stiffness = sim.contact_stiffness();
  r.contacts = static_cast<int>(potential.size());
  r.min_det_f = sim.model().min_jacobian(system.full_displacement(x));
  if (const tet::ElasticModel* support_model = sim.support_model()) {
    const tet::StaticSystem& support_system = *sim.support_system();
    const Eigen::VectorXd u = support_system.full_displacement(sim.support_dofs());
    r.support_min_det_f = support_model->min_jacobian(u);
    const Eigen::VectorXd reaction = support_system.reactions(sim.support_dofs());
    r.support_max_displacement = 0.0;
    r.support_base_force.setZero();
    for (Eigen::Index v = 0; v < u.size() / 3; ++v) {
      r.support_max_displacement = std::max(r.support_max_displacement, u.segment<3>(3 * v).norm());
      r.support_base_force += reaction.segment<3>(3 * v);
    }
  }

  // Each vertex's force over its area (the body's skin share, the
  // support's vertex area at rest).
  r.body_pressure = cp.body;
  r.support_pressure = cp.support;
  r.support_contacts = static_cast<int>((cp.support.array() > 0.0).count());
  const Eigen::MatrixX3d body_points =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(p.data(), p.size() / 3, 3);
  r.body_metrics = report::pressure_metrics(body_points, sim.skin_area(), cp.body);
  const contact::Obstacle& support = sim.support();
  Eigen::MatrixX3d support_points(support.vertices().rows(), 3);
  for (Eigen::Index j = 0; j < support_points.rows(); ++j) {
    support_points.row(j) = support.world_vertex(static_cast<int>(j)).transpose();
  }
  r.support_metrics = report::pressure_metrics(support_points, sim.support_area(), cp.support);
  // Integrated as a user would: Σ p·A over each map's vertex areas. That is
  // Σ |f_i|: the load where the contact forces are parallel to it, more where
  // the surface curves and they fan out.
  r.body_map_force = (cp.body.array() * sim.skin_area().array()).sum();
  r.support_map_force = (cp.support.array() * sim.support_area().array()).sum();
}

}  // namespace palpa::rest
