// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The vocabulary of penalty contact against a closed triangle obstacle
// (thesis §7.3.4–7.3.5, Appendix A): the positions a pass reads, a closest
// feature's world vertices, the wrench on the obstacle. The potential is
// penalty_contact.hpp (detection included), the stiffness rule stiffness.hpp,
// the spring areas of skin vertices spring_areas.hpp.
//
// Usage in a System (solve/system.hpp); positions are world [m], one column
// per point (a 3N DOF vector maps as Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, N)):
//
//   contact::Obstacle support(mesh, "chair.obj");        // validates; set_pose() moves it
//   contact::PenaltyContact contact(contact::vertex_samples(surface), k, "chair");
//                                                        // member: committed state;
//                                                        // surface: columns that can touch
//   prepare(x):  contact.commit(support, P(x));           // Newton iterate
//   energy(x):   E_el(x) + contact.detected_energy(support, P(x));
//                                                        // line-search trial: fresh detection,
//                                                        // const, parallel, nothing stored
//   gradient(x): contact.add_gradient(support, P(x), G);  // G: 3×N, += ∂E/∂p
//   hessian(x):  contact.for_each_surface_hessian(support, [&](int a, int b, const Matrix3d& B) {
//                  H.block(3a, 3b) += B; });             // 2k P⊥: with vertex samples only
//                                                        // diagonal 3×3 blocks of the surface
//                                                        // vertices, already in an elastic pattern
//   output:      contact.add_forces(...), obstacle_wrench(...)
//
// (System Hessians hold the lower triangle only: add the block's lower
// triangle, entries (r, c) with r ≥ c.) Several obstacles: one PenaltyContact
// per obstacle, energies add. A complete small System wired this way, solved
// by palpa's Newton, is in tests/contact/newton_contact_test.cpp.
//
// Units: [m], forces [N], torques [N·m].

#include <Eigen/Core>

#include "palpa/contact/obstacle.hpp"
#include "palpa/contact/penalty.hpp"

namespace palpa::contact {

using Points = Eigen::Ref<const Eigen::Matrix3Xd>;

// The feature's vertices in world coordinates.
FeatureGeometry feature_geometry(const Obstacle& obstacle, const ClosestPoint& closest);

struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // [N·m]
};

}  // namespace palpa::contact
