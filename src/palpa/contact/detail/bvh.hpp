// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// palpa's own bounding-volume hierarchy over triangles for closest-point
// queries: a binary tree of axis-aligned boxes built by median splits along the
// longest axis of the triangle centroids, nodes in depth-first order (left
// child = next node), leaves of up to kLeafSize triangles whose corner
// positions are stored contiguously in tree order. refit() recomputes the boxes
// bottom-up for moved vertices without changing the tree.

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "palpa/geometry/closest_point_on_triangle.hpp"

namespace palpa::contact::detail {

class Bvh {
 public:
  static constexpr int kLeafSize = 4;

  Bvh() = default;
  void build(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);
  // Same triangles, moved vertices.
  void refit(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

  struct Hit {
    int triangle = -1;
    double distance2 = std::numeric_limits<double>::infinity();
    geometry::TrianglePoint where{};
  };
  // Closest triangle to p (ties: the first found).
  Hit closest(const Eigen::Vector3d& p) const;

  // Root box (empty tree: an inverted box).
  const Eigen::Vector3d& lo() const { return nodes_.front().lo; }
  const Eigen::Vector3d& hi() const { return nodes_.front().hi; }

 private:
  struct Node {
    Eigen::Vector3d lo = Eigen::Vector3d::Zero();
    Eigen::Vector3d hi = Eigen::Vector3d::Zero();
    int first = 0;  // leaf: first slot in order_; inner: index of the right child
    int count = 0;  // leaf: number of triangles (> 0); inner: 0
  };
  int build_node(int begin, int end, std::vector<Eigen::Vector3d>& centroid);
  void store_corners(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

  std::vector<Node> nodes_;
  std::vector<int> order_;               // triangle index per slot
  std::vector<Eigen::Vector3d> corner_;  // 3 corners per slot
};

}  // namespace palpa::contact::detail
