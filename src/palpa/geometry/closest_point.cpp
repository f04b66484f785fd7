// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/geometry/closest_point.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace palpa::geometry {
namespace {

// Closest point of segment ab to p as the parameter t in [0, 1].
double segment_parameter(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  if (!(length2 > 0.0)) return 0.0;
  return std::clamp((p - a).dot(ab) / length2, 0.0, 1.0);
}

}  // namespace

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Voronoi regions of the triangle (vertex, edge, face), as in Ericson,
  // Real-Time Collision Detection §5.1.5.
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1.0, 0.0, 0.0};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {0.0, 1.0, 0.0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    const double t = d1 / (d1 - d3);
    return {1.0 - t, t, 0.0};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {0.0, 0.0, 1.0};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    const double t = d2 / (d2 - d6);
    return {1.0 - t, 0.0, t};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0.0, 1.0 - t, t};
  }
  const double denominator = va + vb + vc;
  if (denominator > 0.0 && (ab.cross(ac)).squaredNorm() > 0.0) {
    const double v = vb / denominator;
    const double w = vc / denominator;
    return {1.0 - v - w, v, w};
  }
  // Degenerate (zero-area) triangle: the best of its three edges.
  Eigen::Vector3d best(1.0, 0.0, 0.0);
  double best_d2 = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d corners[3] = {a, b, c};
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const double t = segment_parameter(p, corners[k], corners[k1]);
    const double d = (p - ((1.0 - t) * corners[k] + t * corners[k1])).squaredNorm();
    if (d < best_d2) {
      best_d2 = d;
      best.setZero();
      best(k) = 1.0 - t;
      best(k1) = t;
    }
  }
  return best;
}

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
