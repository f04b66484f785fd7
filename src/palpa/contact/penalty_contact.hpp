// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The penalty-contact potential of one pass (thesis §7.3.4–7.3.5, Appendix A):
// sample points of one surface pressed into a closed obstacle, each
// penetrating sample held by a spring to its sliding anchor on the obstacle's
// closest feature:
//
//   E(x, q) = Σ_s k·c_s ‖x_s − a_s(x_s, q)‖²,   x_s = Σ_i N_si x_{v_si},
//
// x the surface's vertices (columns of a 3×N position matrix), q the
// obstacle's vertices (world), and each sample a fixed point of the surface:
// a vertex (node-to-surface, N = 1), or a quadrature point of a triangle
// (surface contact: tractions integrated over the surface, so that the nodal
// forces are the consistent loads of the pressure field and balance the
// obstacle's exactly). c_s is the sample's spring factor: 1 (k [N/m]) or its
// share of the surface's area, ½·w_q·A_t (k [Pa/m] the pressure per depth:
// a sample at depth δ presses with p = k·δ).
//
// Passes. The potential does not know which surface is which: its outputs are
// on the surface side (N columns) and on the obstacle side (the obstacle's #V
// vertices, its own numbering), and the caller maps both to its unknowns.
// palpa runs it forward (a body's skin into a rigid or deformable support) and
// in reverse (a deformable support's surface into the body's boundary).
//
// Values. detected_energy() detects afresh (a line-search trial sees its own
// contacts; const, parallel, nothing stored); commit() keeps the contacts of
// an accepted iterate; every other method uses the committed features with
// sliding anchors and is an exact derivative of the committed energy(). At the
// committed point both energies agree; away from it a committed contact acts as
// a two-sided spring to its feature, which is why trials must use
// detected_energy() (contact.hpp).
//
// Derivatives. Per contact, the kernel's 12×12 Hessian over (x_s, q_0, q_1,
// q_2) (penalty.hpp) maps to the stencil's vertices through x_s = Σ N_i x_i:
// block (a, b) of two surface vertices is N_a N_b H_xx, and so on
// (Stencil::block). The surface blocks N_a N_b 2k P⊥ form a positive
// semi-definite matrix; the whole stencil's Hessian is the true Hessian,
// indefinite in general (the obstacle gradient and the shape derivative need
// it).
//
// Sign conventions: E ≥ 0; ∂E/∂x_s points into the obstacle; the contact force
// on a sample, f = −∂E/∂x_s, pushes it out and reaches the surface's vertices
// as N_i f; the obstacle's vertices feel forces summing to −Σ f. Units: [m],
// k·c_s [N/m], E [J], forces [N], Hessians [N/m].

#include <Eigen/Core>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "palpa/contact/contact.hpp"
#include "palpa/contact/obstacle.hpp"
#include "palpa/contact/penalty.hpp"

