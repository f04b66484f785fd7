// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/rest/coupled.hpp"

#include <fmt/format.h>

#include "palpa/contact/obstacle.hpp"
#include "palpa/core/error.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/geometry/submesh.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/tet/mesh.hpp"

#include <array>

namespace palpa::rest {

namespace {

// 0 … n−1.
std::vector<int> first_n(std::size_t n) {
  std::vector<int> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<int>(i);
  return out;
}

// H = [A 0; C B] (lower triangles of A and B, C below the diagonal), built
// column by column from compressed A, C, B. The index arrays come out the same
// for the same sub-patterns, so a factorization keeps its analysis.
void stack_lower(const Eigen::SparseMatrix<double>& A, const Eigen::SparseMatrix<double>& C,
                 const Eigen::SparseMatrix<double>& B, Eigen::SparseMatrix<double>& H) {
  const Eigen::Index na = A.cols(), nb = B.cols(), n = na + nb;
  const Eigen::Index nnz = A.nonZeros() + C.nonZeros() + B.nonZeros();
  H.resize(n, n);
  H.resizeNonZeros(nnz);
  int* outer = H.outerIndexPtr();
  int* inner = H.innerIndexPtr();
  double* value = H.valuePtr();
  Eigen::Index k = 0;
  for (Eigen::Index c = 0; c < na; ++c) {
    outer[c] = static_cast<int>(k);
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
      inner[k] = static_cast<int>(it.row());
      value[k++] = it.value();
    }
    for (Eigen::SparseMatrix<double>::InnerIterator it(C, c); it; ++it) {
      inner[k] = static_cast<int>(na + it.row());
      value[k++] = it.value();
    }
  }
  for (Eigen::Index c = 0; c < nb; ++c) {
    outer[na + c] = static_cast<int>(k);
    for (Eigen::SparseMatrix<double>::InnerIterator it(B, c); it; ++it) {
      inner[k] = static_cast<int>(na + it.row());
      value[k++] = it.value();
    }
  }
  outer[n] = static_cast<int>(k);
}

}  // namespace

namespace {

// The reverse pass's samples: the support's surface sampled as the term
// samples the skin.
contact::ContactSamples reverse_samples(const contact::Obstacle& support, const body::ContactTerm& term,
                                        int subdivisions) {
  if (term.sampling() == body::ContactSampling::Surface) {
    return contact::surface_samples(support.vertices(), support.triangles(), contact::subdivision_rule(subdivisions));
  }
  // Springs k·A_j/Ā, areas as built (sample j: vertex j).
  const Eigen::VectorXd area = geometry::vertex_areas(support.vertices(), support.triangles());
  contact::ContactSamples s = contact::vertex_samples(first_n(static_cast<std::size_t>(support.vertices().rows())), area);
  for (Eigen::Index j = 0; j < area.size(); ++j) s.scale[static_cast<std::size_t>(j)] = area[j] / term.mean_area();
  return s;
}

}  // namespace

