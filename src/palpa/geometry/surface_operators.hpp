// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Discrete differential operators on a triangle surface (palpa::SurfaceMesh).
//
// Conventions: V is #V×3 [m], F is #F×3 0-based rows of V. Every function
// accepts any triangle soup; zero-area triangles contribute nothing to the
// Laplacian (their cotangents are undefined) and nothing to areas. Vertices
// used by no triangle get zero area, zero Laplacian row and a zero normal.

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "palpa/geometry/mesh.hpp"

namespace palpa::geometry {

// #F triangle areas [m²].
Eigen::VectorXd face_areas(const SurfaceMesh& mesh);
// The same for V: #V×3 [m] and F: #F×3 rows of V.
Eigen::VectorXd face_areas(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);

// #F×3 unit triangle normals, (V1−V0)×(V2−V0) normalized (outward for a closed
// surface wound counter-clockwise seen from outside). Zero rows for zero-area
// triangles.
Eigen::MatrixX3d face_normals(const SurfaceMesh& mesh);

// ∫ p n dA [N] of a per-vertex pressure p [Pa] (#V) linear over each triangle,
// n the triangles' unit normals (face_normals): the net force of the map on
// the surface's positive side. On a curved surface |∫ p n dA| < ∫ p dA.
Eigen::Vector3d pressure_force(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::VectorXd& pressure);

// #V barycentric vertex areas [m²]: one third of the area of every incident
// triangle. They sum to the surface area and are never negative.
Eigen::VectorXd vertex_areas(const SurfaceMesh& mesh);
// The same for V: #V×3 [m] and F: #F×3 rows of V.
Eigen::VectorXd vertex_areas(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F);
// grad += Σ_v w_v ∂A_v/∂V (#V×3 [m·units of w]) for the vertex areas A_v
// above and a weight w_v per vertex: a triangle (a, b, c) of unit normal n̂
// moves its area by ∂A/∂a = ½ n̂ × (c − b) (cyclically), a third to each corner.
void add_vertex_area_gradient(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::VectorXd& w,
                              Eigen::MatrixX3d& grad);

// How vertex_normals() weighs the normals of the triangles around a vertex.
enum class NormalWeighting {
  Uniform,  // the unit face normals, each counted once
  Area,     // the face normals scaled by the triangle's area: the sum of (V1−V0)×(V2−V0)
  Angle,    // the unit face normals scaled by the corner angle at the vertex (Thürmer &
            // Wüthrich): independent of how a flat region is triangulated
};

// #V×3 unit vertex normals: the weighted sum of the incident face normals,
// normalized. Zero rows for vertices with no (non-degenerate) triangle.
Eigen::MatrixX3d vertex_normals(const SurfaceMesh& mesh,
                                NormalWeighting weighting = NormalWeighting::Angle);

// #V×#V cotangent Laplacian L (the P1 finite-element stiffness matrix):
//   L_ij = −½ (cot α_ij + cot β_ij) for an edge ij (α, β the angles opposite
//   to it), L_ii = −Σ_j L_ij.
// Symmetric positive semi-definite, rows sum to 0; ½ uᵀ L u is the Dirichlet
// energy ½∫|∇u|² of the piecewise-linear function with vertex values u
// (units of u² — L itself is dimensionless). Note the sign: L = −Δ (weak form).
Eigen::SparseMatrix<double> cotangent_laplacian(const SurfaceMesh& mesh);

// #V×#V lumped (diagonal) mass matrix, M_ii = vertex_areas(mesh)(i) [m²].
// M⁻¹ L u is the pointwise −Δu [units of u / m²].
Eigen::SparseMatrix<double> mass_matrix(const SurfaceMesh& mesh);

}  // namespace palpa::geometry
