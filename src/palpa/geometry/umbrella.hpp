// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The umbrella operator of a triangle mesh: each vertex's neighbours along
// triangle edges and their mean. Laplacian smoothing steps x ← x + λ(W − I)x
// (Taubin's λ|μ pairs) are built from it.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace palpa::geometry {

// The distinct neighbours of each of the n vertices along the edges of the
// triangles F (#F×3 rows of a #n-vertex mesh, either winding), sorted; empty
// for a vertex of no triangle.
std::vector<std::vector<int>> vertex_neighbours(const Eigen::MatrixX3i& F, Eigen::Index n);

// W: the row-normalized adjacency of the n vertices (n × n, dimensionless),
// W_ij = 1/|N(i)| for j ∈ vertex_neighbours(F, n)[i]; a vertex of no triangle
// is its own neighbour (W_ii = 1).
Eigen::SparseMatrix<double> umbrella_matrix(const Eigen::MatrixX3i& F, Eigen::Index n);

// The largest spike of a per-vertex field D (#V×3, e.g. a displacement):
// over `vertices`, the largest distance ‖D_v − mean_{j ∈ N(v)} D_j‖ (0 for a
// uniform field, and for an affine one where each ring is centred on its
// vertex, as inside a regular grid; a lone vertex moved by h among still
// neighbours gives h), and its vertex (−1 when `vertices` is empty).
// With `normals` (#V×3, unit: those of the moved surface), only the part of
// D_v − mean along n_v counts — what sticks out of the surface. Neighbours
// that slide past each other along it make no bump: a curved surface moved
// by the same amount along its own, diverging normals is an offset surface,
// smooth, though its moves differ sideways by about the move times the angle
// between neighbouring normals.
struct Spike {
  double distance = 0.0;
  int vertex = -1;
};
Spike largest_spike(const Eigen::MatrixX3d& D, const Eigen::MatrixX3i& F, const std::vector<int>& vertices,
                    const Eigen::MatrixX3d* normals = nullptr);

}  // namespace palpa::geometry