CoupledSystem::CoupledSystem(body::CoreSystem& body, tet::StaticSystem& support, contact::Obstacle& obstacle,
                             std::vector<int> surface, body::ContactTerm& term, int subdivisions)
    : body_(&body),
      support_(&support),
      obstacle_(&obstacle),
      surface_(std::move(surface)),
      term_(&term),
      reverse_(reverse_samples(obstacle, term, subdivisions), term.stiffness(), "the body's surface") {
  if (static_cast<Eigen::Index>(surface_.size()) != obstacle.vertices().rows()) {
    throw Error(ErrorKind::Internal, fmt::format("{} surface vertices for an obstacle of {}", surface_.size(),
                                                 obstacle.vertices().rows()));
  }
  full_to_free_.assign(static_cast<std::size_t>(support.model().num_dofs()), -1);
  for (std::size_t k = 0; k < support.free_dofs().size(); ++k) {
    full_to_free_[static_cast<std::size_t>(support.free_dofs()[k])] = static_cast<int>(k);
  }
  body_full_to_free_.assign(static_cast<std::size_t>(body.model().num_dofs()), -1);
  for (std::size_t k = 0; k < body.free_dofs().size(); ++k) {
    body_full_to_free_[static_cast<std::size_t>(body.free_dofs()[k])] = static_cast<int>(k);
  }
  // The body's boundary (skin and core shells close it), renumbered.
  const TetMesh& mesh = body.model().mesh();
  geometry::Submesh boundary = geometry::submesh(mesh.V, geometry::boundary_of(mesh).faces);
  body_vertex_ = std::move(boundary.to_old);
  contact::ObstacleOptions oo;
  oo.check_self_intersections = false;
  body_surface_ = std::make_unique<contact::Obstacle>(boundary.mesh, "the body's surface", oo);
  // A support vertex that reaches the core's shells is a failed simulation,
  // not a contact.
  std::vector<char> attached(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (int v : body.core().attached) attached[static_cast<std::size_t>(v)] = 1;
  std::vector<char> excluded(body_vertex_.size(), 0);
  for (std::size_t i = 0; i < body_vertex_.size(); ++i) excluded[i] = attached[static_cast<std::size_t>(body_vertex_[i])];
  reverse_.set_excluded(std::move(excluded));
}

void CoupledSystem::set_stiffness(double k) {
  term_->set_stiffness(k);
  reverse_.set_stiffness(k);
}

Eigen::Matrix3Xd CoupledSystem::support_points(const Eigen::VectorXd& y) const {
  return surface_positions(y).transpose();
}

Eigen::Matrix3Xd CoupledSystem::boundary_points(const Eigen::VectorXd& p) const {
  Eigen::Matrix3Xd B(3, static_cast<Eigen::Index>(body_vertex_.size()));
  for (std::size_t i = 0; i < body_vertex_.size(); ++i) B.col(static_cast<Eigen::Index>(i)) = p.segment<3>(3 * body_vertex_[i]);
  return B;
}

Eigen::Matrix3Xd CoupledSystem::gather_boundary(const Eigen::Matrix3Xd& body) const {
  Eigen::Matrix3Xd B(3, static_cast<Eigen::Index>(body_vertex_.size()));
  for (std::size_t i = 0; i < body_vertex_.size(); ++i) B.col(static_cast<Eigen::Index>(i)) = body.col(body_vertex_[i]);
  return B;
}

void CoupledSystem::scatter_boundary(const Eigen::Matrix3Xd& boundary, Eigen::Matrix3Xd& body) const {
  for (std::size_t i = 0; i < body_vertex_.size(); ++i) body.col(body_vertex_[i]) += boundary.col(static_cast<Eigen::Index>(i));
}

Eigen::MatrixX3d CoupledSystem::surface_positions(const Eigen::VectorXd& y) const {
  const Eigen::VectorXd u = support_->full_displacement(y.tail(num_support_dofs()));
  const Eigen::MatrixX3d& X = support_->model().mesh().V;
  Eigen::MatrixX3d P(static_cast<Eigen::Index>(surface_.size()), 3);
  for (std::size_t j = 0; j < surface_.size(); ++j) {
    const int v = surface_[j];
    P.row(static_cast<Eigen::Index>(j)) = X.row(v) + u.segment<3>(3 * v).transpose();
  }
  return P;
}

void CoupledSystem::place_obstacle(const Eigen::VectorXd& y) {
  obstacle_->set_vertices(surface_positions(y));
  body_surface_->set_vertices(boundary_points(body_->positions(y.head(num_body_dofs()))).transpose());
}

CoupledSystem::Surfaces CoupledSystem::surfaces_at(const Eigen::VectorXd& y) const {
  return {obstacle_->deformed(surface_positions(y)),
          body_surface_->deformed(boundary_points(body_->positions(y.head(num_body_dofs()))).transpose())};
}

void CoupledSystem::contact_forces(const Eigen::VectorXd& y, Eigen::Matrix3Xd& body, Eigen::Matrix3Xd& support) const {
  const Surfaces at = surfaces_at(y);
  const Eigen::VectorXd p = body_->positions(y.head(num_body_dofs()));
  const contact::Points P = Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, p.size() / 3);
  body = Eigen::Matrix3Xd::Zero(3, body_->model().num_vertices());
  support = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(surface_.size()));
  term_->potential().add_forces(at.support, P, body, support);
  Eigen::Matrix3Xd on_boundary = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(body_vertex_.size()));
  reverse_.add_forces(at.body, support_points(y), support, on_boundary);
  scatter_boundary(on_boundary, body);
}

void CoupledSystem::contact_areas(const Eigen::VectorXd& y, Eigen::VectorXd& body, Eigen::VectorXd& support) const {
  const Eigen::VectorXd p = body_->positions(y.head(num_body_dofs()));
  const contact::Points P = Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, p.size() / 3);
  const Eigen::MatrixX3d& body_rest = body_->model().mesh().V;
  const Eigen::MatrixX3d& support_rest = support_->model().mesh().V;
  Eigen::Matrix3Xd surface_rest(3, static_cast<Eigen::Index>(surface_.size()));
  for (std::size_t j = 0; j < surface_.size(); ++j) surface_rest.col(static_cast<Eigen::Index>(j)) = support_rest.row(surface_[j]).transpose();
  body = Eigen::VectorXd::Zero(body_->model().num_vertices());
  support = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(surface_.size()));
  term_->potential().add_contact_areas(body_rest.transpose(), P, body, support);
  Eigen::VectorXd on_boundary = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(body_vertex_.size()));
  reverse_.add_contact_areas(surface_rest, support_points(y), support, on_boundary);
  for (std::size_t i = 0; i < body_vertex_.size(); ++i) body[body_vertex_[i]] += on_boundary[static_cast<Eigen::Index>(i)];
  body *= 0.5;
  support *= 0.5;
}

