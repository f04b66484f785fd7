// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// CGAL's AABB_tree over the obstacle's triangles, behind a wall (no CGAL type
// here): the alternative to Bvh, kept for the benchmark and agreement tests.

#include <Eigen/Core>
#include <memory>

namespace palpa::contact::detail {

class CgalTree {
 public:
  CgalTree(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);
  ~CgalTree();
  CgalTree(const CgalTree&) = delete;
  CgalTree& operator=(const CgalTree&) = delete;
  // The triangle holding the closest point to p.
  int closest_triangle(const Eigen::Vector3d& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace palpa::contact::detail
