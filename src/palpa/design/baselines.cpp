#include "palpa/design/baselines.hpp"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "palpa/core/error.hpp"

namespace palpa::design {

PressureEstimate pose_to_seat(const rest::RestSimulation& sim, const rest::RestResult& r, double threshold) {
  if (!(threshold > 0.0)) throw Error(ErrorKind::Input, fmt::format("the contact threshold must be > 0 m, got {}", threshold));
  const TetMesh& mesh = sim.model().mesh();
  const body::CoreSystem& system = sim.system();
  const Eigen::Vector3d c0 = system.core().centre;
  const Eigen::Vector3d t = system.core_translation(sim.dofs());
  const Eigen::Matrix3d R = system.core_rotation(sim.dofs());
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
    const Eigen::Vector3d x = c0 + t + R * (mesh.V.row(v).transpose() - c0);
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
  const Eigen::Matrix3Xd f = sim.contact_term().vertex_forces(P);
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
