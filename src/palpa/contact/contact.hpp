// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Contact detection of points (the surface vertices of a tet mesh) against a
// closed triangle obstacle (thesis §7.3.4–7.3.5, Appendix A): which points are
// inside and their closest features. The penalty potential built on it is
// penalty_contact.hpp, the stiffness rule stiffness.hpp, the spring areas of
// skin vertices spring_areas.hpp.
//
// Usage in a System (solve/system.hpp); positions are world [m], one column
// per point (a 3N DOF vector maps as Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, N)):
//
//   contact::Obstacle support(mesh, "chair.obj");        // validates; set_pose() moves it
//   contact::PenaltyContact contact(surface, k, "chair"); // member: committed state;
//                                                        // surface: columns that can touch
//   prepare(x):  contact.commit(support, P(x));           // Newton iterate
//   energy(x):   E_el(x) + contact.detected_energy(support, P(x));
//                                                        // line-search trial: fresh detection,
//                                                        // const, parallel, nothing stored
//   gradient(x): contact.add_gradient(support, P(x), G);  // G: 3×N, += ∂E/∂p
//   hessian(x):  contact.for_each_point_hessian(support, [&](int p, const Matrix3d& B) {
//                  H.block(3p, 3p) += B; });             // 2k P⊥: only diagonal 3×3 blocks of
//                                                        // the surface vertices, already in
//                                                        // an elastic pattern
//   output:      contact.add_forces(...), obstacle_wrench(...)
//
// (System Hessians hold the lower triangle only: add the block's lower
// triangle, entries (r, c) with r ≥ c.) Several obstacles: one PenaltyContact
// per obstacle, energies add. A complete small System wired this way, solved
// by palpa's Newton, is in tests/contact/newton_contact_test.cpp.
//
// Units: [m], forces [N], torques [N·m].

#include <Eigen/Core>
#include <span>
#include <vector>

#include "palpa/contact/obstacle.hpp"
#include "palpa/contact/penalty.hpp"

namespace palpa::contact {

using Points = Eigen::Ref<const Eigen::Matrix3Xd>;

// One penetrating point and the feature it is anchored to.
struct Contact {
  int point = -1;        // column of the positions
  ClosestPoint closest;  // at detection: anchor, depth (= distance), feature
};

// The feature's vertices in world coordinates.
FeatureGeometry feature_geometry(const Obstacle& obstacle, const ClosestPoint& closest);

struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // [N·m]
};

class ContactSet {
 public:
  // Finds the points `which` (columns of `points`; all columns if omitted)
  // strictly inside the obstacle and their closest features, replacing the
  // contacts held. Parallel (TBB); once the set has seen as many points it
  // allocates nothing. Contacts come in the order of `which`.
  void detect(const Obstacle& obstacle, Points points, std::span<const int> which);
  void detect(const Obstacle& obstacle, Points points);
  void clear() { contacts_.clear(); }

  const std::vector<Contact>& contacts() const { return contacts_; }
  std::size_t size() const { return contacts_.size(); }
  bool empty() const { return contacts_.empty(); }
  // Largest depth at detection [m] (0 without contacts).
  double max_depth() const;

 private:
  std::vector<Contact> contacts_;
  std::vector<ClosestPoint> slot_;  // scratch: one per queried point
  std::vector<unsigned char> hit_;  // scratch: inside or not
  std::vector<int> all_;            // 0 … N−1, for detect() without a list
};

}  // namespace palpa::contact
