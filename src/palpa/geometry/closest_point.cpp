// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/closest_point.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace palpa::geometry {

SurfacePoint closest_point(const SurfaceMesh& mesh, const Eigen::Vector3d& p) {
  assert(mesh.F.rows() > 0);
  SurfacePoint best;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1));
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2));
    // Bounding-sphere cut: no point of the triangle is closer than |p−m| − r.
    const Eigen::Vector3d m = (a + b + c) / 3.0;
    const double r = std::sqrt(std::max({(a - m).squaredNorm(), (b - m).squaredNorm(),
                                         (c - m).squaredNorm()}));
    const double lower = (p - m).norm() - r;
    if (lower > 0.0 && lower * lower >= best_d2) continue;
    const Eigen::Vector3d w = closest_point_on_triangle(p, a, b, c);
    const Eigen::Vector3d q = w(0) * a + w(1) * b + w(2) * c;
    const double d2 = (p - q).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best.face = f;
      best.barycentric = w;
      best.position = q;
    }
  }
  best.distance = std::sqrt(best_d2);
  return best;
}

Eigen::RowVectorXd evaluate_at(const SurfaceMesh& mesh, const SurfacePoint& point,
                               const Eigen::MatrixXd& vertex_values) {
  assert(point.face >= 0 && point.face < mesh.F.rows());
  Eigen::RowVectorXd value = Eigen::RowVectorXd::Zero(vertex_values.cols());
  for (int k = 0; k < 3; ++k) value += point.barycentric(k) * vertex_values.row(mesh.F(point.face, k));
  return value;
}

}  // namespace palpa::geometry
