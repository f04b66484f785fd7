// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Sparse symmetric test matrices, shared by the solve tests and benchmarks.
// All are returned with BOTH triangles stored (so A * x is the true product);
// lower_triangle() gives the half that systems hand to the solvers.

#include <Eigen/SparseCore>
#include <random>

namespace palpa::test {

// 5-point Laplacian on an m×m grid of interior points with zero Dirichlet
// boundary: SPD, n = m², 4 ≤ nonzeros per row ≤ 5. Unit grid spacing.
Eigen::SparseMatrix<double> laplacian_2d(int m);

// The same in 2D, the pattern of the axisymmetric solver's bilinear quads:
// m×m nodes, 2 DOFs per node, each cell couples its 4 nodes through springs
// along its 6 node pairs. SPD, n = 2m², up to 18 nonzeros per row.
Eigen::SparseMatrix<double> elasticity_2d_like(int m, double mass_diagonal = 1e-3);

// A stiffness-like matrix with the structure of trilinear hexahedral elasticity:
// m×m×m nodes on a unit grid, 3 DOFs per node, each cell couples its 8 nodes
// through axial springs (stiffness 1) along all 28 node pairs, plus
// `mass_diagonal` on the diagonal (a mass term that removes the rigid modes;
// the condition number grows as it shrinks, about 5e4 for 1e-3). SPD, n = 3m³,
// up to 81 nonzeros per row.
Eigen::SparseMatrix<double> elasticity_3d_like(int m, double mass_diagonal = 1e-3);

// Random symmetric matrix with about `offdiag_per_column` off-diagonal entries per
// column (uniform in [-1, 1]) and diagonal = 1 + sum of |off-diagonals| of the
// row: strictly diagonally dominant, hence SPD.
Eigen::SparseMatrix<double> random_spd(int n, int offdiag_per_column, std::mt19937_64& rng);

// The entries with row ≥ col.
Eigen::SparseMatrix<double> lower_triangle(const Eigen::SparseMatrix<double>& A);

// Full symmetric matrix from its lower triangle (the System::hessian convention).
Eigen::SparseMatrix<double> symmetric_from_lower(const Eigen::SparseMatrix<double>& L);

}  // namespace palpa::test
