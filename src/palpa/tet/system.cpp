// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/tet/system.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "palpa/core/error.hpp"
#include "palpa/tet/nodal_pressure.hpp"

namespace palpa::tet {

std::vector<std::unique_ptr<Term>> make_elastic_terms(const ElasticModel& model) {
  std::vector<std::unique_ptr<Term>> terms;
  if (model.element() == TetElement::NodalPressure) {
    terms.push_back(std::make_unique<DeviatoricTerm>(model));
    terms.push_back(std::make_unique<NodalVolumeTerm>(model));
  } else {
    terms.push_back(std::make_unique<ElasticTerm>(model));
  }
  return terms;
}

std::vector<char> hold_unused_vertices(const TetMesh& mesh, std::vector<char> fixed) {
  std::vector<char> used(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (Eigen::Index e = 0; e < mesh.T.rows(); ++e) {
    for (int a = 0; a < 4; ++a) used[static_cast<std::size_t>(mesh.T(e, a))] = 1;
  }
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (!used[v]) fixed[3 * v] = fixed[3 * v + 1] = fixed[3 * v + 2] = 1;
  }
  return fixed;
}

namespace {

std::vector<char> checked_flags(const ElasticModel& model, std::vector<char> fixed) {
  if (static_cast<Eigen::Index>(fixed.size()) != model.num_dofs()) {
    throw Error(ErrorKind::Internal, fmt::format("{} fixed-DOF flags for {} DOFs", fixed.size(), model.num_dofs()));
  }
  return hold_unused_vertices(model.mesh(), std::move(fixed));
}

}  // namespace

StaticSystem::StaticSystem(const ElasticModel& model, std::vector<char> fixed, PsdProjection newton)
    : TermSystem(DofMap(model.mesh().V, checked_flags(model, std::move(fixed))), newton),
      model_(&model),
      elastic_(make_elastic_terms(model)),
      gravity_(Eigen::VectorXd::Zero(model.num_dofs())),
      external_(Eigen::VectorXd::Zero(model.num_dofs())) {
  for (const auto& t : elastic_) add_term(t.get());
  add_term(&gravity_);
  add_term(&external_);
}

StaticSystem::~StaticSystem() = default;

void StaticSystem::set_external_forces(const Eigen::VectorXd& f) {
  if (f.size() != model_->num_dofs()) throw Error(ErrorKind::Internal, "external forces of the wrong size");
  external_.set_coefficients(-f);
}

void StaticSystem::add_mass(double s, Eigen::SparseMatrix<double>& H) const {
  add_vertex_mass(Eigen::VectorXd::Zero(num_dofs()), model_->lumped_mass(), s, H);
}

Eigen::VectorXd StaticSystem::reactions(const Eigen::VectorXd& x) const {
  Eigen::VectorXd g;
  vertex_gradient(x, g);
  // At equilibrium the free part of g vanishes; at a fixed DOF the support
  // supplies the force g (= ∂E/∂u there) that balances the rest.
  for (Eigen::Index d = 0; d < g.size(); ++d) {
    if (!dof_map().fixed()[static_cast<std::size_t>(d)]) g[d] = 0.0;
  }
  return g;
}

// ---------------------------------------------------------------- dynamics

BackwardEulerSystem::BackwardEulerSystem(StaticSystem& statics, double step, Damping damping)
    : BackwardEulerSystem(statics, step, damping, statics.newton_projection()) {}

BackwardEulerSystem::BackwardEulerSystem(StaticSystem& statics, double step, Damping damping, PsdProjection projection)
    : statics_(&statics), h_(step), damping_(damping), projection_(projection) {
  if (!(step > 0.0) || !std::isfinite(step)) {
    throw Error(ErrorKind::Input, fmt::format("time step must be > 0 s, got {}", step));
  }
  if (!(damping.mass >= 0.0) || !(damping.stiffness >= 0.0)) {
    throw Error(ErrorKind::Input, "Rayleigh damping coefficients must be ≥ 0");
  }
  const Eigen::VectorXd& m = statics.model().lumped_mass();
  mass_.resize(statics.num_dofs());
  for (std::size_t k = 0; k < statics.free_dofs().size(); ++k) {
    mass_[static_cast<Eigen::Index>(k)] = m[statics.free_dofs()[k] / 3];
  }
}

void BackwardEulerSystem::begin_step(const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
  x_n_ = x;
  x_hat_ = x + h_ * v;
  damping_matrix_.resize(0, 0);
  if (damping_.stiffness > 0.0) {
    statics_->stiffness(x, PsdProjection::Clamp, damping_matrix_);
    damping_matrix_ *= damping_.stiffness;
  }
}

double BackwardEulerSystem::inertia(const Eigen::VectorXd& x, Eigen::VectorXd* g) const {
  const Eigen::VectorXd d = x - x_hat_;
  const Eigen::VectorXd dn = x - x_n_;
  const double c = 1.0 / (h_ * h_);
  double e = 0.5 * c * d.dot(mass_.cwiseProduct(d)) + 0.5 * damping_.mass / h_ * dn.dot(mass_.cwiseProduct(dn));
  Eigen::VectorXd cd;
  if (damping_matrix_.rows() > 0) {
    cd = damping_matrix_.selfadjointView<Eigen::Lower>() * dn;
    e += 0.5 / h_ * dn.dot(cd);
  }
  if (g != nullptr) {
    *g += c * mass_.cwiseProduct(d) + damping_.mass / h_ * mass_.cwiseProduct(dn);
    if (damping_matrix_.rows() > 0) *g += cd / h_;
  }
  return e;
}

double BackwardEulerSystem::energy(const Eigen::VectorXd& x) const {
  const double e = statics_->energy(x);
  if (!std::isfinite(e)) return e;
  return e + inertia(x, nullptr);
}

void BackwardEulerSystem::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  statics_->gradient(x, g);
  inertia(x, &g);
}

double BackwardEulerSystem::energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  const double e = statics_->energy_gradient(x, g);
  if (!std::isfinite(e)) return e;
  return e + inertia(x, &g);
}

void BackwardEulerSystem::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  statics_->hessian(x, projection_, H);
  statics_->regularize(x, H);
  // Inertia and mass damping on the diagonal (lumped): (1/h² + a/h) m.
  statics_->add_mass(1.0 / (h_ * h_) + damping_.mass / h_, H);
  if (damping_matrix_.rows() > 0) {
    // C has H's pattern (both are the statics' pattern).
    double* values = H.valuePtr();
    const double* c = damping_matrix_.valuePtr();
    for (Eigen::Index k = 0; k < H.nonZeros(); ++k) values[k] += c[k] / h_;
  }
}

}  // namespace palpa::tet
