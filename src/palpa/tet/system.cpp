// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/tet/system.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "palpa/core/error.hpp"

namespace palpa::tet {

VertexTerm::~VertexTerm() = default;
void VertexTerm::prepare(const Eigen::VectorXd&) {}
bool VertexTerm::active() const { return false; }
std::vector<std::array<int, 2>> VertexTerm::vertex_pairs() const { return {}; }

namespace {

std::uint64_t pair_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

}  // namespace

StaticSystem::StaticSystem(const ElasticModel& model, std::vector<char> fixed)
    : model_(&model), fixed_(std::move(fixed)) {
  const Eigen::Index n = model.num_dofs();
  if (static_cast<Eigen::Index>(fixed_.size()) != n) {
    throw Error(ErrorKind::Internal, fmt::format("{} fixed-DOF flags for {} DOFs", fixed_.size(), n));
  }
  // A vertex no tet uses has no stiffness at all: it is held where it is.
  {
    std::vector<char> used(static_cast<std::size_t>(model.num_vertices()), 0);
    for (Eigen::Index e = 0; e < model.num_elements(); ++e) {
      for (int a = 0; a < 4; ++a) used[static_cast<std::size_t>(model.mesh().T(e, a))] = 1;
    }
    for (std::size_t v = 0; v < used.size(); ++v) {
      if (!used[v]) fixed_[3 * v] = fixed_[3 * v + 1] = fixed_[3 * v + 2] = 1;
    }
  }
  full_to_free_.assign(static_cast<std::size_t>(n), -1);
  for (Eigen::Index d = 0; d < n; ++d) {
    if (!fixed_[static_cast<std::size_t>(d)]) {
      full_to_free_[static_cast<std::size_t>(d)] = static_cast<int>(free_dofs_.size());
      free_dofs_.push_back(static_cast<int>(d));
    }
  }
  prescribed_ = Eigen::VectorXd::Zero(n);
  gravity_gradient_ = Eigen::VectorXd::Zero(n);
  external_ = Eigen::VectorXd::Zero(n);

  // The pattern: every pair of free DOFs of a tet (lower triangle), which
  // includes every vertex's own 3×3 block.
  const TetMesh& mesh = model.mesh();
  const auto dof = [&](Eigen::Index e, int i) {
    return full_to_free_[static_cast<std::size_t>(3 * mesh.T(e, i / 3) + i % 3)];
  };
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(static_cast<std::size_t>(mesh.T.rows()) * 78);
  for (Eigen::Index e = 0; e < mesh.T.rows(); ++e) {
    for (int i = 0; i < 12; ++i) {
      for (int j = 0; j < 12; ++j) {
        const int fi = dof(e, i);
        const int fj = dof(e, j);
        if (fi >= 0 && fj >= 0 && fi >= fj) trip.emplace_back(fi, fj, 0.0);
      }
    }
  }
  const auto nf = static_cast<Eigen::Index>(free_dofs_.size());
  pattern_.resize(nf, nf);
  pattern_.setFromTriplets(trip.begin(), trip.end());
  pattern_.makeCompressed();
  const auto slot = [&](int row, int col) { return lower_slot(pattern_, row, col); };
  element_slots_.resize(static_cast<std::size_t>(mesh.T.rows()));
  for (Eigen::Index e = 0; e < mesh.T.rows(); ++e) {
    auto& s = element_slots_[static_cast<std::size_t>(e)];
    for (int i = 0; i < 12; ++i) {
      for (int j = 0; j < 12; ++j) {
        const int fi = dof(e, i);
        const int fj = dof(e, j);
        s[static_cast<std::size_t>(12 * j + i)] = (fi >= 0 && fj >= 0 && fi >= fj) ? slot(fi, fj) : -1;
      }
    }
  }
  vertex_slots_.resize(static_cast<std::size_t>(mesh.V.rows()));
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) {
    auto& s = vertex_slots_[static_cast<std::size_t>(v)];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const int fi = full_to_free_[static_cast<std::size_t>(3 * v + i)];
        const int fj = full_to_free_[static_cast<std::size_t>(3 * v + j)];
        s[static_cast<std::size_t>(3 * j + i)] = (fi >= 0 && fj >= 0 && fi >= fj) ? slot(fi, fj) : -1;
      }
    }
  }
}

