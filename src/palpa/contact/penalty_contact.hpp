// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The penalty-contact potential of one pass (thesis §7.3.4–7.3.5, Appendix A):
// points of one surface (columns of a 3×N position matrix) pressed into a
// closed obstacle, each penetrating point held by a spring to its sliding
// anchor on the obstacle's closest feature:
//
//   E(p, q) = Σ_c k_c ‖p_c − a_c(p_c, q)‖²,   k_c = k·s_{p_c},
//
// p the points, q the obstacle's vertices (world), s per-point spring factors
// (e.g. a vertex's area over the mean, so that a uniform depth δ is a uniform
// pressure 2kδ/Ā).
//
// Passes. The potential does not know which surface is which: its outputs are
// on the point side (N columns, the columns of the positions) and on the
// obstacle side (#V columns, the obstacle's own vertex numbering), and the
// caller maps both to its unknowns. palpa runs it forward (a body's skin
// vertices into a rigid or deformable support) and in reverse (a deformable
// support's surface vertices into the body's boundary).
//
// Values. detected_energy() detects afresh (a line-search trial sees its own
// contacts; const, parallel, nothing stored); commit() keeps the contacts of
// an accepted iterate; every other method uses the committed features with
// sliding anchors and is an exact derivative of the committed energy(). At the
// committed point both energies agree; away from it a committed contact acts as
// a two-sided spring to its feature, which is why trials must use
// detected_energy() (contact.hpp).
//
// Derivatives per contact over its stencil z = (p, q_0, …, q_{m−1})
// (penalty.hpp): the point block 2k P⊥ is positive semi-definite; the whole
// stencil's Hessian is the true Hessian, indefinite in general (the obstacle
// gradient and the shape derivative need it).
//
// Sign conventions: E ≥ 0; ∂E/∂p points into the obstacle; the contact force
// on a point, f = −∂E/∂p, pushes it out; the obstacle's vertices feel forces
// summing to −Σ f. Units: [m], k [N/m], E [J], forces [N], Hessians [N/m].

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "palpa/contact/contact.hpp"
#include "palpa/contact/obstacle.hpp"
#include "palpa/contact/penalty.hpp"

namespace palpa::contact {

// One committed contact as a stencil: the point (a column of the positions)
// and the feature's obstacle vertices, the first m of `obstacle_vertex`.
struct Stencil {
  int point = -1;
  int m = 0;
  std::array<int, 3> obstacle_vertex{-1, -1, -1};
};

class PenaltyContact {
 public:
  // candidates: the columns of the positions that can touch (each ≥ 0). k:
  // the stiffness [N/m]. name: used in error messages (the obstacle, say).
  // Throws palpa::Error (Input) naming `name` unless k is finite and > 0.
  PenaltyContact(std::vector<int> candidates, double k, std::string name);

  const std::vector<int>& candidates() const noexcept { return candidates_; }
  double stiffness() const noexcept { return k_; }
  // Throws palpa::Error (Input) naming the pass unless k is finite and > 0.
  void set_stiffness(double k);
  // Per-column spring factors s (one per column of the positions; empty: 1).
  void set_scale(std::vector<double> scale);
  const std::vector<double>& scale() const noexcept { return scale_; }
  // One flag per obstacle vertex: a point whose closest feature has a flagged
  // vertex is no contact (e.g. the body's core shells in the reverse pass).
  // Empty: every feature counts.
  void set_excluded(std::vector<char> excluded_obstacle_vertices);

  // Σ k_c·depth² over the candidates inside the obstacle, detected afresh at
  // `points` [J]. Parallel, deterministic, allocation-free, thread-safe.
  double detected_energy(const Obstacle& obstacle, Points points) const;
  // Detects the candidates inside the obstacle at `points` and keeps them (in
  // candidate order) as the committed contacts.
  void commit(const Obstacle& obstacle, Points points);
  void clear() noexcept { contacts_.clear(); }

  const std::vector<Contact>& contacts() const noexcept { return contacts_; }
  std::size_t size() const noexcept { return contacts_.size(); }
  bool empty() const noexcept { return contacts_.empty(); }
  // Largest depth at commit [m] (0 without contacts).
  double max_depth() const;
  // k_c of a contact [N/m].
  double stiffness_of(const Contact& c) const;
  Stencil stencil_of(const Contact& c) const;

  // With the committed contacts at `points` (any positions, same columns):
  // E [J].
  double energy(const Obstacle& obstacle, Points points) const;
  // grad.col(point) += ∂E/∂p [N]; grad: 3×N.
  void add_gradient(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> grad) const;
  // grad.col(v) += ∂E/∂q_v for every obstacle vertex v [N]; grad: 3×#V.
  void add_obstacle_gradient(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> grad) const;
  // Contact forces −∂E/∂p added to on_points (3×N) and −∂E/∂q to on_obstacle
  // (3×#V, or 0 columns to skip the obstacle side) [N].
  void add_forces(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> on_points,
                  Eigen::Ref<Eigen::Matrix3Xd> on_obstacle) const;
  // The reaction on the obstacle: force −Σ f, torque Σ (a − about) × (−f)
  // about `about` [m]; equal and opposite to the wrench of the f on the points.
  Wrench obstacle_wrench(const Obstacle& obstacle, Points points, const Eigen::Vector3d& about) const;

  // fn(point, ∂²E/∂p²): the point block of every contact, 2k_c P⊥ [N/m],
  // positive semi-definite (a point may come more than once).
  template <class Fn>
  void for_each_point_hessian(const Obstacle& obstacle, Fn&& fn) const {
    for (const Contact& c : contacts_) fn(c.point, penalty_hessian(feature_geometry(obstacle, c.closest), stiffness_of(c)));
  }
  // fn(stencil, H): the true Hessian of every contact over its stencil
  // z = (p, q_0, …, q_{m−1}) [N/m] (rows and columns past 3(m+1) are zero).
  template <class Fn>
  void for_each_stencil_hessian(const Obstacle& obstacle, Points points, Fn&& fn) const {
    for (const Contact& c : contacts_) {
      fn(stencil_of(c), penalty_hessian_full(points.col(c.point), feature_geometry(obstacle, c.closest), stiffness_of(c)));
    }
  }
  // (out_points, out_obstacle) += H (v_points, v_obstacle), H the true Hessian
  // of E over the points (3×N) and the obstacle's vertices (3×#V) [N].
  // v_obstacle and out_obstacle may have 0 columns (a rigid obstacle: only
  // the point side, or only its response, is wanted).
  void add_hessian_product(const Obstacle& obstacle, Points points, Points v_points, Points v_obstacle,
                           Eigen::Ref<Eigen::Matrix3Xd> out_points, Eigen::Ref<Eigen::Matrix3Xd> out_obstacle) const;

 private:
  bool excluded(const ClosestPoint& c) const;

  std::string name_;
  std::vector<int> candidates_;
  double k_ = 0.0;
  std::vector<double> scale_;
  std::vector<char> excluded_;
  std::vector<Contact> contacts_;
  ContactSet detection_;  // scratch of commit()
};

}  // namespace palpa::contact
