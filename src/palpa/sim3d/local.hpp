// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Poking a large body locally (thesis §5.5): only the tets near the obstacles
// are simulated, the cut boundary is held fixed.

#include <Eigen/Core>
#include <vector>

#include "palpa/contact/obstacle.hpp"
#include "palpa/geometry/mesh.hpp"

namespace palpa::sim3d {

struct ActiveRegion {
  TetMesh mesh;                // the kept tets, vertices renumbered
  std::vector<int> vertex;     // sub-mesh vertex -> full-mesh vertex
  std::vector<int> element;    // sub-mesh tet -> full-mesh tet
  std::vector<int> cut;        // sub-mesh vertices on the cut boundary (held fixed)
};

// Keeps every tet with a vertex inside, or within `margin` [m] of, any of the
// obstacles at their posed positions (pass them at their deepest pose). The
// cut boundary: kept vertices that also belong to a dropped tet. Throws
// palpa::Error (Input) if no tet is near an obstacle.
ActiveRegion active_region(const TetMesh& mesh, const std::vector<const contact::Obstacle*>& obstacles,
                           double margin);

}  // namespace palpa::sim3d
