// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A refittable bounding-volume hierarchy over the triangles of a surface, for
// closest-point queries: the tree behind contact::Obstacle and
// geometry::closest_point.
//
// Layout: a binary tree of axis-aligned boxes built by median splits along the
// longest axis of the triangle centroids, nodes in depth-first order (left
// child = next node), leaves of up to kLeafSize triangles whose corner
// positions are stored contiguously in tree order. refit() recomputes the boxes
// bottom-up for moved vertices without changing the tree: the answers stay
// exact whatever the motion; only the query time grows when the motion is
// large (boxes that overlap more).
//
// Queries are const, allocation-free (a fixed-size stack) and safe to run
// concurrently; build() and refit() must not run during queries.

#include <Eigen/Core>
#include <array>
#include <limits>
#include <vector>

#include "palpa/geometry/closest_point_on_triangle.hpp"

namespace palpa::geometry {

class TriangleTree {
 public:
  // Triangles per leaf (at most).
  static constexpr int kLeafSize = 4;

  // The closest triangle to a query point.
  struct Hit {
    int triangle = -1;  // row of F; −1 when the tree is empty or the query not finite
    double distance2 = std::numeric_limits<double>::infinity();  // ‖p − where.point‖² [m²]
    // The closest point [m], its barycentric weights of F(triangle, 0..2)
    // (≥ 0, sum 1; where.point = Σ_k weights_k V(F(triangle, k)) to rounding)
    // and the feature it lies in (a TriangleRegion: a corner, an edge interior
    // or the face interior of that triangle).
    TrianglePoint where{};
  };

  // An empty tree: closest() finds nothing; lo() > hi().
  TriangleTree();
  // Same as build(V, F).
  TriangleTree(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

  // V: #V×3 vertex positions [m]; F: #F×3 triangles, rows of V (winding
  // irrelevant; degenerate triangles allowed; #F = 0 gives an empty tree).
  // O(#F log #F).
  void build(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);
  // The same triangles (the F of build()) on moved vertices V (#V×3 [m]):
  // keeps the tree's topology and recomputes its boxes, O(#F).
  void refit(const Eigen::MatrixX3d& V);

  // The closest point of the triangles to p [m]. Exact (every triangle that
  // could be closer is visited). Ties (equal squared distances, as computed)
  // go to the lowest triangle index, so the answer does not depend on the
  // tree's shape: a refitted tree answers as a rebuilt one. (A query exactly on
  // a vertex or an edge therefore visits every leaf that touches it.)
  Hit closest(const Eigen::Vector3d& p) const;

  // Number of triangles.
  int size() const { return static_cast<int>(order_.size()); }
  // The box around every triangle [m] (empty tree: lo() > hi()).
  const Eigen::Vector3d& lo() const { return nodes_.front().lo; }
  const Eigen::Vector3d& hi() const { return nodes_.front().hi; }

 private:
  struct Node {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero();
    Eigen::Vector3d hi = Eigen::Vector3d::Zero();
    int first = 0;  // leaf: first slot in order_; inner: index of the right child
    int count = 0;  // leaf: number of triangles (> 0); inner: 0
  };
  int build_node(int begin, int end, const std::vector<Eigen::Vector3d>& centroid);
  void store_corners(const Eigen::MatrixX3d& V);

  std::vector<Node> nodes_;                   // root first; never empty
  std::vector<int> order_;                    // triangle index per slot
  std::vector<std::array<int, 3>> vertices_;  // its three vertex indices per slot
  std::vector<Eigen::Vector3d> corner_;       // its 3 corner positions per slot [m]
  int max_vertex_ = -1;                       // largest vertex index of F
};

}  // namespace palpa::geometry
