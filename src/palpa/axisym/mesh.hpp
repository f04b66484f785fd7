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

// `n` + 1 coordinates from x0 to x1 whose interval lengths form a geometric
// sequence with `ratio` between consecutive intervals (ratio < 1: shrinking
// toward x1).
std::vector<double> geometric_points(double x0, double x1, int n, double ratio);

}  // namespace palpa::axisym
