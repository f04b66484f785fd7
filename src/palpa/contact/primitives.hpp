// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Closed, outward triangle surfaces of simple rigid objects (indenters,
// blocks), centred on the origin of their body frame; place them with
// Obstacle::set_pose(). Sizes in metres.

#include <Eigen/Core>

#include "palpa/geometry/mesh.hpp"

namespace palpa::contact {

// The box [−half, half] (12 triangles). half: three positive half-extents [m].
SurfaceMesh box_surface(const Eigen::Vector3d& half);

// A cylinder along z from −length/2 to length/2, its circles approximated by
// regular `segments`-gons (inscribed; segments ≥ 3): 4·segments triangles,
// caps fanned from their centres. Enclosed volume
// (segments/2)·radius²·sin(2π/segments)·length.
SurfaceMesh cylinder_surface(double radius, double length, int segments);

// An icosahedron subdivided `levels` times (20·4^levels triangles), its
// vertices on the sphere of radius `radius`.
SurfaceMesh sphere_surface(double radius, int levels);

// A torus around z: tube centre radius R, tube radius r (R > r > 0), nu × nv
// quads (nu, nv ≥ 3) each split in two: 2·nu·nv triangles.
SurfaceMesh torus_surface(double R, double r, int nu, int nv);

}  // namespace palpa::contact
