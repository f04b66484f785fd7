// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The smoothing filter of the design variables: the support moves by S θ,
// not by θ, so the optimizer can only make smooth shapes — no single-vertex
// spikes — however rough the score's gradient is (a contact's gradient sits
// on the few vertices under it).
//
//   S = (A⁻¹ M)²,   A = M + r² L   over the design vertices,
//
// M the lumped vertex areas, L the cotangent Laplacian of the support, r the
// filter radius [m]. One factor is the Helmholtz (PDE) filter of topology
// optimization: the u with u − r²Δu = θ, whose kernel decays over r. Its 2D
// kernel is logarithmically singular at its centre, so it is applied twice:
// the kernel of S is continuous, and a θ on one vertex moves a smooth bump.
// Vertices outside the design region are held at 0 (A keeps the rows and
// columns of the design vertices only), so the moved region meets the rest of
// the support smoothly, over about r. A wave of length λ is scaled by
// (1 + (2πr/λ)²)⁻²: the checkerboard of the grid (λ = 2h) by 10⁻² at r = h,
// a dent five edges wide by 0.5 — the filter removes roughness and slows the
// optimizer's smallest features, it takes no smooth shape away (S is
// invertible). r = 0: S = I.

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <memory>
#include <vector>

#include "palpa/geometry/mesh.hpp"

namespace palpa::design {

class DesignFilter {
 public:
  // vertices: the design vertices (rows of support.V); radius ≥ 0 [m].
  // Throws palpa::Error (Input) for a negative or non-finite radius.
  DesignFilter(const SurfaceMesh& support, const std::vector<int>& vertices, double radius);
  ~DesignFilter();
  DesignFilter(const DesignFilter&) = delete;
  DesignFilter& operator=(const DesignFilter&) = delete;

  double radius() const noexcept { return radius_; }
  // S U: U has one row per design vertex, one column per component.
  Eigen::MatrixXd apply(const Eigen::MatrixXd& U) const;
  // Sᵀ G (the chain rule back from the moves to θ).
  Eigen::MatrixXd apply_transpose(const Eigen::MatrixXd& G) const;

 private:
  double radius_;
  Eigen::VectorXd mass_;  // M over the design vertices [m²]
  std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>> solver_;  // A
};

// The mean length of the support's edges between two design vertices [m]
// (0 when there is none): the default filter radius's unit.
double design_edge_length(const SurfaceMesh& support, const std::vector<int>& vertices);

}  // namespace palpa::design
