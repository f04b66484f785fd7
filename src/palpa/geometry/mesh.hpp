// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The mesh types shared by palpa's modules: a triangle surface and a
// tetrahedral volume. Reading and writing them is io/mesh.hpp's business.

#include <Eigen/Core>

namespace palpa {

// A triangle surface.
struct SurfaceMesh {
  // #V×3 vertex positions [m] (file unit × MeshReadOptions::unit_to_si).
  Eigen::MatrixX3d V;
  // #F×3 triangles as 0-based rows of V, in the file's winding: counter-clockwise
  // seen from the side the normal (V1−V0)×(V2−V0) points to.
  Eigen::MatrixX3i F;
};

// A tetrahedral volume mesh, with optional labelled boundary triangles.
struct TetMesh {
  // #V×3 vertex positions [m].
  Eigen::MatrixX3d V;
  // #T×4 tetrahedra as 0-based rows of V, in the file's vertex order.
  Eigen::MatrixX4i T;
  // #T region (material) ids, one per tet; empty when the file has none.
  Eigen::VectorXi region;
  // #B×3 boundary triangles as 0-based rows of V; #B may be 0.
  Eigen::MatrixX3i boundary;
  // #B boundary markers (e.g. Gmsh physical tags), one per boundary triangle;
  // empty when the file has none.
  Eigen::VectorXi boundary_marker;
};

}  // namespace palpa