namespace palpa::contact {

// Where a pass's springs sit on its surface: sample s is the point
// x_s = Σ_i weights[s][i]·x(vertices[s][i]) over its first count(s) vertices
// (columns of the positions; the rest −1), with spring factor scale[s],
// standing for area[s] of the surface at rest (what the contact area and the
// pressure's footprint are measured with: rest/measurements.hpp).
struct ContactSamples {
  std::vector<std::array<int, 3>> vertices;
  std::vector<Eigen::Vector3d> weights;  // N_s, Σ = 1
  std::vector<double> scale;             // c_s > 0
  std::vector<double> area;              // [m²]; 0 where not known
  std::size_t size() const noexcept { return vertices.size(); }
  int count(std::size_t s) const noexcept { return vertices[s][2] >= 0 ? 3 : vertices[s][1] >= 0 ? 2 : 1; }
};

// One sample per vertex listed (columns of the positions), c_s = 1, standing
// for vertex_area[v] (one per column; empty: areas not known, 0).
ContactSamples vertex_samples(std::span<const int> vertices, const Eigen::VectorXd& vertex_area = {});

// Points of a reference triangle with weights summing to 1.
struct TriangleRule {
  std::vector<Eigen::Vector3d> barycentric;
  std::vector<double> weight;
};
// n² points, one at the centroid of each of the n×n sub-triangles of the
// uniform subdivision, equal weights 1/n² (n ≥ 1). Exact for linear
// integrands, so a vertex's share Σ_t Σ_q N_i w_q A_t is its lumped area; and
// robust where the contact's edge cuts a triangle, where higher-order Gauss
// rules gain nothing on an integrand with a kink.
TriangleRule subdivision_rule(int n);
// The rule's points on every triangle (rows of `faces`, columns of the
// positions), c_s = ½·w_q·A_t with A_t the triangle's area in `rest`
// (#V×3 [m]): k is then the pressure per depth [Pa/m]; each stands for
// w_q·A_t. Samples come face by
// face, in rule order. Throws palpa::Error (Input) for a degenerate triangle.
ContactSamples surface_samples(const Eigen::MatrixX3d& rest, const Eigen::MatrixX3i& faces,
                               const TriangleRule& rule);

// One committed contact: a penetrating sample and the feature it is anchored to.
struct SampleContact {
  int sample = -1;
  ClosestPoint closest;  // at detection: anchor, depth (= distance), feature
  // Stuck (Friction::Stick): closest.feature is the face holding the anchor,
  // closest.vertices its corners and closest.weights the anchor's fixed
  // weights on them; distance stays the depth.
  bool stuck = false;
};

// How a contact holds the surface tangentially: not at all (the sliding
// anchor), or fully ("stick": static friction without a limit, a bonded
// punch face) once the sample has been anchored (PenaltyContact::anchor).
enum class Friction { Frictionless, Stick };

// One committed contact as a stencil: its slots are the sample's n surface
// vertices, then the feature's m obstacle vertices.
struct Stencil {
  int sample = -1;
  int n = 1;
  std::array<int, 3> surface_vertex{-1, -1, -1};
  Eigen::Vector3d weight = Eigen::Vector3d::Zero();  // N of the surface slots
  int m = 0;
  std::array<int, 3> obstacle_vertex{-1, -1, -1};
  int slots() const noexcept { return n + m; }
  bool on_surface(int slot) const noexcept { return slot < n; }
  int vertex(int slot) const noexcept {
    return slot < n ? surface_vertex[static_cast<std::size_t>(slot)] : obstacle_vertex[static_cast<std::size_t>(slot - n)];
  }
  // The 3×3 block (slot a, slot b) of the stencil's Hessian, from the
  // kernel's H over (x_s, q_0, q_1, q_2).
  Eigen::Matrix3d block(const Matrix12d& H, int a, int b) const;
};

class PenaltyContact {
 public:
  // samples: where the springs sit; k: the stiffness ([N/m] with c_s = 1,
  // [Pa/m] with area shares). name: used in error messages (the obstacle,
  // say). Throws palpa::Error (Input) naming `name` unless k is finite and
  // > 0.
  PenaltyContact(ContactSamples samples, double k, std::string name);

  const ContactSamples& samples() const noexcept { return samples_; }
  double stiffness() const noexcept { return k_; }
  // Throws palpa::Error (Input) naming the pass unless k is finite and > 0.
  void set_stiffness(double k);
  // Replaces the samples' spring factors (one per sample, each > 0).
  void set_scale(std::vector<double> scale);
  // One flag per obstacle vertex: a sample whose closest feature has a
  // flagged vertex is no contact (e.g. the body's core shells in the reverse
  // pass). Empty: every feature counts.
  void set_excluded(std::vector<char> excluded_obstacle_vertices);

  // Stick: a sample inside the obstacle that has an anchor is held by a
  // spring to that point, carried by the obstacle's face (penalty.hpp); a
  // sample found outside at commit() loses its anchor. Frictionless (the
  // default) never anchors.
  void set_friction(Friction friction);
  Friction friction() const noexcept { return friction_; }
  // Gives every committed contact without an anchor the point where it met
  // the obstacle: the obstacle point closest to the sample's position in
  // `reference` (the last converged state) with the obstacle at
  // `reference_pose` (its pose then), carried to its pose now. Then recommits
  // at `points`. Returns the number of new anchors (0 when frictionless).
  int anchor(const Obstacle& obstacle, Points points, Points reference, const Pose& reference_pose);
  // The anchors as (sample, face, w0, w1, w2) rows, for saving a state; and
  // back (Stick only; throws palpa::Error (Input) for a row out of range).
  std::vector<std::array<double, 5>> anchors() const;
  void set_anchors(const std::vector<std::array<double, 5>>& rows, const Obstacle& obstacle);

  // Σ k·c_s·depth² over the samples inside the obstacle, detected afresh at
  // `points` (k·c_s·‖x_s − a_s‖² for an anchored one) [J]. Parallel, deterministic, allocation-free, thread-safe.
  double detected_energy(const Obstacle& obstacle, Points points) const;
  // Detects the samples inside the obstacle at `points` and keeps them (in
  // sample order) as the committed contacts. Parallel.
  void commit(const Obstacle& obstacle, Points points);
  void clear() noexcept { contacts_.clear(); }

