// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/closest_point.hpp"

#include <cassert>
#include <limits>

namespace palpa::geometry {

SurfacePoint closest_point(const SurfaceMesh& mesh, const TriangleTree& tree,
                           const Eigen::Vector3d& p) {
  assert(mesh.F.rows() > 0 && tree.size() == mesh.F.rows());
  const TriangleTree::Hit hit = tree.closest(p);
  SurfacePoint best;
  if (hit.triangle < 0) {
    best.distance = std::numeric_limits<double>::infinity();
    return best;
  }
  const Eigen::Vector3d& w = hit.where.weights;
  best.face = hit.triangle;
  best.barycentric = w;
  best.position = w(0) * mesh.V.row(mesh.F(best.face, 0)).transpose() +
                  w(1) * mesh.V.row(mesh.F(best.face, 1)).transpose() +
                  w(2) * mesh.V.row(mesh.F(best.face, 2)).transpose();
  best.distance = (p - best.position).norm();
  return best;
}

SurfacePoint closest_point(const SurfaceMesh& mesh, const Eigen::Vector3d& p) {
  return closest_point(mesh, TriangleTree(mesh.V, mesh.F), p);
}

Eigen::RowVectorXd evaluate_at(const SurfaceMesh& mesh, const SurfacePoint& point,
                               const Eigen::MatrixXd& vertex_values) {
  assert(point.face >= 0 && point.face < mesh.F.rows());
  Eigen::RowVectorXd value = Eigen::RowVectorXd::Zero(vertex_values.cols());
  for (int k = 0; k < 3; ++k) value += point.barycentric(k) * vertex_values.row(mesh.F(point.face, k));
  return value;
}

}  // namespace palpa::geometry
