// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A part of a triangle surface as a surface of its own: the vertices its
// triangles use, renumbered compactly.

#include <Eigen/Core>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::geometry {

struct Submesh {
  // #U×3 positions [m] of the used vertices and #F×3 triangles (rows of it).
  SurfaceMesh mesh;
  // #U: the row of the input V of each new vertex.
  std::vector<int> to_old;
  // #V: the new index of each input vertex, −1 for a vertex no triangle uses.
  std::vector<int> to_new;
};

// The triangles F (#F×3 rows of V, in order) with the vertices they use: V
// #V×3 [m]. New vertices are numbered in order of first appearance, row by
// row of F and corner by corner.
Submesh submesh(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

}  // namespace palpa::geometry