StaticSystem::~StaticSystem() = default;

void StaticSystem::set_prescribed(const Eigen::VectorXd& u_fixed) {
  if (u_fixed.size() != prescribed_.size()) {
    throw Error(ErrorKind::Internal, "prescribed displacement of the wrong size");
  }
  for (Eigen::Index d = 0; d < u_fixed.size(); ++d) {
    prescribed_[d] = fixed_[static_cast<std::size_t>(d)] ? u_fixed[d] : 0.0;
  }
}

void StaticSystem::set_external_forces(const Eigen::VectorXd& f) {
  if (f.size() != external_.size()) throw Error(ErrorKind::Internal, "external forces of the wrong size");
  external_ = f;
}

bool StaticSystem::regularizing() const {
  if (!(alpha_ > 0.0)) return false;
  return std::none_of(terms_.begin(), terms_.end(), [](const VertexTerm* t) { return t->active(); });
}

Eigen::VectorXd StaticSystem::full_displacement(const Eigen::VectorXd& x) const {
  Eigen::VectorXd u = prescribed_;
  for (std::size_t k = 0; k < free_dofs_.size(); ++k) u[free_dofs_[k]] = x[static_cast<Eigen::Index>(k)];
  return u;
}

Eigen::VectorXd StaticSystem::free_part(const Eigen::VectorXd& u) const {
  Eigen::VectorXd x(num_dofs());
  for (std::size_t k = 0; k < free_dofs_.size(); ++k) x[static_cast<Eigen::Index>(k)] = u[free_dofs_[k]];
  return x;
}

Eigen::VectorXd StaticSystem::positions(const Eigen::VectorXd& u) const {
  const Eigen::MatrixX3d& V = model_->mesh().V;
  Eigen::VectorXd p(u.size());
  for (Eigen::Index v = 0; v < V.rows(); ++v) p.segment<3>(3 * v) = V.row(v).transpose() + u.segment<3>(3 * v);
  return p;
}

double StaticSystem::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* g) const {
  const Eigen::VectorXd u = full_displacement(x);
  Eigen::VectorXd full_g;
  double e = model_->elastic_energy(u, g != nullptr ? &full_g : nullptr);
  if (!std::isfinite(e)) return std::numeric_limits<double>::infinity();
  e += gravity_gradient_.dot(u) - external_.dot(u);
  if (!terms_.empty()) {
    const Eigen::VectorXd p = positions(u);
    for (const VertexTerm* t : terms_) {
      const double et = g != nullptr ? t->add_gradient(p, full_g) : t->energy(p);
      if (!std::isfinite(et)) return std::numeric_limits<double>::infinity();
      e += et;
    }
  }
  if (g != nullptr) {
    full_g += gravity_gradient_ - external_;
    g->resize(num_dofs());
    for (std::size_t k = 0; k < free_dofs_.size(); ++k) (*g)[static_cast<Eigen::Index>(k)] = full_g[free_dofs_[k]];
  }
  return e;
}

double StaticSystem::energy(const Eigen::VectorXd& x) const { return evaluate(x, nullptr); }
void StaticSystem::gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const { evaluate(x, &g); }
double StaticSystem::energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const {
  return evaluate(x, &g);
}

void StaticSystem::add_term(VertexTerm* term) {
  const std::vector<std::array<int, 2>> pairs = term->vertex_pairs();
  for (const auto& [a, b] : pairs) {
    for (const auto& [r, c] : {std::array<int, 2>{a, b}, std::array<int, 2>{b, a}}) {
      std::array<int, 9> s{};
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const int fi = full_to_free_[static_cast<std::size_t>(3 * r + i)];
          const int fj = full_to_free_[static_cast<std::size_t>(3 * c + j)];
          int& slot = s[static_cast<std::size_t>(3 * j + i)];
          slot = fi >= 0 && fj >= 0 && fi >= fj ? lower_slot(pattern_, fi, fj) : -1;
          if (fi >= 0 && fj >= 0 && fi >= fj && slot < 0) {
            throw Error(ErrorKind::Internal, fmt::format("a vertex term couples vertices {} and {}, which share no tet", a, b));
          }
        }
      }
      pair_slots_[pair_key(r, c)] = s;
    }
  }
  terms_.push_back(term);
}