  const std::vector<SampleContact>& contacts() const noexcept { return contacts_; }
  std::size_t size() const noexcept { return contacts_.size(); }
  bool empty() const noexcept { return contacts_.empty(); }
  // Largest depth at commit [m] (0 without contacts).
  double max_depth() const;
  // The contact of that depth (the first in sample order), or nullptr.
  const SampleContact* deepest() const noexcept;
  // k·c_s of a contact [N/m].
  double stiffness_of(const SampleContact& c) const { return k_ * samples_.scale[static_cast<std::size_t>(c.sample)]; }
  Stencil stencil_of(const SampleContact& c) const;
  // The kernel's feature (stuck or sliding) of a contact, in world coordinates.
  FeatureGeometry geometry_of(const Obstacle& obstacle, const SampleContact& c) const;
  // The sample's position at `points` [m].
  Eigen::Vector3d position(int sample, Points points) const;

  // With the committed contacts at `points` (any positions, same columns):
  // E [J].
  double energy(const Obstacle& obstacle, Points points) const;
  // grad.col(v) += ∂E/∂x_v [N]; grad: 3×N.
  void add_gradient(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> grad) const;
  // grad.col(v) += ∂E/∂q_v for every obstacle vertex v [N]; grad: 3×#V.
  void add_obstacle_gradient(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> grad) const;
  // Contact forces −∂E/∂x added to on_points (3×N) and −∂E/∂q to on_obstacle
  // (3×#V, or 0 columns to skip the obstacle side) [N].
  void add_forces(const Obstacle& obstacle, Points points, Eigen::Ref<Eigen::Matrix3Xd> on_points,
                  Eigen::Ref<Eigen::Matrix3Xd> on_obstacle) const;
  // The area in contact [m²]: each committed contact's sample area
  // (ContactSamples::area; a triangle sample's stretched as its triangle from
  // `rest` to `points`, same columns), added to on_points (N) by the
  // sample's weights and to on_obstacle (#V, or empty to skip) by its
  // feature's weights at detection.
  void add_contact_areas(Points rest, Points points, Eigen::Ref<Eigen::VectorXd> on_points,
                         Eigen::Ref<Eigen::VectorXd> on_obstacle) const;
  // The reaction on the obstacle: force −Σ f, torque Σ (a − about) × (−f)
  // about `about` [m]; equal and opposite to the wrench of the f on the samples.
  Wrench obstacle_wrench(const Obstacle& obstacle, Points points, const Eigen::Vector3d& about) const;

  // fn(v_a, v_b, ∂²E/∂x_a∂x_b) for every ordered pair of surface vertices of
  // every contact's sample (both orders, and a = b), N_a N_b 2k c_s P⊥
  // [N/m]: together positive semi-definite. A pair may come more than once.
  template <class Fn>
  void for_each_surface_hessian(const Obstacle& obstacle, Fn&& fn) const {
    for (const SampleContact& c : contacts_) {
      const Stencil st = stencil_of(c);
      const Eigen::Matrix3d P = penalty_hessian(geometry_of(obstacle, c), stiffness_of(c));
      for (int a = 0; a < st.n; ++a) {
        for (int b = 0; b < st.n; ++b) fn(st.surface_vertex[static_cast<std::size_t>(a)], st.surface_vertex[static_cast<std::size_t>(b)], Eigen::Matrix3d(st.weight[a] * st.weight[b] * P));
      }
    }
  }
  // fn(stencil, H): every contact's stencil and the kernel's true Hessian over
  // (x_s, q_0, …, q_{m−1}) [N/m] (rows and columns past 3(m+1) are zero);
  // Stencil::block maps it to the stencil's vertices.
  template <class Fn>
  void for_each_stencil_hessian(const Obstacle& obstacle, Points points, Fn&& fn) const {
    for (const SampleContact& c : contacts_) {
      fn(stencil_of(c), penalty_hessian_full(position(c.sample, points), geometry_of(obstacle, c),
                                             stiffness_of(c)));
    }
  }
  // (out_points, out_obstacle) += H (v_points, v_obstacle), H the true Hessian
  // of E over the surface's vertices (3×N) and the obstacle's (3×#V) [N].
  // v_obstacle and out_obstacle may have 0 columns (a rigid obstacle: only
  // the surface side, or only the obstacle's response, is wanted).
  void add_hessian_product(const Obstacle& obstacle, Points points, Points v_points, Points v_obstacle,
                           Eigen::Ref<Eigen::Matrix3Xd> out_points, Eigen::Ref<Eigen::Matrix3Xd> out_obstacle) const;

 private:
  bool excluded(const ClosestPoint& c) const;

  std::string name_;
  ContactSamples samples_;
  double k_ = 0.0;
  std::vector<char> excluded_;
  Friction friction_ = Friction::Frictionless;
  // Per sample under Stick: the anchor's face (−1: none) and weights.
  std::vector<int> anchor_face_;
  std::vector<Eigen::Vector3d> anchor_weights_;
  std::vector<SampleContact> contacts_;
  std::vector<ClosestPoint> slot_;  // scratch of commit(): one per sample
  std::vector<unsigned char> hit_;  // scratch of commit(): inside or not
};

}  // namespace palpa::contact
