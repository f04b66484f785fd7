// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The subdivided icosahedron: a near-uniform triangulation of the unit sphere.

#include "palpa/geometry/mesh.hpp"

namespace palpa::geometry {

// An icosahedron subdivided `level` times (each triangle into four), vertices
// on the unit sphere about the origin; 10·4^level + 2 vertices, 20·4^level
// triangles, wound counter-clockwise seen from outside. level ≥ 0.
SurfaceMesh unit_icosphere(int level);

}  // namespace palpa::geometry