void StaticSystem::add_vertex_block(const VertexBlock& b, double* values) const {
  const std::array<int, 9>* s = nullptr;
  if (b.row == b.col) {
    s = &vertex_slots_[static_cast<std::size_t>(b.row)];
  } else {
    const auto it = pair_slots_.find(pair_key(b.row, b.col));
    assert(it != pair_slots_.end());
    s = &it->second;
  }
  for (int k = 0; k < 9; ++k) {
    if ((*s)[static_cast<std::size_t>(k)] >= 0) values[(*s)[static_cast<std::size_t>(k)]] += b.block.data()[k];
  }
}

void StaticSystem::hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const {
  stiffness(x, true_hessian_, H);
  if (regularizing()) add_mass(alpha_, H);
}

void StaticSystem::stiffness(const Eigen::VectorXd& x, bool true_hessian, Eigen::SparseMatrix<double>& H) const {
  if (H.rows() != pattern_.rows() || H.nonZeros() != pattern_.nonZeros() || !H.isCompressed() ||
      !std::equal(H.innerIndexPtr(), H.innerIndexPtr() + H.nonZeros(), pattern_.innerIndexPtr())) {
    H = pattern_;
  }
  std::fill(H.valuePtr(), H.valuePtr() + H.nonZeros(), 0.0);
  const Eigen::VectorXd u = full_displacement(x);
  thread_local std::vector<Mat12> blocks;
  model_->element_hessians(u, true_hessian ? material::PsdProjection::None : material::PsdProjection::Clamp,
                           blocks);
  double* values = H.valuePtr();
  for (std::size_t e = 0; e < blocks.size(); ++e) {
    const auto& slots = element_slots_[e];
    const double* h = blocks[e].data();
    for (std::size_t k = 0; k < 144; ++k) {
      if (slots[k] >= 0) values[slots[k]] += h[k];
    }
  }
  if (!terms_.empty()) {
    const Eigen::VectorXd p = positions(u);
    std::vector<VertexBlock> vb;
    for (const VertexTerm* t : terms_) t->add_hessian(p, true_hessian, vb);
    for (const VertexBlock& b : vb) add_vertex_block(b, values);
  }
}

void StaticSystem::add_mass(double s, Eigen::SparseMatrix<double>& H) const {
  const Eigen::VectorXd& m = model_->lumped_mass();
  double* values = H.valuePtr();
  for (Eigen::Index v = 0; v < m.size(); ++v) {
    const auto& sl = vertex_slots_[static_cast<std::size_t>(v)];
    for (int c = 0; c < 3; ++c) {
      const int k = sl[static_cast<std::size_t>(4 * c)];
      if (k >= 0) values[k] += s * m[v];
    }
  }
}

void StaticSystem::prepare(const Eigen::VectorXd& x) {
  if (terms_.empty()) return;
  const Eigen::VectorXd p = positions(full_displacement(x));
  for (VertexTerm* t : terms_) t->prepare(p);
}

Eigen::VectorXd StaticSystem::reactions(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd u = full_displacement(x);
  Eigen::VectorXd g;
  model_->elastic_energy(u, &g);
  g += gravity_gradient_ - external_;
  if (!terms_.empty()) {
    const Eigen::VectorXd p = positions(u);
    for (const VertexTerm* t : terms_) t->add_gradient(p, g);
  }
  // At equilibrium the free part of g vanishes; at a fixed DOF the support
  // supplies the force g (= ∂E/∂u there) that balances the rest.
  for (Eigen::Index d = 0; d < g.size(); ++d) {
    if (!fixed_[static_cast<std::size_t>(d)]) g[d] = 0.0;
  }
  return g;
}

// ---------------------------------------------------------------- dynamics

BackwardEulerSystem::BackwardEulerSystem(StaticSystem& statics, double step, Damping damping)
    : statics_(&statics), h_(step), damping_(damping) {
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
    statics_->stiffness(x, false, damping_matrix_);
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
  statics_->hessian(x, H);
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
