// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Penalty contact of points (the surface vertices of a tet mesh) against a
// closed triangle obstacle (thesis §7.3.4–7.3.5, Appendix A).
//
// Usage in a System (solve/system.hpp); positions are world [m], one column
// per point (a 3N DOF vector maps as Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, N)):
//
//   contact::Obstacle support(mesh, "chair.obj");        // validates; set_pose() moves it
//   contact::ContactSet committed;                       // member: the committed state
//   std::vector<int> surface = ...;                      // columns that can touch
//
//   prepare(x):  committed.detect(support, P(x), surface);           // Newton iterate
//   energy(x):   E_el(x) + contact::detected_energy(support, P(x), surface, k);
//                                                        // line-search trial: fresh detection,
//                                                        // const, parallel, nothing stored
//   gradient(x): committed.add_gradient(support, P(x), k, G);        // G: 3×N, += ∂E/∂p
//   hessian(x):  for (const auto& c : committed.contacts())
//                  H.block(3·c.point, 3·c.point) += contact::hessian_block(support, c, k);
//                                                        // 2k P⊥: only diagonal 3×3 blocks of
//                                                        // the surface vertices, already in
//                                                        // an elastic pattern
//   output:      committed.forces(...), obstacle_wrench(...), pressures(...)
//
// (System Hessians hold the lower triangle only: add the block's lower
// triangle, entries (r, c) with r ≥ c.) Several obstacles: one ContactSet per obstacle, energies
// add. A complete small System wired this way, solved by palpa's Newton, is in
// tests/contact/newton_contact_test.cpp. k: stiffness_for_penetration() below.
//
// gradient/Hessian with the committed set are exact derivatives of
// committed.energy(x): each contact keeps its feature (vertex, edge or face),
// and its anchor slides on that feature as the point moves (Appendix A). At the
// prepared point committed.energy(x) == detected_energy(x), and both have the
// same gradient as long as no point changes Voronoi region or crosses the
// surface. Away from it a committed contact acts as a two-sided spring to its
// feature even if the point has left the obstacle: that is why line-search
// trials must use detected_energy(), never committed.energy().
//
// Sign conventions: E ≥ 0; the gradient ∂E/∂p = 2k(p − a) points into the
// obstacle; the contact force on a point, f = −∂E/∂p = 2k(a − p), pushes it out
// of the obstacle; the obstacle feels the reaction −f at the anchor a.
// Units: [m], k [N/m], E [J], forces [N], torques [N·m], pressures [Pa].

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

// ∂²E/∂p² of one contact, 2k P⊥ [N/m] (positive semi-definite).
Eigen::Matrix3d hessian_block(const Obstacle& obstacle, const Contact& contact, double k);

// Σ k·depth² over the points `which` (columns of `points`) inside the obstacle,
// detected afresh [J]. Parallel (TBB), deterministic sum, allocation-free;
// safe to call concurrently. scale: empty, or one factor per column of
// `points`: point i's stiffness is k·scale[i] (e.g. its vertex area over the
// mean, so that a uniform penetration means a uniform pressure).
double detected_energy(const Obstacle& obstacle, Points points, std::span<const int> which,
                       double k, std::span<const double> scale = {});

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
  // Per-point stiffness factors (one per column of the positions; empty: 1):
  // every method below then uses k·scale[point] for that point's spring.
  void set_scale(std::vector<double> scale);
  const std::vector<double>& scale() const noexcept { return scale_; }
  // k·scale[c.point] (k without a scale).
  double stiffness_of(const Contact& c, double k) const;

  const std::vector<Contact>& contacts() const { return contacts_; }
  std::size_t size() const { return contacts_.size(); }
  bool empty() const { return contacts_.empty(); }
  // Largest depth at detection [m] (0 without contacts).
  double max_depth() const;

  // With the committed features and sliding anchors, at `points` (any
  // positions, same columns):
  // E = Σ k‖p − a(p)‖² [J].
  double energy(const Obstacle& obstacle, Points points, double k) const;
  // grad.col(point) += ∂E/∂p [N]; grad: 3×N.
  void add_gradient(const Obstacle& obstacle, Points points, double k,
                    Eigen::Ref<Eigen::Matrix3Xd> grad) const;
  // grad.col(v) += ∂E/∂q_v for every obstacle vertex v (world) [N]; grad: 3×#V.
  // For a deformable obstacle or one whose vertices are design variables.
  void add_obstacle_gradient(const Obstacle& obstacle, Points points, double k,
                             Eigen::Ref<Eigen::Matrix3Xd> grad) const;
  // Contact force on each point, f = −∂E/∂p [N]: forces is resized to 3×N
  // (N = points.cols()), zero where there is no contact.
  void forces(const Obstacle& obstacle, Points points, double k, Eigen::Matrix3Xd& forces) const;
  // Reaction on the obstacle: force −Σ f, torque Σ (a − about) × (−f) about
  // `about` [m]. Equal and opposite to the wrench of the f on the points.
  Wrench obstacle_wrench(const Obstacle& obstacle, Points points, double k,
                         const Eigen::Vector3d& about) const;

 private:
  std::vector<Contact> contacts_;
  std::vector<double> scale_;        // per-point stiffness factors (empty: none)
  std::vector<ClosestPoint> slot_;  // scratch: one per queried point
  std::vector<unsigned char> hit_;  // scratch: inside or not
  std::vector<int> all_;            // 0 … N−1, for detect() without a list
};

// Contact pressure per point [Pa]: ‖f_i‖ / area_i (0 where area_i = 0).
// forces: 3×N [N]; areas: N [m²] (e.g. vertex_areas() of the body surface,
// indexed by the same columns).
Eigen::VectorXd pressures(const Eigen::Matrix3Xd& forces, const Eigen::VectorXd& areas);

// Choosing k (the thesis aims at a maximum penetration of about 0.3 mm).
// A penetrating point at depth δ carries 2kδ. If a load [N] is carried evenly
// by `contact_points` points, each at the target depth [m], then
//   k = load / (2 · contact_points · target).
// Assumes an even share: the deepest point carries more, so expect the maximum
// penetration above target by the peak-to-mean pressure ratio; correct with
// corrected_stiffness(). contact_points may be estimated as the expected contact
// area over the mean vertex area.
double stiffness_for_penetration(double load, double contact_points, double target);
// Outer-loop update after an equilibrium with maximum penetration `max_depth`:
// k·max_depth/target (under a fixed load and contact area the depth scales as
// 1/k), the factor clamped to [1/max_factor, max_factor]. Returns k unchanged
// when nothing penetrated (max_depth ≤ 0).
double corrected_stiffness(double k, double max_depth, double target, double max_factor = 10.0);

}  // namespace palpa::contact
