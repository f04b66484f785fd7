// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Closed triangle surfaces for the contact tests and benchmark, and reference
// answers computed by brute force (no tree, no pseudo-normals).

#include <Eigen/Core>

#include "palpa/geometry/mesh.hpp"

namespace palpa::test {

// The cube [−h, h]³, 12 triangles, outward.
SurfaceMesh cube_mesh(double h);
// An icosahedron subdivided `levels` times, projected on the sphere of radius r
// (20·4^levels triangles), outward.
SurfaceMesh sphere_mesh(double r, int levels);
// A torus around z: tube centre radius R, tube radius r, nu × nv quads split in
// two (2·nu·nv triangles), outward.
SurfaceMesh torus_mesh(double R, double r, int nu, int nv);
// Two tetrahedra sharing one edge (a closed but non-manifold surface).
SurfaceMesh bowtie_mesh();

// Generalized winding number of p (1 inside a closed outward surface, 0 outside).
double winding_number(const SurfaceMesh& mesh, const Eigen::Vector3d& p);
// Distance from p to the surface, over all triangles.
double brute_distance(const SurfaceMesh& mesh, const Eigen::Vector3d& p);

}  // namespace palpa::test
