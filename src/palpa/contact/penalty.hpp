// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The penalty kernel of one contact (thesis (7.10) and Appendix A):
//
//   E = k‖p − a‖²,  a = the projection of p onto the affine hull of the feature
//                      q_0 … q_{m−1} (m = 1 vertex, 2 edge, 3 face),
//
// the sliding anchor: while p stays in the feature's Voronoi region, a is the
// closest surface point and slides along the edge or face as p (or the
// feature's vertices) move. With d = p − a and a = Σ β_i q_i:
//   ∂E/∂p   = 2k d,          ∂E/∂q_i = −2k β_i d   (envelope theorem)
//   ∂²E/∂p² = 2k P⊥,  P⊥ = I (vertex), I − eeᵀ (edge, e unit), nnᵀ (face),
// (A.3), (A.6), (A.9); the full Hessian over z = (p, q_0, q_1, q_2) follows from
// differentiating β and d (penalty.cpp derives it). The p-block is positive
// semi-definite; the full 12×12 Hessian is not in general (it is the true
// Hessian, for sensitivities with respect to the obstacle's vertices).
//
// A stuck contact (static friction, "stick") keeps its anchor at fixed
// weights β on a face instead: a = Σ β_i q_i moves only with the q_i, so
//   ∂E/∂p = 2k d,  ∂E/∂q_i = −2k β_i d,  ∂²E/∂z² = 2k [I, −β_j I; −β_i I, β_i β_j I],
// a spring to a point carried by the obstacle (tangential and normal alike).
//
// Units: positions [m], k [N/m], E [J], gradients [N], Hessians [N/m].

#include <Eigen/Core>
#include <array>

namespace palpa::contact {

// The feature's vertices q_0 … q_{m−1} in world coordinates [m], m = 1, 2, 3.
struct FeatureGeometry {
  int m = 3;
  std::array<Eigen::Vector3d, 3> q{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                   Eigen::Vector3d::Zero()};
  // A stuck anchor: a = Σ stuck_weights_i q_i (m = 3) instead of the projection.
  bool stuck = false;
  Eigen::Vector3d stuck_weights = Eigen::Vector3d::Zero();
};

using Vector12d = Eigen::Matrix<double, 12, 1>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

// The sliding anchor of p on a feature: a = Σ weights_i q_i, d = p − a.
struct Anchor {
  Eigen::Vector3d point;    // a [m]
  Eigen::Vector3d weights;  // β (unused entries 0)
};
Anchor sliding_anchor(const Eigen::Vector3d& p, const FeatureGeometry& g);

// E = k‖p − a‖² [J].
double penalty_energy(const Eigen::Vector3d& p, const FeatureGeometry& g, double k);
// ∂E/∂p = 2k(p − a) [N].
Eigen::Vector3d penalty_gradient(const Eigen::Vector3d& p, const FeatureGeometry& g, double k);
// ∂²E/∂p² = 2k P⊥ [N/m] (independent of p).
Eigen::Matrix3d penalty_hessian(const FeatureGeometry& g, double k);
// ∂E/∂z over z = (p, q_0, q_1, q_2) [N]; blocks of unused q_i are zero.
Vector12d penalty_gradient_full(const Eigen::Vector3d& p, const FeatureGeometry& g, double k);
// ∂²E/∂z² [N/m], symmetric; rows/columns of unused q_i are zero.
Matrix12d penalty_hessian_full(const Eigen::Vector3d& p, const FeatureGeometry& g, double k);

}  // namespace palpa::contact
