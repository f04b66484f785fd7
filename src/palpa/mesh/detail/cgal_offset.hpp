// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The inward offset of a closed surface by distance (CGAL Mesh_3 on an
// implicit function), kept apart from cgal_surface.cpp because Mesh_3 is a
// heavy include.

#include <Eigen/Core>
#include <functional>

#include "palpa/geometry/mesh.hpp"

namespace palpa::mesh::detail {

// The surface {p inside `skin` : dist(p, skin) = depth(p)}, where `depth`
// gives the depth at a point's closest skin point: every point of the region
// it encloses is at least its depth from the skin. Where the body is thinner
// than twice the depth the region is simply absent, so it may have several
// components or none (an empty mesh; a region thinner than half an edge
// everywhere counts as none). Triangles of about `edge` [m]; the
// surface approximates the level set to `edge`/10. The result may need
// orientation and manifold repairs by the caller.
SurfaceMesh cgal_distance_offset(const SurfaceMesh& skin,
                                 const std::function<double(Eigen::Index face, const Eigen::Vector3d& at)>& depth,
                                 double edge);

// The outward offset of a closed surface: the surface at `distance` [m]
// outside it (rounded over its convex edges, filled over narrow gaps), with
// triangles of about `edge`, within a fifth of `distance` of the level set.
// Same caveats as above.
SurfaceMesh cgal_dilation(const SurfaceMesh& skin, double distance, double edge);

}  // namespace palpa::mesh::detail
