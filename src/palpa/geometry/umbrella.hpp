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

}  // namespace palpa::geometry
