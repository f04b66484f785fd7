// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The contact pressure a mat would read, recovered from nodal contact forces
// on one triangle surface: the normal traction per deformed area.
//
// A surface's nodal contact force F_k (its normal part [N]) is the integral
// of the traction against the vertex's hat function. Where the forces come
// from the surface's own samples (surface contact: contact/penalty_contact.hpp)
// they are consistent, and the lumped L2 projection recovers the traction:
//   p_k = F_k / A_k,   A_k the vertex's area where the surface is now.
// Where they are point loads from the other surface's samples (deposited on
// this surface's triangles at the anchors), a vertex receives one sample or
// three by chance when its mesh is as fine as the samples or finer: the
// lumped field aliases. Each force is then spread over the footprint of the
// samples it came from, a radius r (a few sample spacings), with weights that keep it whole:
//   p_j = Σ_k w_jk F_k / W_k,   w_jk = φ(|V_j − V_k| / r),
//   W_k = Σ_j w_jk A_j,         φ(q) = (1 − q²)² for q < 1, else 0,
// j and k vertices joined by a path along edges shorter than 2r (the other
// side of a thin sheet is not a neighbour). So Σ_j A_j p_j = Σ_k F_k: the
// map integrates to the force over the surface it is drawn on; a uniform
// traction stays uniform where the mesh is; r = 0 is the lumped projection.
// The same operator spreads any per-vertex amount the same way (a contact
// area: recover() of the areas in contact gives each vertex's fraction).
//
// Derivatives: recover() is linear in F; add_pullback() gives Σ_j g_j ∂p_j/∂F
// and ∂/∂V of a weighted sum of the pressures, the areas through
// geometry::add_vertex_area_gradient, the weights through the distances.
//
// Units: V [m], F [N], p [Pa]; r [m].

#include <Eigen/Core>
#include <vector>

namespace palpa::contact {

class TractionRecovery {
 public:
  // F: the surface's triangles (rows of a #V = n vertex set; vertices of no
  // triangle have no area and no pressure); radius: the footprint r ≥ 0 [m].
  // Throws palpa::Error (Input) for a negative or non-finite radius or a
  // triangle outside [0, n).
  TractionRecovery(Eigen::MatrixX3i F, Eigen::Index n, double radius);

  double radius() const noexcept { return radius_; }
  const Eigen::MatrixX3i& triangles() const noexcept { return F_; }

  // p (#V) at positions V (#V×3) from per-vertex amounts F (#V): the
  // pressures [Pa] of nodal normal forces [N].
  Eigen::VectorXd recover(const Eigen::MatrixX3d& V, const Eigen::VectorXd& F) const;
  // For a weight g on the pressures (#V): d_force += Σ_j g_j ∂p_j/∂F_k (#V;
  // only where F_k ≠ 0: a force of 0 has no direction to change along) and
  // d_position += Σ_j g_j ∂p_j/∂V (#V×3).
  void add_pullback(const Eigen::MatrixX3d& V, const Eigen::VectorXd& F, const Eigen::VectorXd& g,
                    Eigen::VectorXd& d_force, Eigen::MatrixX3d& d_position) const;

 private:
  // The vertices within the footprint of source k at V and their weights
  // (path: scratch, one +∞ per vertex, left so).
  struct Reach {
    std::vector<int> vertex;
    std::vector<double> weight;
  };
  Reach reach(const Eigen::MatrixX3d& V, int k, std::vector<double>& path) const;
  // fn(k, reach, W_k) for every source k with a force and an area (A: the
  // vertex areas at V); r = 0: the reach is k alone.
  template <class Fn>
  void for_each_source(const Eigen::MatrixX3d& V, const Eigen::VectorXd& F, const Eigen::VectorXd& A, Fn&& fn) const;

  Eigen::MatrixX3i F_;
  Eigen::Index n_;
  double radius_;
  std::vector<std::vector<int>> neighbours_;
};

}  // namespace palpa::contact
