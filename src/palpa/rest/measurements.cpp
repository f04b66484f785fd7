// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/rest/measurements.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "palpa/geometry/surface_operators.hpp"
#include "palpa/rest/coupled.hpp"

namespace palpa::rest {

namespace {

// κ√ā of a pass's committed contacts (0 without any).
double footprint(const contact::PenaltyContact& pass) {
  double area = 0.0;
  for (const contact::SampleContact& c : pass.contacts()) area += pass.samples().area[static_cast<std::size_t>(c.sample)];
  return pass.empty() ? 0.0 : kFootprintSamples * std::sqrt(area / static_cast<double>(pass.size()));
}

}  // namespace

Eigen::MatrixX3d body_points(const RestSimulation& sim) {
  const Eigen::VectorXd Y = sim.system().positions(sim.dofs());
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(Y.data(), Y.size() / 3, 3);
}

Eigen::MatrixX3d support_points(const RestSimulation& sim) {
  const contact::Obstacle& support = sim.support();
  Eigen::MatrixX3d P(support.vertices().rows(), 3);
  for (Eigen::Index j = 0; j < P.rows(); ++j) P.row(j) = support.world_vertex(static_cast<int>(j)).transpose();
  return P;
}

PressureRecovery pressure_recovery(const RestSimulation& sim) {
  const CoupledSystem* coupled = sim.coupled_system();
  const double body = coupled != nullptr ? footprint(coupled->reverse_contacts()) : 0.0;
  const double support = footprint(sim.contact_term().potential());
  return {contact::TractionRecovery(sim.surface_faces(), sim.model().num_vertices(), body),
          contact::TractionRecovery(sim.support().triangles(), sim.support().vertices().rows(), support)};
}

ContactPressures contact_pressures(const RestSimulation& sim) { return contact_pressures(sim, pressure_recovery(sim)); }

ContactPressures contact_pressures(const RestSimulation& sim, const PressureRecovery& recovery) {
  ContactPressures out;
  const contact::Obstacle& support = sim.support();
  const Eigen::MatrixX3d Yb = body_points(sim), Ys = support_points(sim);
  if (const CoupledSystem* coupled = sim.coupled_system()) {
    coupled->contact_forces(sim.coupled_dofs(), out.body_force, out.support_force);
  } else {
    out.body_force = Eigen::Matrix3Xd::Zero(3, Yb.rows());
    out.support_force = Eigen::Matrix3Xd::Zero(3, support.vertices().rows());
    sim.contact_term().potential().add_forces(support, Yb.transpose(), out.body_force, out.support_force);
  }
  out.body = recovery.body.recover(Yb, out.body_force.colwise().norm().transpose());
  out.support = recovery.support.recover(Ys, out.support_force.colwise().norm().transpose());
  out.body_area = geometry::vertex_areas(Yb, recovery.body.triangles());
  out.support_area = geometry::vertex_areas(Ys, recovery.support.triangles());
  return out;
}

ContactAreas contact_areas(const RestSimulation& sim, const PressureRecovery& recovery, const ContactPressures& cp) {
  const Eigen::MatrixX3d Yb = body_points(sim), Ys = support_points(sim);
  Eigen::VectorXd in_body, in_support;  // the areas in contact, deposited
  if (const CoupledSystem* coupled = sim.coupled_system()) {
    coupled->contact_areas(sim.coupled_dofs(), in_body, in_support);
  } else {
    in_body = Eigen::VectorXd::Zero(Yb.rows());
    in_support = Eigen::VectorXd::Zero(Ys.rows());
    sim.contact_term().potential().add_contact_areas(sim.body().mesh.V.transpose(), Yb.transpose(), in_body,
                                                     in_support);
  }
  // The recovered share of each vertex's area in contact.
  return {recovery.body.recover(Yb, in_body).cwiseMin(1.0).cwiseProduct(cp.body_area),
          recovery.support.recover(Ys, in_support).cwiseMin(1.0).cwiseProduct(cp.support_area)};
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
  const PressureRecovery recovery = pressure_recovery(sim);
  const ContactPressures cp = contact_pressures(sim, recovery);
  const ContactAreas in_contact = contact_areas(sim, recovery, cp);
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

  // Traction per deformed area on both sides (contact_pressures).
  r.body_pressure = cp.body;
  r.support_pressure = cp.support;
  r.support_contacts = static_cast<int>((cp.support.array() > 0.0).count());
  r.body_metrics = report::pressure_metrics(body_points(sim), cp.body_area, cp.body, in_contact.body);
  r.support_metrics = report::pressure_metrics(support_points(sim), cp.support_area, cp.support, in_contact.support);
  // Σ p·A over each map's vertex areas where it is drawn: Σ |f_i|, the load
  // where the contact forces are parallel to it, more where the surface
  // curves and they fan out.
  r.body_map_force = cp.body.dot(cp.body_area);
  r.support_map_force = cp.support.dot(cp.support_area);
}

}  // namespace palpa::rest
