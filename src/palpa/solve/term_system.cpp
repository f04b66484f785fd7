// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/term_system.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace palpa {

Term::~Term() = default;
int Term::stencil(Eigen::Index /*i*/, int* /*vertices*/) const { return 0; }
bool Term::stencil_hessian(const VertexState& /*s*/, Eigen::Index /*i*/, PsdProjection /*projection*/,
                           double* /*h*/) const {
  return true;
}
std::vector<std::array<int, 2>> Term::vertex_pairs() const { return {}; }
void Term::add_blocks(const VertexState& /*s*/, PsdProjection /*projection*/,
                      std::vector<VertexBlock>& /*blocks*/) const {}
void Term::prepare(const VertexState& /*s*/) {}
bool Term::active() const { return false; }

TermSystem::TermSystem(DofMap map, PsdProjection newton)
    : map_(std::move(map)), newton_(newton), assembler_(std::make_unique<Assembler>(map_, std::vector<const Term*>{})) {}

TermSystem::~TermSystem() = default;

void TermSystem::add_term(Term* term) {
  terms_.push_back(term);
  if (!assembler_->extend(term)) {
    assembler_ = std::make_unique<Assembler>(map_, std::vector<const Term*>(terms_.begin(), terms_.end()));
  }
}

void TermSystem::set_regularization(double alpha, const Eigen::VectorXd* vertex_mass, Eigen::VectorXd dof_mass) {
  alpha_ = alpha;
  vertex_mass_ = vertex_mass;
  dof_mass_ = std::move(dof_mass);
}

bool TermSystem::regularizing() const {
  if (!(alpha_ > 0.0)) return false;
  return std::none_of(terms_.begin(), terms_.end(), [](const Term* t) { return t->active(); });
}

double TermSystem::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* g) const {
  const Eigen::VectorXd u = map_.displacement(x);
  const Eigen::VectorXd p = map_.positions(u);
  const VertexState s{u, p};
  double e = 0.0;
  Eigen::VectorXd G;
  if (g != nullptr) G = Eigen::VectorXd::Zero(u.size());
  for (const Term* t : terms_) {
    const double et = g != nullptr ? t->add_gradient(s, G) : t->energy(s);
    if (!std::isfinite(et)) return std::numeric_limits<double>::infinity();
    e += et;
  }
  if (dof_load_.size() > 0) e += dof_load_.dot(x);
  if (g != nullptr) {
    *g = map_.pull_back(x, G);
    if (dof_load_.size() > 0) *g += dof_load_;
  }
  return e;
}

double TermSystem::energy(const Eigen::VectorXd& x) const { return evaluate(x, nullptr); }
void TermSystem::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const { evaluate(x, &g); }
double TermSystem::energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const { return evaluate(x, &g); }

double TermSystem::vertex_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& G) const {
  const Eigen::VectorXd u = map_.displacement(x);
  const Eigen::VectorXd p = map_.positions(u);
  const VertexState s{u, p};
  G = Eigen::VectorXd::Zero(u.size());
  double e = 0.0;
  for (const Term* t : terms_) e += t->add_gradient(s, G);
  return e;
}

void TermSystem::hessian(const Eigen::VectorXd& x, PsdProjection projection, Eigen::SparseMatrix<double>& H) const {
  const Eigen::VectorXd u = map_.displacement(x);
  const Eigen::VectorXd p = map_.positions(u);
  assembler_->assemble(x, {u, p}, projection, H);
  if (map_.num_core_dofs() > 0) {
    // The rotation's curvature, from the vertex gradient at x.
    Eigen::VectorXd G;
    vertex_gradient(x, G);
    assembler_->add_rotation_block(map_.curvature(x, G), H);
  }
}

void TermSystem::regularize(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  if (!regularizing()) return;
  if (vertex_mass_ != nullptr) assembler_->add_vertex_mass(x, *vertex_mass_, alpha_, H);
  if (dof_mass_.size() > 0) assembler_->add_diagonal(dof_mass_, alpha_, H);
}

void TermSystem::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  hessian(x, newton_, H);
  regularize(x, H);
}

void TermSystem::prepare(const Eigen::VectorXd& x) {
  map_.commit(x);
  if (terms_.empty()) return;
  const Eigen::VectorXd u = map_.displacement(x);
  const Eigen::VectorXd p = map_.positions(u);
  for (Term* t : terms_) t->prepare({u, p});
}

}  // namespace palpa
