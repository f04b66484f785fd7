// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Closed triangle surfaces of rigid indenters (contact/primitives.hpp moved
// to stand on their lowest point), outward-oriented, in their own
// frame: the contact face down, its lowest point at the origin, the axis +z.
// A pose then places that point where the indenter starts.

#include "palpa/geometry/mesh.hpp"

namespace palpa::sim3d {

// A flat-ended cylinder of radius r and height h [m]: `segments` sides (≥ 8),
// end caps fanned around their centres; bottom face at z = 0.
SurfaceMesh make_cylinder(double radius, double height, int segments = 64);

// A box sx × sy × sz [m], centred in x and y, bottom face at z = 0; each face
// split into n × n squares (n ≥ 1) of two triangles.
SurfaceMesh make_box_surface(const Eigen::Vector3d& size, int n = 1);
// The same with n[k] divisions along axis k (so a thin slab's sides need not
// be slivers: a tet mesh of its inside stays well shaped).
SurfaceMesh make_box_surface(const Eigen::Vector3d& size, const Eigen::Vector3i& n);

// A sphere of radius r [m] centred at (0, 0, r): an icosahedron subdivided
// `level` times (20·4^level triangles) with vertices on the sphere.
SurfaceMesh make_sphere(double radius, int level = 3);

}  // namespace palpa::sim3d
