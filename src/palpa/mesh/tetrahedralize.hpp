// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Quality tetrahedral meshes of closed surfaces (TetGen 1.5, used privately),
// and the quality figures of any tet mesh.

#include <Eigen/Core>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::mesh {

// TetGen's quality bounds (its -q, -a and -Y switches).
struct TetQuality {
  // Largest circumradius / shortest edge of a tet (-q first value); > 1.0
  // (TetGen terminates for bounds ≥ about 1.1; 2.0 is its default).
  double max_radius_edge = 1.5;
  // Smallest dihedral angle TetGen refines towards [rad] (-q second value);
  // in [0, 70°). A target, not a guarantee near sharp input features: check
  // TetStatistics::min_dihedral of the result.
  double min_dihedral = 12.0 * 3.14159265358979323846 / 180.0;
  // Largest tet volume [m³] (-a); 0 = no bound.
  double max_volume = 0.0;
  // Keep the input surface triangles as they are (-Y: no Steiner points on the
  // boundary), so the mesh's boundary vertices are exactly the surface's.
  bool preserve_surface = true;
};

// Solid tet mesh of the inside of a closed, consistently oriented,
// self-intersection-free triangle surface (check it with
// check_closed_surface() first). The result's boundary holds the surface
// triangles (marker 1), region is all 1, vertices 0..#V−1 are the surface's
// vertices in order when preserve_surface is set. Tets are positively oriented
// (det[b−a, c−a, d−a] > 0). Throws palpa::Error (Input) for bad quality
// options or when TetGen refuses the surface (naming what it found), (Solver)
// for a TetGen failure otherwise.
TetMesh tetrahedralize(const SurfaceMesh& closed_surface, const TetQuality& quality = {});

// Element quality of a tet mesh.
struct TetStatistics {
  Eigen::Index tets = 0;
  Eigen::Index vertices = 0;
  double volume = 0.0;              // Σ signed volumes [m³]
  double min_volume = 0.0;          // smallest signed tet volume [m³]
  Eigen::Index inverted = 0;        // tets with signed volume ≤ 0
  double min_dihedral = 0.0;        // over all tets [rad]
  double max_dihedral = 0.0;        // [rad]
  double max_radius_edge = 0.0;     // circumradius / shortest edge (≥ √(3/8) ≈ 0.612)
  double mean_radius_edge = 0.0;
  Eigen::Index below_min_dihedral = 0;     // tets with a dihedral angle below the bound asked
  Eigen::Index above_max_radius_edge = 0;  // tets whose radius-edge ratio exceeds the bound
};
// Quality figures of `mesh`, counting tets beyond `bounds` (its dihedral and
// radius-edge values only).
TetStatistics tet_statistics(const TetMesh& mesh, const TetQuality& bounds = {});

// Per-tet signed volume det[b−a, c−a, d−a]/6 [m³], #T.
Eigen::VectorXd tet_volumes(const TetMesh& mesh);

namespace detail {
// TetGen on several closed shells at once: every triangle of shells[k] gets
// boundary marker k+1; `holes` are points inside regions to leave empty.
TetMesh tetgen_shells(const std::vector<const SurfaceMesh*>& shells,
                      const std::vector<Eigen::Vector3d>& holes, const TetQuality& quality);
}  // namespace detail

}  // namespace palpa::mesh
