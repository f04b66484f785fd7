// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Closest points on a triangle surface.

#include <Eigen/Core>

#include "palpa/geometry/closest_point_on_triangle.hpp"
#include "palpa/geometry/mesh.hpp"
#include "palpa/geometry/triangle_tree.hpp"

namespace palpa::geometry {

// A point on a surface: a triangle and barycentric coordinates in it.
struct SurfacePoint {
  Eigen::Index face = -1;                                 // row of F
  Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();  // weights of F(face, 0..2), sum 1, ≥ 0
  Eigen::Vector3d position = Eigen::Vector3d::Zero();     // Σ b_k V(F(face,k)) [m]
  double distance = 0.0;  // from the query point to `position` [m]
};

// The closest point of the surface to p [m], found with `tree`, a
// TriangleTree built from (or refitted to) mesh.V and mesh.F (typically
// O(log #F) per query). Ties go to the lowest face index. mesh must have at
// least one triangle (asserted). A non-finite p gives face −1 and an infinite
// distance.
SurfacePoint closest_point(const SurfaceMesh& mesh, const TriangleTree& tree,
                           const Eigen::Vector3d& p);

// The same for one query: builds a TriangleTree of the mesh first (O(#F log
// #F): about 40 ms for 50k triangles, the time of some fifty exhaustive
// scans), so for more than one query build the tree once and use the overload
// above.
SurfacePoint closest_point(const SurfaceMesh& mesh, const Eigen::Vector3d& p);

// Σ_k b_k values(F(face,k), :): a per-vertex field (#V×k) evaluated at a
// surface point, 1×k.
Eigen::RowVectorXd evaluate_at(const SurfaceMesh& mesh, const SurfacePoint& point,
                               const Eigen::MatrixXd& vertex_values);

}  // namespace palpa::geometry
