// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The closest point of a triangle to a point, with the Voronoi region it lies
// in (the region tests of Ericson, Real-Time Collision Detection §5.1.5).
// Inline: it is the inner loop of every closest-point query.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <limits>

namespace palpa::geometry {

// Region of the closest point: a corner (0, 1, 2 = a, b, c), an edge interior
// (3 = ab, 4 = bc, 5 = ca) or the face interior (6).
enum TriangleRegion : int { kCornerA = 0, kCornerB, kCornerC, kEdgeAB, kEdgeBC, kEdgeCA, kFace };

struct TrianglePoint {
  Eigen::Vector3d point;    // the closest point [m]
  Eigen::Vector3d weights;  // its barycentric weights of a, b, c (≥ 0, sum 1)
  int region;               // a TriangleRegion
};

// The closest point of triangle (a, b, c) to p [m]. A degenerate (zero-area)
// triangle is handled as the nearest of its three edges (a repeated corner
// makes one of them a point).
inline TrianglePoint closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, {1.0, 0.0, 0.0}, kCornerA};
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, {0.0, 1.0, 0.0}, kCornerB};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, {1.0 - v, v, 0.0}, kEdgeAB};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, {0.0, 0.0, 1.0}, kCornerC};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, {1.0 - w, 0.0, w}, kEdgeCA};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), {0.0, 1.0 - w, w}, kEdgeBC};
  }
  const double sum = va + vb + vc;
  if (sum > 0.0 && ab.cross(ac).squaredNorm() > 0.0) {
    const double denom = 1.0 / sum;
    const double v = vb * denom;
    const double w = vc * denom;
    return {a + v * ab + w * ac, {1.0 - v - w, v, w}, kFace};
  }
  // Degenerate triangle: the nearest point of its three edges.
  const Eigen::Vector3d corners[3] = {a, b, c};
  TrianglePoint best{a, {1.0, 0.0, 0.0}, kCornerA};
  double best_d2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3;
    const Eigen::Vector3d edge = corners[k1] - corners[k];
    const double length2 = edge.squaredNorm();
    const double t =
        length2 > 0.0 ? std::clamp((p - corners[k]).dot(edge) / length2, 0.0, 1.0) : 0.0;
    const Eigen::Vector3d q = (1.0 - t) * corners[k] + t * corners[k1];
    const double d = (p - q).squaredNorm();
    if (d < best_d2) {
      best_d2 = d;
      best.point = q;
      best.weights.setZero();
      best.weights(k) = 1.0 - t;
      best.weights(k1) = t;
      best.region = t == 0.0 ? k : t == 1.0 ? k1 : kEdgeAB + k;
    }
  }
  return best;
}

// The barycentric weights of closest_on_triangle(p, a, b, c).
inline Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                                 const Eigen::Vector3d& b,
                                                 const Eigen::Vector3d& c) {
  return closest_on_triangle(p, a, b, c).weights;
}

}  // namespace palpa::geometry
