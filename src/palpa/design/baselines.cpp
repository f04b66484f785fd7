// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/baselines.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include <Eigen/SparseCholesky>
#include <algorithm>

#include "palpa/core/error.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/mesh/surface_check.hpp"
#include "palpa/rest/measurements.hpp"

namespace palpa::design {

namespace {

// The body's rest vertices carried rigidly by the core's current pose (the
// undeformed body as it sits: both estimates without elasticity start here).
std::vector<Eigen::Vector3d> placed_undeformed(const rest::RestSimulation& sim) {
  const TetMesh& mesh = sim.model().mesh();
  const body::CoreSystem& system = sim.system();
  const Eigen::Vector3d c0 = system.core().centre;
  const Eigen::Vector3d t = system.core_translation(sim.dofs());
  const Eigen::Matrix3d R = system.core_rotation(sim.dofs());
  std::vector<Eigen::Vector3d> Y(static_cast<std::size_t>(mesh.V.rows()));
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) Y[static_cast<std::size_t>(v)] = c0 + t + R * (mesh.V.row(v).transpose() - c0);
  return Y;
}

}  // namespace

PressureEstimate pose_to_seat(const rest::RestSimulation& sim, const rest::RestResult& r, double threshold) {
  if (!(threshold > 0.0)) throw Error(ErrorKind::Input, fmt::format("the contact threshold must be > 0 m, got {}", threshold));
  const TetMesh& mesh = sim.model().mesh();
  const body::CoreSystem& system = sim.system();
  const std::vector<Eigen::Vector3d> Y = placed_undeformed(sim);
  const contact::Obstacle& support = sim.support();

  // Gravity frame: z along −gravity (the load's direction reversed).
  Eigen::Vector3d up = -r.load;
  if (!(up.norm() > 0.0)) throw Error(ErrorKind::Input, "no load: nothing presses the body onto the support");
  up.normalize();
  const Eigen::Vector3d e1 = up.unitOrthogonal(), e2 = up.cross(e1);

  PressureEstimate est;
  est.body_pressure = Eigen::VectorXd::Zero(mesh.V.rows());
  est.support_pressure = Eigen::VectorXd::Zero(support.vertices().rows());
  std::vector<int> C;
  std::vector<Eigen::Vector3d> X;
  for (int v : sim.surface_vertices()) {
    const Eigen::Vector3d& x = Y[static_cast<std::size_t>(v)];
    const contact::ClosestPoint cp = support.closest_point(x);
    if (cp.inside || cp.distance <= threshold) {
      C.push_back(v);
      X.push_back(x);
    }
  }
  est.contacts = static_cast<int>(C.size());
  if (C.empty()) return est;

  // The load line: where palpa's contact forces act.
  const Eigen::VectorXd P = system.positions(sim.dofs());
  const Eigen::Matrix3Xd f = rest::contact_pressures(sim).body_force;
  double fz = 0.0;
  Eigen::Vector2d load_point = Eigen::Vector2d::Zero();
  for (Eigen::Index v = 0; v < f.cols(); ++v) {
    const double w = f.col(v).dot(up);
    if (w <= 0.0) continue;
    fz += w;
    load_point += w * Eigen::Vector2d(P.segment<3>(3 * v).dot(e1), P.segment<3>(3 * v).dot(e2));
  }
  const double W = r.contact_force.dot(up);
  if (fz > 0.0) load_point /= fz;

  const Eigen::VectorXd& area = sim.skin_area();
  double total = 0.0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < C.size(); ++i) {
    total += area[C[i]];
    centroid += area[C[i]] * Eigen::Vector2d(X[i].dot(e1), X[i].dot(e2));
  }
  centroid /= total;
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();
  for (std::size_t i = 0; i < C.size(); ++i) {
    const Eigen::Vector2d d = Eigen::Vector2d(X[i].dot(e1), X[i].dot(e2)) - centroid;
    S += area[C[i]] * d * d.transpose();
  }
  const double a = W / total;
  Eigen::Vector2d bc = Eigen::Vector2d::Zero();
  if (std::abs(S.determinant()) > 1e-30) bc = S.ldlt().solve(W * (load_point - centroid));
  double carried = 0.0;
  for (std::size_t i = 0; i < C.size(); ++i) {
    const Eigen::Vector2d d = Eigen::Vector2d(X[i].dot(e1), X[i].dot(e2)) - centroid;
    const double p = std::max(0.0, a + bc.dot(d));
    est.body_pressure[C[i]] = p;
    carried += p * area[C[i]];
  }
  if (carried > 0.0) est.body_pressure *= W / carried;

  // Onto the support: the nearest contact skin vertex within 1.5 mean edges.
  double edge = 0.0;
  const Eigen::MatrixX3i& F = sim.surface_faces();
  for (Eigen::Index fi = 0; fi < F.rows(); ++fi) edge += (mesh.V.row(F(fi, 0)) - mesh.V.row(F(fi, 1))).norm();
  edge /= std::max<Eigen::Index>(1, F.rows());
  const double reach = 1.5 * edge;
  for (Eigen::Index s = 0; s < support.vertices().rows(); ++s) {
    const Eigen::Vector3d q = support.world_vertex(static_cast<int>(s));
    double best = std::numeric_limits<double>::infinity();
    int arg = -1;
    for (std::size_t i = 0; i < C.size(); ++i) {
      const double d = (X[i] - q).squaredNorm();
      if (d < best) {
        best = d;
        arg = static_cast<int>(i);
      }
    }
    if (arg >= 0 && std::sqrt(best) <= reach) est.support_pressure[s] = est.body_pressure[C[static_cast<std::size_t>(arg)]];
  }
  return est;
}

}  // namespace palpa::design

