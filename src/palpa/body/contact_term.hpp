// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Penalty contact of a tet body's skin with one obstacle (thesis §7.3.4–7.3.5,
// Appendix A), as a term (solve/term.hpp) of the tet systems: the forward pass of
// contact::PenaltyContact, sampled on the skin in one of two ways:
//  * Vertices: node-to-surface, each skin vertex a spring k·A_i/Ā with
//    A_i from contact::SpringAreas (k [N/m]; the thesis's model).
//  * Surface: the rule's points on every skin triangle, each spring its share
//    of the triangle's rest area (k the pressure per depth [Pa/m]): the
//    tractions integrated over the skin, so the nodal forces are the
//    consistent loads of the pressure field and the Hessian couples a
//    triangle's corners (vertex_pairs()).
// The obstacle is the rigid indenter or support, or a deformable support's
// boundary surface (rest/coupled.hpp moves it).
//
// energy(x) detects afresh at x (a line-search trial sees its own contacts);
// prepare(x) commits the contact set of an accepted iterate; the gradient and
// Hessian use the committed features with sliding anchors (exact derivatives
// of the committed energy). Collision-detection time is accumulated for the
// benchmarks and the summary.

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "palpa/contact/obstacle.hpp"
#include "palpa/contact/penalty_contact.hpp"
#include "palpa/contact/spring_areas.hpp"
#include "palpa/solve/term.hpp"

namespace palpa::body {

enum class ContactSampling { Vertices, Surface };

class ContactTerm final : public Term {
 public:
  // obstacle: must outlive the term; its pose may change between solves.
  // rest: the body's rest positions (#V×3) [m]; faces: its skin triangles
  // (rows of rest, outward), whose vertices are the ones that can touch.
  // k: the spring of a vertex of mean skin area [N/m] (Vertices), or the
  // pressure per depth [Pa/m] (Surface, with `subdivisions`² points per
  // triangle, contact::subdivision_rule).
  ContactTerm(const contact::Obstacle& obstacle, const Eigen::MatrixX3d& rest, Eigen::MatrixX3i faces, double k,
              ContactSampling sampling = ContactSampling::Vertices, int subdivisions = 2);

  ContactSampling sampling() const noexcept { return sampling_; }

  // Stick (contact::Friction): see anchor().
  void set_friction(contact::Friction friction) { potential_.set_friction(friction); }
  // Anchors the contacts at x that have no anchor where they met the
  // obstacle: `reference` (positions, 3N) with the obstacle at
  // `reference_pose` (contact::PenaltyContact::anchor). Recommits; returns the
  // number of new anchors.
  int anchor(const Eigen::VectorXd& x, const Eigen::VectorXd& reference, const contact::Pose& reference_pose);
  void set_anchors(const std::vector<std::array<double, 5>>& rows) { potential_.set_anchors(rows, *obstacle_); }

  double stiffness() const noexcept { return potential_.stiffness(); }
  void set_stiffness(double k) { potential_.set_stiffness(k); }
  const contact::Obstacle& obstacle() const noexcept { return *obstacle_; }
  const std::vector<int>& surface() const noexcept { return areas_.surface(); }
  // The skin triangles (rows of the body's vertices).
  const Eigen::MatrixX3i& faces() const noexcept { return areas_.faces(); }
  // The committed contacts and the potential they make; sample s sits on
  // skin vertex surface()[s].
  const contact::PenaltyContact& potential() const noexcept { return potential_; }

  // The energy at positions p (3N) against `obstacle` in place of the
  // term's own (a deformed copy of it: rest/coupled.hpp), detected afresh.
  double detected_energy(const contact::Obstacle& obstacle, const Eigen::VectorXd& p) const;

  // Term (the positions s.p only).
  double energy(const VertexState& s) const override;
  double add_gradient(const VertexState& s, Eigen::VectorXd& g) const override;
  void add_blocks(const VertexState& s, PsdProjection projection, std::vector<VertexBlock>& blocks) const override;
  std::vector<std::array<int, 2>> vertex_pairs() const override;
  void prepare(const VertexState& s) override;
  bool active() const override { return !potential_.empty(); }

  // The spring-area law (contact/spring_areas.hpp) over the committed
  // contacts; Surface sampling has no spring areas (0: nothing changed).
  double update_areas(double min_change = 0.0);
  void set_areas(const std::vector<double>& areas);
  double mean_area() const noexcept { return areas_.mean_area(); }
  const std::vector<double>& spring_area() const noexcept { return areas_.areas(); }

  // Contact force on every body vertex at positions x (3N) [N] (3×N).
  Eigen::Matrix3Xd vertex_forces(const Eigen::VectorXd& x) const;
  // Contact pressure per body vertex at x [Pa], 0 off contact: the traction
  // per deformed area, |f_i| over the vertex's share of the skin at x (the
  // lumped recovery, contact/traction_recovery.hpp), so that Σ p_i A_i(x) =
  // Σ |f_i|.
  Eigen::VectorXd pressures(const Eigen::VectorXd& x) const;
  // The wrench on the obstacle about `about` [m].
  contact::Wrench obstacle_wrench(const Eigen::VectorXd& x, const Eigen::Vector3d& about) const;

  // Seconds spent in collision detection since construction (or reset).
  double detection_seconds() const noexcept { return static_cast<double>(detection_ns_.load()) * 1e-9; }
  std::int64_t detections() const noexcept { return detections_.load(); }
  void reset_timers() noexcept {
    detection_ns_ = 0;
    detections_ = 0;
  }

 private:
  // The samples' spring factors from the spring areas.
  void rescale();

  const contact::Obstacle* obstacle_;
  ContactSampling sampling_;
  contact::SpringAreas areas_;
  contact::PenaltyContact potential_;
  mutable std::atomic<std::int64_t> detection_ns_{0};
  mutable std::atomic<std::int64_t> detections_{0};
};

}  // namespace palpa::body
