// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/body/core_system.hpp"

#include <cmath>
#include <fmt/format.h>

#include "palpa/core/error.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::body {

namespace {

// The map of a layer on its core, after checking the core.
DofMap core_map(const tet::ElasticModel& model, const CoreSpec& core) {
  const Eigen::Index nv = model.num_vertices();
  if (core.attached.empty()) {
    throw Error(ErrorKind::Input, "the rigid core has no attached vertices: nothing holds the layer to it");
  }
  if (!std::isfinite(core.mass) || core.mass < 0.0) {
    throw Error(ErrorKind::Input, fmt::format("core mass must be finite and ≥ 0 kg, got {}", core.mass));
  }
  if (!core.centre.allFinite() || !core.force.allFinite() || !core.torque.allFinite()) {
    throw Error(ErrorKind::Input, "core centre, force and torque must be finite");
  }
  for (int v : core.attached) {
    if (v < 0 || v >= nv) {
      throw Error(ErrorKind::Input, fmt::format("attached vertex {} is not a vertex of the layer ({} vertices)", v, nv));
    }
  }
  DofMap map(model.mesh().V,
             tet::hold_unused_vertices(model.mesh(), std::vector<char>(static_cast<std::size_t>(3 * nv), 0)),
             RigidCore{core.attached, core.centre, core.locked});
  if (map.num_dofs() == 0) {
    throw Error(ErrorKind::Input, "every core DOF is locked and every vertex is attached: nothing can move");
  }
  return map;
}

}  // namespace

CoreSystem::CoreSystem(const tet::ElasticModel& model, CoreSpec core, PsdProjection newton)
    : TermSystem(core_map(model, core), newton),
      model_(&model),
      core_(std::move(core)),
      elastic_(tet::make_elastic_terms(model)),
      gravity_(Eigen::VectorXd::Zero(model.num_dofs())) {
  for (const auto& t : elastic_) add_term(t.get());
  add_term(&gravity_);
  set_gravity(Eigen::Vector3d::Zero());
}

CoreSystem::~CoreSystem() = default;

void CoreSystem::set_gravity(const Eigen::Vector3d& g) {
  gravity_.set_coefficients(model_->gravity_gradient(g));
  // The core's own potential: −m_c g·t − F·t − τ·ω.
  Eigen::VectorXd load = Eigen::VectorXd::Zero(num_dofs());
  const Eigen::Vector3d f = -core_.mass * g - core_.force;
  const std::vector<int>& dofs = dof_map().core_dofs();
  for (std::size_t k = 0; k < dofs.size(); ++k) {
    const int c = dofs[k];
    load[num_vertex_dofs() + static_cast<Eigen::Index>(k)] = c < 3 ? f[c] : -core_.torque[c - 3];
  }
  set_dof_load(std::move(load));
}

void CoreSystem::set_regularization(double alpha) {
  // K + α(Pᵀ M P + the core's mass on its translation).
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(num_dofs());
  const std::vector<int>& dofs = dof_map().core_dofs();
  for (std::size_t k = 0; k < dofs.size(); ++k) {
    if (dofs[k] < 3) mass[num_vertex_dofs() + static_cast<Eigen::Index>(k)] = core_.mass;
  }
  TermSystem::set_regularization(alpha, &model_->lumped_mass(), std::move(mass));
}

}  // namespace palpa::body