namespace palpa::design {

namespace {

// Signed distance s along the line x + s·n to triangle (a, b, c), if the line
// meets it (Möller–Trumbore), with the barycentric weights of the hit.
bool line_hits(const Eigen::Vector3d& x, const Eigen::Vector3d& n, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
               const Eigen::Vector3d& c, double& s, Eigen::Vector3d& w) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a;
  const Eigen::Vector3d p = n.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-18) return false;
  const Eigen::Vector3d tv = x - a;
  const double u = tv.dot(p) / det;
  if (u < 0.0 || u > 1.0) return false;
  const Eigen::Vector3d q = tv.cross(e1);
  const double v = n.dot(q) / det;
  if (v < 0.0 || u + v > 1.0) return false;
  s = e2.dot(q) / det;
  w = Eigen::Vector3d(1.0 - u - v, u, v);
  return true;
}

}  // namespace

SitAndRelaxFit sit_and_relax(const rest::RestSimulation& sim, const DesignSpace& space, const Eigen::VectorXd& frozen,
                             double lambda) {
  if (!(lambda >= 0.0)) throw Error(ErrorKind::Input, fmt::format("the Sit & Relax smoothness must be ≥ 0, got {}", lambda));
  const Eigen::MatrixX3i& F = sim.surface_faces();
  const std::vector<Eigen::Vector3d> Y = placed_undeformed(sim);

  const std::vector<int>& D = space.vertices();
  const auto n = static_cast<Eigen::Index>(D.size());
  Eigen::VectorXd h = Eigen::VectorXd::Zero(n), w = Eigen::VectorXd::Zero(n);
  const Eigen::MatrixX3d& X0 = space.initial();
  const Eigen::MatrixX3d& N = space.normals();
  for (Eigen::Index i = 0; i < n; ++i) {
    const int v = D[static_cast<std::size_t>(i)];
    const Eigen::Vector3d x = X0.row(v).transpose(), nv = N.row(v).transpose();
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index f = 0; f < F.rows(); ++f) {
      double s = 0.0;
      Eigen::Vector3d bw;
      if (!line_hits(x, nv, Y[static_cast<std::size_t>(F(f, 0))], Y[static_cast<std::size_t>(F(f, 1))],
                     Y[static_cast<std::size_t>(F(f, 2))], s, bw)) {
        continue;
      }
      if (std::abs(s) < std::abs(best)) {
        best = s;
        w[i] = bw[0] * frozen[F(f, 0)] + bw[1] * frozen[F(f, 1)] + bw[2] * frozen[F(f, 2)];
        h[i] = s;
      }
    }
    if (!std::isfinite(best)) w[i] = 0.0;
  }
  // Normal equations: (W + λ w̄ LᵀL) t = W h.
  std::vector<int> index(static_cast<std::size_t>(X0.rows()), -1);
  for (Eigen::Index i = 0; i < n; ++i) index[static_cast<std::size_t>(D[static_cast<std::size_t>(i)])] = static_cast<int>(i);
  std::vector<std::vector<int>> nb(static_cast<std::size_t>(X0.rows()));
  const Eigen::MatrixX3i& SF = sim.support().triangles();
  for (Eigen::Index f = 0; f < SF.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      nb[static_cast<std::size_t>(SF(f, k))].push_back(SF(f, (k + 1) % 3));
      nb[static_cast<std::size_t>(SF(f, (k + 1) % 3))].push_back(SF(f, k));
    }
  }
  std::vector<Eigen::Triplet<double>> lt;  // L over the design vertices (others fixed at t = 0)
  for (Eigen::Index i = 0; i < n; ++i) {
    auto& l = nb[static_cast<std::size_t>(D[static_cast<std::size_t>(i)])];
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    lt.emplace_back(static_cast<int>(i), static_cast<int>(i), 1.0);
    for (int j : l) {
      const int k = index[static_cast<std::size_t>(j)];
      if (k >= 0) lt.emplace_back(static_cast<int>(i), k, -1.0 / static_cast<double>(l.size()));
    }
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(lt.begin(), lt.end());
  const double wbar = w.sum() / std::max<double>(1.0, static_cast<double>((w.array() > 0.0).count()));
  if (!(wbar > 0.0)) throw Error(ErrorKind::Solver, "Sit & Relax: no design vertex lies under the body's pressed skin");
  Eigen::SparseMatrix<double> A = (lambda * wbar) * Eigen::SparseMatrix<double>(L.transpose() * L);
  for (Eigen::Index i = 0; i < n; ++i) A.coeffRef(i, i) += w[i] + 1e-9 * wbar;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
  if (solver.info() != Eigen::Success) throw Error(ErrorKind::Solver, "Sit & Relax: the fitting system could not be factored");
  const Eigen::VectorXd tt = solver.solve(w.cwiseProduct(h));
  const auto moved = [&](double scale) {
    SurfaceMesh m{X0, sim.support().triangles()};
    for (Eigen::Index i = 0; i < n; ++i) {
      const int v = D[static_cast<std::size_t>(i)];
      m.V.row(v) += scale * tt[i] * N.row(v);
    }
    return m;
  };
  constexpr int kHalvings = 8;
  SitAndRelaxFit fit;
  for (int k = 0; k <= kHalvings; ++k, fit.scale *= 0.5) {
    SurfaceMesh m = moved(fit.scale);
    if (!mesh::self_intersects(m)) {
      fit.vertices = std::move(m.V);
      return fit;
    }
  }
  throw Error(ErrorKind::Solver, fmt::format("Sit & Relax: the support crosses itself even with 1/{} of the fitted "
                                             "moves (largest {:.3g} mm)",
                                             1 << kHalvings, tt.cwiseAbs().maxCoeff() * 1e3));
}

}  // namespace palpa::design
