// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/rest/coupled.hpp"

#include <fmt/format.h>

#include "palpa/contact/contact.hpp"
#include "palpa/core/error.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/geometry/submesh.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/tet/mesh.hpp"

#include <array>

namespace palpa::rest {

namespace {

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

CoupledSystem::CoupledSystem(body::CoreSystem& body, tet::StaticSystem& support, contact::Obstacle& obstacle,
                             std::vector<int> surface, const sim3d::RigidContactTerm& term)
    : body_(&body), support_(&support), obstacle_(&obstacle), surface_(std::move(surface)), term_(&term) {
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
  attached_.assign(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (int v : body.core().attached) attached_[static_cast<std::size_t>(v)] = 1;
  // Springs of the support's vertices: k·A_j/Ā, areas as built.
  const Eigen::VectorXd area = geometry::vertex_areas(obstacle.vertices(), obstacle.triangles());
  reverse_scale_.resize(static_cast<std::size_t>(area.size()));
  for (Eigen::Index j = 0; j < area.size(); ++j) reverse_scale_[static_cast<std::size_t>(j)] = area[j] / term.mean_area();
  reverse_.set_scale(reverse_scale_);
}

bool CoupledSystem::on_skin(const contact::Contact& c) const {
  for (int i = 0; i < contact::feature_size(c.closest.feature); ++i) {
    if (attached_[static_cast<std::size_t>(body_vertex_[static_cast<std::size_t>(c.closest.vertices[static_cast<std::size_t>(i)])])]) {
      return false;
    }
  }
  return true;
}

Eigen::Matrix3Xd CoupledSystem::reverse_body_forces(const Eigen::VectorXd& y) const {
  place_obstacle(y);
  const Eigen::MatrixX3d S = surface_positions(y);
  Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, body_->model().num_vertices());
  for (const contact::Contact& c : reverse_.contacts()) {
    if (!on_skin(c)) continue;
    const contact::FeatureGeometry fg = contact::feature_geometry(*body_surface_, c.closest);
    const contact::Vector12d G = contact::penalty_gradient_full(S.row(c.point).transpose(), fg,
                                                                reverse_.stiffness_of(c, term_->stiffness()));
    for (int i = 0; i < fg.m; ++i) {
      f.col(body_vertex_[static_cast<std::size_t>(c.closest.vertices[static_cast<std::size_t>(i)])]) -=
          G.segment<3>(3 * (i + 1));
    }
  }
  return f;
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

void CoupledSystem::place_obstacle(const Eigen::VectorXd& y) const {
  obstacle_->set_vertices(surface_positions(y));
  const Eigen::VectorXd p = body_->positions(y.head(num_body_dofs()));
  Eigen::MatrixX3d B(static_cast<Eigen::Index>(body_vertex_.size()), 3);
  for (std::size_t i = 0; i < body_vertex_.size(); ++i) B.row(static_cast<Eigen::Index>(i)) = p.segment<3>(3 * body_vertex_[i]).transpose();
  body_surface_->set_vertices(B);
}

std::vector<CoupledSystem::Pair> CoupledSystem::pairs(const Eigen::VectorXd& y) const {
  place_obstacle(y);
  const Eigen::VectorXd p = body_->positions(y.head(num_body_dofs()));
  const Eigen::MatrixX3d S = surface_positions(y);
  const double k = term_->stiffness();
  std::vector<Pair> out;
  for (const contact::Contact& c : term_->contacts().contacts()) {
    Pair q;
    q.feature = contact::feature_geometry(*obstacle_, c.closest);
    q.point = p.segment<3>(3 * c.point);
    q.k = term_->contacts().stiffness_of(c, k);
    q.vertex[0] = c.point;
    for (int i = 0; i < q.feature.m; ++i) q.vertex[static_cast<std::size_t>(i + 1)] = c.closest.vertices[static_cast<std::size_t>(i)];
    out.push_back(q);
  }
  for (const contact::Contact& c : reverse_.contacts()) {
    if (!on_skin(c)) continue;
    Pair q;
    q.forward = false;
    q.feature = contact::feature_geometry(*body_surface_, c.closest);
    q.point = S.row(c.point).transpose();
    q.k = reverse_.stiffness_of(c, k);
    q.vertex[0] = c.point;
    for (int i = 0; i < q.feature.m; ++i) {
      q.vertex[static_cast<std::size_t>(i + 1)] = body_vertex_[static_cast<std::size_t>(c.closest.vertices[static_cast<std::size_t>(i)])];
    }
    out.push_back(q);
  }
  return out;
}

void CoupledSystem::contact_forces(const Eigen::VectorXd& y, Eigen::Matrix3Xd& body, Eigen::Matrix3Xd& support) const {
  body = Eigen::Matrix3Xd::Zero(3, body_->model().num_vertices());
  support = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(surface_.size()));
  for (const Pair& q : pairs(y)) {
    const contact::Vector12d G = contact::penalty_gradient_full(q.point, q.feature, q.k);
    for (int s = 0; s <= q.feature.m; ++s) {
      Eigen::Matrix3Xd& side = q.on_body(s) ? body : support;
      side.col(q.vertex[static_cast<std::size_t>(s)]) -= G.segment<3>(3 * s);
    }
  }
}

void CoupledSystem::contact_hessian_product(const Eigen::VectorXd& y, const Eigen::Matrix3Xd& v_body,
                                            const Eigen::Matrix3Xd& v_support, Eigen::Matrix3Xd& body,
                                            Eigen::Matrix3Xd& support) const {
  body = Eigen::Matrix3Xd::Zero(3, v_body.cols());
  support = Eigen::Matrix3Xd::Zero(3, v_support.cols());
  for (const Pair& q : pairs(y)) {
    const contact::Matrix12d K = contact::penalty_hessian_full(q.point, q.feature, q.k);
    contact::Vector12d v = contact::Vector12d::Zero();
    for (int s = 0; s <= q.feature.m; ++s) {
      v.segment<3>(3 * s) = (q.on_body(s) ? v_body : v_support).col(q.vertex[static_cast<std::size_t>(s)]);
    }
    const contact::Vector12d Kv = K * v;
    for (int s = 0; s <= q.feature.m; ++s) {
      (q.on_body(s) ? body : support).col(q.vertex[static_cast<std::size_t>(s)]) += Kv.segment<3>(3 * s);
    }
  }
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
  place_obstacle(y);
  const Eigen::Index nb = num_body_dofs(), ns = num_support_dofs();
  const Eigen::VectorXd x = y.head(nb), v = y.tail(ns);
  const Eigen::MatrixX3d S = surface_positions(y);
  const double k = term_->stiffness();
  if (g == nullptr) {
    const double e = body_->energy(x) + support_->energy(v);
    if (!std::isfinite(e)) return e;
    // The reverse pass, detected afresh at this (trial) point.
    contact::ContactSet trial;
    trial.set_scale(reverse_scale_);
    const Eigen::Matrix3Xd St = S.transpose();
    trial.detect(*body_surface_, St);
    double reverse = 0.0;
    for (const contact::Contact& c : trial.contacts()) {
      if (!on_skin(c)) continue;
      reverse += contact::penalty_energy(St.col(c.point), contact::feature_geometry(*body_surface_, c.closest),
                                         trial.stiffness_of(c, k));
    }
    return e + reverse;
  }
  Eigen::VectorXd gb, gs;
  double e = body_->energy_gradient(x, gb) + support_->energy_gradient(v, gs);
  g->resize(nb + ns);
  if (!std::isfinite(e)) return e;
  // The reactions of the committed contacts on the support's surface.
  const Eigen::VectorXd p = body_->positions(x);
  Eigen::Matrix3Xd G = Eigen::Matrix3Xd::Zero(3, static_cast<Eigen::Index>(surface_.size()));
  term_->contacts().add_obstacle_gradient(*obstacle_, Eigen::Map<const Eigen::Matrix3Xd>(p.data(), 3, p.size() / 3), k,
                                          G);
  // The reverse pass with its committed features.
  Eigen::VectorXd gbody = Eigen::VectorXd::Zero(p.size());
  for (const contact::Contact& c : reverse_.contacts()) {
    if (!on_skin(c)) continue;
    const contact::FeatureGeometry fg = contact::feature_geometry(*body_surface_, c.closest);
    const Eigen::Vector3d q = S.row(c.point).transpose();
    const double kc = reverse_.stiffness_of(c, k);
    e += contact::penalty_energy(q, fg, kc);
    const contact::Vector12d d = contact::penalty_gradient_full(q, fg, kc);
    G.col(c.point) += d.head<3>();
    for (int i = 0; i < fg.m; ++i) {
      gbody.segment<3>(3 * body_vertex_[static_cast<std::size_t>(c.closest.vertices[static_cast<std::size_t>(i)])]) +=
          d.segment<3>(3 * (i + 1));
    }
  }
  g->head(nb) = gb;
  for (Eigen::Index d = 0; d < gbody.size(); ++d) {
    if (gbody[d] == 0.0) continue;
    const int r = body_full_to_free_[static_cast<std::size_t>(d)];
    if (r >= 0) (*g)[r] += gbody[d];
  }
  g->tail(ns) = gs + support_free_part(G.transpose());
  return e;
}

double CoupledSystem::energy(const Eigen::VectorXd& y) const { return evaluate(y, nullptr); }

void CoupledSystem::gradient(const Eigen::VectorXd& y, Eigen::VectorXd& g) const { evaluate(y, &g); }

double CoupledSystem::energy_gradient(const Eigen::VectorXd& y, Eigen::VectorXd& g) const { return evaluate(y, &g); }

void CoupledSystem::hessian(const Eigen::VectorXd& y, Eigen::SparseMatrix<double>& H) const {
  place_obstacle(y);
  const Eigen::Index nb = num_body_dofs(), ns = num_support_dofs();
  const Eigen::VectorXd x = y.head(nb);
  body_->hessian(x, body_hessian_);
  support_->hessian(y.tail(ns), support_hessian_);
  const Eigen::VectorXd p = body_->positions(x);

  std::vector<Eigen::Triplet<double>> cross;
  for (const contact::Contact& c : term_->contacts().contacts()) {
    const contact::FeatureGeometry fg = contact::feature_geometry(*obstacle_, c.closest);
    const contact::Matrix12d K = contact::penalty_hessian_full(p.segment<3>(3 * c.point), fg,
                                                               term_->contacts().stiffness_of(c, term_->stiffness()));
    for (int i = 0; i < fg.m; ++i) {
      const int qi = c.closest.vertices[static_cast<std::size_t>(i)];
      const int vi = surface_[static_cast<std::size_t>(qi)];
      pairs_.emplace(qi, c.point);
      for (int a = 0; a < 3; ++a) {
        const int r = support_dof(vi, a);
        if (r < 0) continue;
        // (q_i, q_j): in the support's pattern (a face's corners share a tet).
        for (int j = 0; j < fg.m; ++j) {
          const int vj = surface_[static_cast<std::size_t>(c.closest.vertices[static_cast<std::size_t>(j)])];
          for (int b = 0; b < 3; ++b) {
            const int s = support_dof(vj, b);
            if (s < 0 || s > r) continue;
            support_hessian_.coeffRef(r, s) += K(3 * (i + 1) + a, 3 * (j + 1) + b);
          }
        }
        // (q_i, p)
        for (int b = 0; b < 3; ++b) {
          const int s = body_full_to_free_[static_cast<std::size_t>(3 * c.point + b)];
          if (s >= 0) cross.emplace_back(r, s, K(3 * (i + 1) + a, b));
        }
      }
    }
  }
  // The reverse pass: (q, q) into the support's block, (b_i, b_j) into the
  // body's (a skin triangle's corners share a tet), (q, b_i) coupling.
  const Eigen::MatrixX3d S = surface_positions(y);
  const auto body_dof = [&](int b, int c) { return body_full_to_free_[static_cast<std::size_t>(3 * b + c)]; };
  for (const contact::Contact& c : reverse_.contacts()) {
    if (!on_skin(c)) continue;
    const contact::FeatureGeometry fg = contact::feature_geometry(*body_surface_, c.closest);
    const contact::Matrix12d K = contact::penalty_hessian_full(S.row(c.point).transpose(), fg,
                                                               reverse_.stiffness_of(c, term_->stiffness()));
    const int vq = surface_[static_cast<std::size_t>(c.point)];
    std::array<int, 3> b{};
    for (int i = 0; i < fg.m; ++i) {
      b[static_cast<std::size_t>(i)] = body_vertex_[static_cast<std::size_t>(c.closest.vertices[static_cast<std::size_t>(i)])];
      pairs_.emplace(c.point, b[static_cast<std::size_t>(i)]);
    }
    for (int a = 0; a < 3; ++a) {
      const int r = support_dof(vq, a);
      if (r < 0) continue;
      for (int a2 = 0; a2 < 3; ++a2) {
        const int s2 = support_dof(vq, a2);
        if (s2 >= 0 && s2 <= r) support_hessian_.coeffRef(r, s2) += K(a, a2);
      }
      for (int i = 0; i < fg.m; ++i) {
        for (int e = 0; e < 3; ++e) {
          const int s2 = body_dof(b[static_cast<std::size_t>(i)], e);
          if (s2 >= 0) cross.emplace_back(r, s2, K(a, 3 * (i + 1) + e));
        }
      }
    }
    for (int i = 0; i < fg.m; ++i) {
      for (int a = 0; a < 3; ++a) {
        const int r = body_dof(b[static_cast<std::size_t>(i)], a);
        if (r < 0) continue;
        for (int j = 0; j < fg.m; ++j) {
          for (int e = 0; e < 3; ++e) {
            const int s2 = body_dof(b[static_cast<std::size_t>(j)], e);
            if (s2 >= 0 && s2 <= r) body_hessian_.coeffRef(r, s2) += K(3 * (i + 1) + a, 3 * (j + 1) + e);
          }
        }
      }
    }
  }
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
  stack_lower(body_hessian_, C, support_hessian_, H);
}

void CoupledSystem::prepare(const Eigen::VectorXd& y) {
  place_obstacle(y);
  const Eigen::Index nb = num_body_dofs();
  body_->prepare(y.head(nb));
  support_->prepare(y.tail(num_support_dofs()));
  const Eigen::Matrix3Xd S = surface_positions(y).transpose();
  reverse_.detect(*body_surface_, S);
}

}  // namespace palpa::rest
