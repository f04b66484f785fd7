// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Making a scanned surface fit for simulation: cheap repairs, the checks a
// closed surface must pass, and isotropic remeshing to a chosen resolution.

#include <Eigen/Core>
#include <string>

#include "palpa/geometry/mesh.hpp"

namespace palpa::mesh {

// What repair_surface() changed.
struct RepairReport {
  Eigen::Index merged_vertices = 0;    // vertices merged into an equal one
  Eigen::Index degenerate_faces = 0;   // triangles with a repeated corner (after merging)
  Eigen::Index duplicate_faces = 0;    // triangles on the same three vertices as another
  Eigen::Index unused_vertices = 0;    // vertices no triangle uses (removed)
  bool flipped = false;                // winding reversed so that normals point outward
};

// Cheap repairs: merges vertices closer than merge_tolerance [m] (default: 1e-9
// × the bounding-box diagonal; 0 merges only identical positions), removes
// triangles with a repeated corner and repeated triangles (both copies of a
// pair wound oppositely), drops unused vertices, and — when the surface is
// closed and encloses a negative volume — reverses the winding. Collinear
// (zero-area) triangles with distinct corners are left to check/remesh.
SurfaceMesh repair_surface(const SurfaceMesh& mesh, RepairReport* report = nullptr,
                           double merge_tolerance = -1.0);

// Checks that `mesh` is a closed, consistently oriented 2-manifold with
// outward normals and no self-intersection. Throws palpa::Error (Input) naming
// `source` and the first offending edge or triangle pair with its position:
// open boundary (an edge of one triangle), an edge of more than two
// triangles, inconsistent winding, a non-manifold vertex, inward orientation,
// self-intersection.
void check_closed_surface(const SurfaceMesh& mesh, const std::string& source);

// Whether two triangles of the surface cross (share no edge or vertex and
// intersect).
bool self_intersects(const SurfaceMesh& mesh);

// Volume enclosed by a closed, outward-oriented surface [m³] (divergence
// theorem; negative when inward).
double enclosed_volume(const SurfaceMesh& mesh);

// Isotropic remeshing to `edge_length` [m] (> 0): every edge near that length,
// triangles near equilateral, vertices on the input surface. The input must
// pass check_closed_surface(). A remeshing that would make more than
// kMaxRemeshTriangles is refused (palpa::Error, Input) before it starts.
SurfaceMesh remesh_surface(const SurfaceMesh& mesh, double edge_length, int iterations = 5);

// The most triangles palpa remeshes a surface into (a few GB of memory and
// many minutes on a workstation): beyond it the edge length is surely wrong
// for the surface, or the surface's unit is (a scan in millimetres read as
// metres has a million times its area).
inline constexpr double kMaxRemeshTriangles = 4e6;

// About how many triangles a remeshing of a surface of `area` [m²] to
// `edge_length` makes: the area over that of an equilateral triangle.
double remeshed_triangles(double area, double edge_length);

// Total triangle area [m²].
double surface_area(const SurfaceMesh& mesh);

// Mean edge length [m] of a surface.
double mean_edge_length(const SurfaceMesh& mesh);

}  // namespace palpa::mesh
