// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The boundary surface of a tet mesh.

#include <Eigen/Core>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::geometry {

// The boundary of a tet mesh: the faces that belong to one tet only, wound so
// that their normals point out of the volume (for positively oriented tets).
// Vertices keep their tet-mesh numbering (the returned faces index the tet
// mesh's V), so unused rows are the interior vertices.
struct Boundary {
  Eigen::MatrixX3i faces;     // #B×3 outward triangles (rows of the tet mesh's V), ordered
                              // by tet, then by the corner each is opposite to
  std::vector<int> vertices;  // the distinct vertices of those faces, sorted
  Eigen::VectorXi face_tet;   // #B: the tet each face belongs to
};
Boundary boundary_of(const TetMesh& mesh);

}  // namespace palpa::geometry
