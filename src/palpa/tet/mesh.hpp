// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Tet meshes for simulation: checks, orientation and structured box meshes
// (the boundary surface is geometry/boundary.hpp).

#include <Eigen/Core>
#include <map>
#include <numbers>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::tet {

// What prepare_tet_mesh found and did.
struct TetMeshCheck {
  Eigen::Index flipped = 0;   // tets whose corner order was reversed (all, or none)
  Eigen::Index unused_vertices = 0;
  double min_volume = 0.0;    // smallest tet volume after orientation [m³]
  double total_volume = 0.0;  // [m³]
};

// Checks a tet mesh for simulation and orients it. `name` (a file name or
// "scene.json: mesh") is used in every message. Throws palpa::Error (Input) for:
// no vertices or tets, non-finite coordinates, corner indices out of range or
// repeated within a tet, degenerate tets (|V| ≤ 1e-9 · h³, h the tet's longest
// edge), and inverted tets — a mesh whose tets are all negatively oriented is
// accepted and flipped (some writers use that convention), but a mix of
// orientations means inverted elements and is refused, naming the first one.
TetMeshCheck prepare_tet_mesh(TetMesh& mesh, std::string_view name);

// A structured box [lo, hi] with cells(0)×cells(1)×cells(2) cubes, each cut
// into 6 tets around its main diagonal (a conforming Kuhn subdivision), all
// positively oriented; region 0. Vertex sets of the six faces are named
// "xmin", "xmax", "ymin", "ymax", "zmin" (also "bottom") and "zmax" (also "top").
struct StructuredMesh {
  TetMesh mesh;
  std::map<std::string, std::vector<int>> vertex_sets;
};
using BoxMesh = StructuredMesh;
BoxMesh make_box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                      const Eigen::Vector3i& cells);

// A structured cylinder on the z axis, or a sector of one, with its top face at
// z = 0: rings at `radii` (increasing, radii[0] = 0 the axis), layers at
// `depths` below the top (increasing, depths[0] = 0), and `segments` equal
// angles around the full circle, of which a sector θ ∈ [0, angle] keeps
// segments·angle/2π (a whole number ≥ 1; angle = 2π closes the circle). The
// ring nodes sit at θ = 2πj/segments, as contact::cylinder_surface's, so a punch
// of radius radii[i] with as many segments has its edge on ring i.
// Every cell (two rings × two layers × two angles) is cut into two triangular
// prisms (one on the axis), and every prism into 3 tets whose quad faces are
// split from their lowest vertex index, so that neighbours agree. Region 0.
// Vertex sets: "top"/"zmax", "bottom"/"zmin", "side" (the outer ring), and for a
// sector "sector_start" (θ = 0: the half-plane y = 0, x ≥ 0) and "sector_end"
// (θ = angle), both with the axis.
StructuredMesh make_cylinder_mesh(std::span<const double> radii, std::span<const double> depths, int segments,
                                  double angle = 2.0 * std::numbers::pi);

}  // namespace palpa::tet
