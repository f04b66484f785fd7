// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Closest point of a triangle to a point, with the Voronoi region it lies in
// (the region tests of Ericson, Real-Time Collision Detection §5.1.5).

#include <Eigen/Core>

namespace palpa::contact::detail {

// Region of the closest point: a corner (0, 1, 2 = a, b, c), an edge interior
// (3 = ab, 4 = bc, 5 = ca) or the face interior (6).
enum TriangleRegion : int { kCornerA = 0, kCornerB, kCornerC, kEdgeAB, kEdgeBC, kEdgeCA, kFace };

struct TrianglePoint {
  Eigen::Vector3d point;
  Eigen::Vector3d weights;  // barycentric weights of a, b, c
  int region;
};

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
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, {1.0 - v, v, 0.0}, kEdgeAB};
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, {0.0, 0.0, 1.0}, kCornerC};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, {1.0 - w, 0.0, w}, kEdgeCA};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), {0.0, 1.0 - w, w}, kEdgeBC};
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  return {a + v * ab + w * ac, {1.0 - v - w, v, w}, kFace};
}

}  // namespace palpa::contact::detail
