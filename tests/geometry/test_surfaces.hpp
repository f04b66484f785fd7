// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Small analytic surfaces for the geometry tests.

#include "palpa/geometry/mesh.hpp"

namespace palpa::test {

// Icosahedron subdivided `level` times, vertices projected to the sphere of
// `radius` [m] about the origin; outward counter-clockwise winding.
SurfaceMesh icosphere(int level, double radius);

// An n×n-cell square grid in the plane z = 0 of side `size` [m], centred at the
// origin, each cell split into two triangles along alternating diagonals.
SurfaceMesh square_grid(int n, double size);

}  // namespace palpa::test
