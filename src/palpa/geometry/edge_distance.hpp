// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Distances along a triangle surface's edges from a set of its vertices.

#include <Eigen/Core>
#include <limits>
#include <span>

#include "palpa/geometry/mesh.hpp"

namespace palpa::geometry {

// The length of the shortest path along the mesh's edges from each vertex to
// the nearest of `sources` (rows of mesh.V), by Dijkstra's algorithm, not
// searched beyond `limit` [m]: vertices farther than the limit, or on a part
// of the mesh no source is on, get +infinity. A path along edges is at least
// the geodesic distance and, on a mesh of well-shaped triangles, within about
// a tenth above it. Sources out of range throw std::out_of_range.
Eigen::VectorXd edge_path_distance(const SurfaceMesh& mesh, std::span<const Eigen::Index> sources,
                                   double limit = std::numeric_limits<double>::infinity());

}  // namespace palpa::geometry
