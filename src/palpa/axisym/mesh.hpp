// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Structured quadrilateral mesh of the (r, z) half-plane of an axisymmetric
// layer: r ∈ [0, R], z ∈ [−D, 0], top surface z = 0, rigid base z = −D, punch of
// radius a centred on the axis r = 0 (thesis ch. 4).
//
// The grid is graded: under the punch the columns shrink toward the rim r = a,
// outside they grow geometrically from the rim to R, and the rows grow from the
// top surface down to the base. Mesh level L splits every cell of the level-0
// grid into 2^L × 2^L, so refining keeps the grading and the mesh nests: the
// force converges as the cells shrink (h-refinement).

#include <Eigen/Core>
#include <vector>

namespace palpa::axisym {

struct LayerGeometry {
  double punch_radius = 0.0;  // a [m]
  double thickness = 0.0;     // D [m]
  double outer_radius = 0.0;  // R [m]; 0 = default_outer_radius(a, D)
};

// The far-field radius used when none is given: kOuterRadiusFactor · max(a, D),
// enough for the force to be within 0.5% of an infinite layer (tested).
inline constexpr double kOuterRadiusFactor = 8.0;
double default_outer_radius(double punch_radius, double thickness) noexcept;

struct AxisymMesh {
  Eigen::MatrixX2d nodes;   // #N × 2 rest positions (r, z) [m]
  Eigen::MatrixX4i quads;   // #E × 4 node indices, counter-clockwise in (r, z)
  int columns = 0;          // nodes per row (along r)
  int rows = 0;             // nodes per column (along z)
  std::vector<int> axis_nodes;  // r = 0
  std::vector<int> base_nodes;  // z = −D
  std::vector<int> top_nodes;   // z = 0, by increasing r
  double rim_cell_size = 0.0;   // smallest cell size at the punch rim [m]
  LayerGeometry geometry;       // with outer_radius resolved

  Eigen::Index num_nodes() const noexcept { return nodes.rows(); }
  Eigen::Index num_elements() const noexcept { return quads.rows(); }
  // Node at column i (along r) and row j (j = 0 at the base, rows − 1 at the top).
  int node(int i, int j) const noexcept { return j * columns + i; }
};

// Builds the mesh at `level` (>= 0). Throws palpa::Error (Input) for
// non-positive or non-finite sizes, R <= a, or a level above 7.
AxisymMesh make_layer_mesh(const LayerGeometry& geometry, int level);

// Structured quadrilateral mesh of a whole cylindrical sample compressed between
// two plates: r ∈ [0, R], z ∈ [−H, 0], the top face z = 0 under the moving
// platen, the base z = −H on the fixed one, the side wall r = R free. The
// sample radius R is geometry.punch_radius (the platen covers the whole top) or,
// if that is 0, geometry.outer_radius; if both are given they must agree. H is
// geometry.thickness. The returned geometry has punch_radius = outer_radius = R.
//
// There is no rim inside the sample: a frictionless test is homogeneous (any
// mesh is exact), and a bonded one concentrates its strain where the free side
// wall meets the platens, and that is also where the bulging wall folds onto
// them under large compression. So the columns shrink geometrically toward the
// side wall and the rows toward both platens (largest to smallest cell
// kCylinderGrading at level 0), with about kCylinderCells cells across the
// shorter of R and H; levels refine as for the layer. top_nodes and base_nodes
// run by increasing r; rim_cell_size is the smallest cell size at the corners.
inline constexpr int kCylinderCells = 8;
inline constexpr double kCylinderGrading = 3.0;
AxisymMesh make_cylinder_mesh(const LayerGeometry& geometry, int level);

// The nodes on the side wall r = R, from the base up, without the two corners
// (those belong to the platens): #rows − 2 node indices.
std::vector<int> side_wall_nodes(const AxisymMesh& mesh);

// `n` + 1 coordinates from x0 to x1 whose interval lengths form a geometric
// sequence with `ratio` between consecutive intervals (ratio < 1: shrinking
// toward x1).
std::vector<double> geometric_points(double x0, double x1, int n, double ratio);

}  // namespace palpa::axisym
