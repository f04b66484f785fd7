// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Mesh checks done with CGAL's Polygon Mesh Processing, behind a wall (no CGAL
// type here).

#include <Eigen/Core>
#include <cstddef>

namespace palpa::contact::detail {

struct SelfIntersections {
  std::size_t pairs = 0;  // pairs found (at most the cap given)
  int first = -1;         // one intersecting pair of triangles (rows of F)
  int second = -1;
};

// Pairs of triangles of a closed, oriented, manifold surface that intersect
// other than along a shared edge or at a shared vertex (exact predicates).
// Stops after `cap` pairs.
SelfIntersections self_intersections(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F,
                                     std::size_t cap);

}  // namespace palpa::contact::detail