void CoupledSystem::contact_hessian_product(const Eigen::VectorXd& y, const Eigen::Matrix3Xd& v_body,
                                            const Eigen::Matrix3Xd& v_support, Eigen::Matrix3Xd& body,
                                            Eigen::Matrix3Xd& support) const {
  const Surfaces at = surfaces_at(y);
  const Eigen::VectorXd p = body_->positions(y.head(num_body_dofs()));
  const contact::Points P = Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, p.size() / 3);
  body = Eigen::Matrix3Xd::Zero(3, v_body.cols());
  support = Eigen::Matrix3Xd::Zero(3, v_support.cols());
  term_->potential().add_hessian_product(at.support, P, v_body, v_support, body, support);
  Eigen::Matrix3Xd on_boundary = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(body_vertex_.size()));
  reverse_.add_hessian_product(at.body, support_points(y), v_support, gather_boundary(v_body), support,
                               on_boundary);
  scatter_boundary(on_boundary, body);
}

Eigen::VectorXd CoupledSystem::support_free_part(const Eigen::MatrixX3d& per_surface_vertex) const {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(num_support_dofs());
  for (std::size_t j = 0; j < surface_.size(); ++j) {
    for (int c = 0; c < 3; ++c) {
      const int d = support_dof(surface_[j], c);
      if (d >= 0) out[d] += per_surface_vertex(static_cast<Eigen::Index>(j), c);
    }
  }
  return out;
}

double CoupledSystem::evaluate(const Eigen::VectorXd& y, Eigen::VectorXd* g) const {
  const Eigen::Index nb = num_body_dofs(), ns = num_support_dofs();
  const Eigen::VectorXd x = y.head(nb), v = y.tail(ns);
  const Surfaces at = surfaces_at(y);
  const Eigen::VectorXd p = body_->positions(x);
  const Eigen::Matrix3Xd S = support_points(y);
  if (g == nullptr) {
    const double e = body_->energy(x) + support_->energy(v);
    if (!std::isfinite(e)) return e;
    // Both passes, detected afresh at this (trial) point.
    return e + term_->detected_energy(at.support, p) + reverse_.detected_energy(at.body, S);
  }
  Eigen::VectorXd gb, gs;
  double e = body_->energy_gradient(x, gb) + support_->energy_gradient(v, gs);
  g->resize(nb + ns);
  if (!std::isfinite(e)) return e;
  // Both passes with their committed features: the forces on the body's
  // vertices (pulled back through its core) and on the support's surface.
  const contact::Points P = Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, p.size() / 3);
  Eigen::Matrix3Xd body_grad = Eigen::Matrix3Xd::Zero(3, p.size() / 3);
  Eigen::Matrix3Xd G = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(surface_.size()));
  if (!term_->potential().empty()) {
    term_->potential().add_gradient(at.support, P, body_grad);
    e += term_->potential().energy(at.support, P);
  }
  term_->potential().add_obstacle_gradient(at.support, P, G);
  e += reverse_.energy(at.body, S);
  reverse_.add_gradient(at.body, S, G);
  Eigen::Matrix3Xd on_boundary = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(body_vertex_.size()));
  reverse_.add_obstacle_gradient(at.body, S, on_boundary);
  scatter_boundary(on_boundary, body_grad);
  g->head(nb) = gb + body_->pull_back(x, Eigen::Map<const Eigen::VectorXd>(body_grad.data(), p.size()));
  g->tail(ns) = gs + support_free_part(G.transpose());
  return e;
}

double CoupledSystem::energy(const Eigen::VectorXd& y) const { return evaluate(y, nullptr); }

void CoupledSystem::gradient(const Eigen::VectorXd& y, Eigen::VectorXd& g) const { evaluate(y, &g); }

double CoupledSystem::energy_gradient(const Eigen::VectorXd& y, Eigen::VectorXd& g) const { return evaluate(y, &g); }

template <class F>
void CoupledSystem::for_each_contact_stencil(const Eigen::VectorXd& y, const contact::Obstacle& support,
                                             const contact::Obstacle& body, F&& f) const {
  const Eigen::VectorXd p = body_->positions(y.head(num_body_dofs()));
  term_->potential().for_each_stencil_hessian(
      support, Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, p.size() / 3),
      [&](const contact::Stencil& st, const contact::Matrix12d& K) { f(st, K, true); });
  reverse_.for_each_stencil_hessian(body, support_points(y),
                                    [&](const contact::Stencil& st, const contact::Matrix12d& K) { f(st, K, false); });
}

