// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// CGAL's AABB_tree over a triangle surface, behind a wall (no CGAL type here):
// the independent reference that the tests and the contact benchmark hold
// palpa's geometry::TriangleTree (and the contact obstacles built on it)
// against. Not part of the library.

#include <Eigen/Core>
#include <memory>

namespace palpa::test {

class CgalTriangleTree {
 public:
  // V: #V×3 positions [m]; F: #F×3 triangles (rows of V), #F ≥ 1. Builds the
  // tree and its distance-query accelerator now, so that concurrent const
  // queries never trigger CGAL's lazy construction.
  CgalTriangleTree(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);
  ~CgalTriangleTree();
  CgalTriangleTree(const CgalTriangleTree&) = delete;
  CgalTriangleTree& operator=(const CgalTriangleTree&) = delete;

  struct Hit {
    int triangle = -1;                                // row of F holding the closest point
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // the closest point, as CGAL computes it [m]
    double distance2 = 0.0;                           // ‖p − point‖² [m²]
  };
  // The closest point of the surface to p [m] (ties: whichever CGAL finds).
  Hit closest(const Eigen::Vector3d& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace palpa::test