void CoupledSystem::hessian(const Eigen::VectorXd& y, Eigen::SparseMatrix<double>& H) const {
  const Eigen::Index nb = num_body_dofs(), ns = num_support_dofs();
  const Eigen::VectorXd x = y.head(nb);
  Eigen::SparseMatrix<double> body_hessian, support_hessian;
  body_->hessian(x, body_->newton_projection(), body_hessian);
  if (!term_->active()) body_->regularize(x, body_hessian);  // K + αM until the body touches
  support_->hessian(y.tail(ns), support_hessian);

  // Every block of a contact's stencil goes where its two vertices are: both
  // on the support (its lower triangle: a face's corners share a tet), both
  // on the body (likewise), or one on each (the coupling C, support rows,
  // body columns). `surface_on_body`: whether the stencil's surface slots are
  // the body's (forward) or the support's (reverse).
  const auto body_vertex = [&](const contact::Stencil& st, int slot, bool surface_on_body) {
    return surface_on_body ? st.vertex(slot) : body_vertex_[static_cast<std::size_t>(st.vertex(slot))];
  };
  const auto dof = [&](bool on_body, int vertex, int c) {
    return on_body ? body_full_to_free_[static_cast<std::size_t>(3 * vertex + c)]
                   : support_dof(surface_[static_cast<std::size_t>(vertex)], c);
  };
  std::vector<Eigen::Triplet<double>> cross;
  const auto add = [&](const contact::Stencil& st, const contact::Matrix12d& K, bool forward) {
    for (int i = 0; i < st.slots(); ++i) {
      const bool a_body = st.on_surface(i) == forward;
      const int a = a_body ? body_vertex(st, i, forward) : st.vertex(i);
      for (int j = 0; j < st.slots(); ++j) {
        const bool b_body = st.on_surface(j) == forward;
        if (a_body && !b_body) continue;  // the upper triangle
        const int b = b_body ? body_vertex(st, j, forward) : st.vertex(j);
        const Eigen::Matrix3d block = st.block(K, i, j);
        for (int c = 0; c < 3; ++c) {
          const int r = dof(a_body, a, c);
          if (r < 0) continue;
          for (int d = 0; d < 3; ++d) {
            const int s = dof(b_body, b, d);
            if (s < 0) continue;
            if (a_body != b_body) {
              cross.emplace_back(r, s, block(c, d));
            } else if (s <= r) {
              (a_body ? body_hessian : support_hessian).coeffRef(r, s) += block(c, d);
            }
          }
        }
      }
    }
  };
  const Surfaces at = surfaces_at(y);
  for_each_contact_stencil(y, at.support, at.body, add);
  // Every pair seen so far stays in the pattern, as explicit zeros when apart.
  for (const auto& [q, b] : pairs_) {
    const int v = surface_[static_cast<std::size_t>(q)];
    for (int a = 0; a < 3; ++a) {
      const int r = support_dof(v, a);
      if (r < 0) continue;
      for (int c = 0; c < 3; ++c) {
        const int s = body_full_to_free_[static_cast<std::size_t>(3 * b + c)];
        if (s >= 0) cross.emplace_back(r, s, 0.0);
      }
    }
  }
  Eigen::SparseMatrix<double> C(ns, nb);
  C.setFromTriplets(cross.begin(), cross.end());
  stack_lower(body_hessian, C, support_hessian, H);
}

void CoupledSystem::add_pairs(const contact::Stencil& st, bool forward) {
  for (int i = 0; i < st.slots(); ++i) {
    if (st.on_surface(i) == forward) continue;  // support rows only
    for (int j = 0; j < st.slots(); ++j) {
      if (st.on_surface(j) != forward) continue;  // body columns only
      const int b = forward ? st.vertex(j) : body_vertex_[static_cast<std::size_t>(st.vertex(j))];
      pairs_.emplace(st.vertex(i), b);
    }
  }
}

void CoupledSystem::prepare(const Eigen::VectorXd& y) {
  place_obstacle(y);
  const Eigen::Index nb = num_body_dofs();
  const Eigen::VectorXd x = y.head(nb);
  body_->prepare(x);
  support_->prepare(y.tail(num_support_dofs()));
  const Eigen::VectorXd u = body_->full_displacement(x);
  const Eigen::VectorXd p = body_->TermSystem::positions(u);
  term_->prepare({u, p});
  reverse_.commit(*body_surface_, support_points(y));
  // The coupling pattern grows by the pairs these contacts couple.
  for_each_contact_stencil(y, *obstacle_, *body_surface_, [&](const contact::Stencil& st, const contact::Matrix12d&, bool forward) {
    add_pairs(st, forward);
  });
}

}  // namespace palpa::rest
