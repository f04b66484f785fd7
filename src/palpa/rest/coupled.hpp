// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A body on its rigid core resting on a deformable support (thesis §7.4.3):
// the two bodies and their penalty contact as one System, so that Newton and
// the adjoint see one equilibrium.
//
// Unknowns. y = (x, v): x the body's CoreSystem DOFs (its free vertex
// displacements and core pose), v the free displacement DOFs of the support's
// tet mesh (its base is fixed). Energy:
//   E(y) = E_body(x) + E_support(v) + E_contact(positions of the body's skin,
//                                              deformed support surface).
// The forward pass is the body's contact term (body::ContactTerm, not among
// the CoreSystem's terms: this system evaluates it), whose obstacle is the
// support's boundary surface. Every const call evaluates both passes against
// copies of the two surfaces moved to y (contact::Obstacle::deformed), so
// calls may run concurrently; prepare() moves the surfaces themselves and
// commits both passes there.
//
// Two passes. The body's skin presses on the support's triangles, and — for
// a deformable support — the support's surface presses on the body's skin
// triangles as well, sampled alike (surface points with their area shares;
// or vertices with springs k·A_j/Ā, A_j the support vertex's area when the
// system is built, Ā the body's mean skin vertex area), so that the same
// depth means the same pressure on both sides. A soft support otherwise
// bulges up between the body's samples, through its skin.
// Contacts whose closest body feature touches the core are left out (a
// support vertex that deep is a failed simulation, not a contact).
//
// Derivatives. With the committed contacts and sliding anchors, the contact
// energy of one contact is a function of its stencil, a point and its
// feature's vertices (contact/penalty_contact.hpp), each a vertex of the body
// or of the support. The forward pass's point blocks are in the body's Hessian
// already; every other block goes to the body's, the support's or the
// coupling, by the sides of its two vertices (contact never touches a
// core-attached vertex, so the core's rotational curvature does not see it).
// The Hessian is
//   [ K_body            ]
//   [ C        K_support]   (lower triangle),
// whose coupling pattern C holds every (support vertex, body vertex) pair that
// has been in contact at a prepare() so far: it only grows, so the sparse
// factorization is analysed again only when a new pair touches.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "palpa/body/core_system.hpp"
#include "palpa/body/contact_term.hpp"
#include "palpa/contact/obstacle.hpp"
#include "palpa/contact/penalty_contact.hpp"
#include "palpa/solve/system.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::rest {

class CoupledSystem final : public System {
 public:
  // body: the body (`term` not among its terms); support: the support's
  // static system (base fixed, nothing else attached); obstacle: the support's
  // boundary surface, whose vertex j is vertex surface[j] of the support's tet
  // mesh, and the obstacle of `term`. All must outlive this system. The
  // reverse pass takes the term's stiffness; set_stiffness() changes both.
  // The reverse pass samples the support's surface as the term samples the
  // skin (its vertices, or `subdivisions`² points per triangle).
  CoupledSystem(body::CoreSystem& body, tet::StaticSystem& support, contact::Obstacle& obstacle,
                std::vector<int> surface, body::ContactTerm& term, int subdivisions = 2);

  // k of each pass [N/m] (the forward term's and the reverse pass's).
  void set_stiffness(double k);
  // The forward term (the body's skin on the support's surface).
  const body::ContactTerm& forward_term() const noexcept { return *term_; }

  Eigen::Index num_body_dofs() const noexcept { return body_->num_dofs(); }
  Eigen::Index num_support_dofs() const noexcept { return support_->num_dofs(); }
  const std::vector<int>& surface() const noexcept { return surface_; }

  // The support's deformed boundary at y (#surface × 3) [m], and the obstacle
  // (and the body's surface) moved there.
  Eigen::MatrixX3d surface_positions(const Eigen::VectorXd& y) const;
  void place_obstacle(const Eigen::VectorXd& y);
  // The reverse pass (the support's surface in the body's skin) with the
  // contacts committed at the last prepare().
  const contact::PenaltyContact& reverse_contacts() const noexcept { return reverse_; }
  // The nodal contact forces of both passes at y (committed features) on the
  // body's vertices (3×N) and the support's surface vertices (3×#surface)
  // [N]: the pressure a vertex feels is its force over its area.
  void contact_forces(const Eigen::VectorXd& y, Eigen::Matrix3Xd& body, Eigen::Matrix3Xd& support) const;
  // The area in contact at y [m²] on the body's vertices (N) and the
  // support's surface vertices: each pass's samples in contact
  // (contact::PenaltyContact::add_contact_areas) on both sides, halved (the
  // two passes measure one patch).
  void contact_areas(const Eigen::VectorXd& y, Eigen::VectorXd& body, Eigen::VectorXd& support) const;
  // H_c v for the contact energy's Hessian H_c over the vertex positions of
  // both bodies (both passes, committed features): v and the result over
  // the body's vertices (3×N) and the support's surface vertices.
  void contact_hessian_product(const Eigen::VectorXd& y, const Eigen::Matrix3Xd& v_body,
                               const Eigen::Matrix3Xd& v_support, Eigen::Matrix3Xd& body,
                               Eigen::Matrix3Xd& support) const;
  // The free support DOFs (v) of a vector over the support surface
  // (#surface × 3): its rows scattered to their tet vertices, fixed DOFs
  // dropped.
  Eigen::VectorXd support_free_part(const Eigen::MatrixX3d& per_surface_vertex) const;

  // System
  Eigen::Index num_dofs() const override { return num_body_dofs() + num_support_dofs(); }
  double energy(const Eigen::VectorXd& y) const override;
  void gradient(const Eigen::VectorXd& y, Eigen::VectorXd& g) const override;
  double energy_gradient(const Eigen::VectorXd& y, Eigen::VectorXd& g) const override;
  void hessian(const Eigen::VectorXd& y, Eigen::SparseMatrix<double>& H) const override;
  void prepare(const Eigen::VectorXd& y) override;

 private:
  double evaluate(const Eigen::VectorXd& y, Eigen::VectorXd* g) const;
  // Copies of the support's surface and of the body's at y.
  struct Surfaces {
    contact::Obstacle support;
    contact::Obstacle body;
  };
  Surfaces surfaces_at(const Eigen::VectorXd& y) const;
  // Calls f(stencil, K, forward) for every committed contact stencil of both
  // passes at y (the surfaces there given), with its Hessian K.
  template <class F>
  void for_each_contact_stencil(const Eigen::VectorXd& y, const contact::Obstacle& support,
                                const contact::Obstacle& body, F&& f) const;
  // The support surface vertex and body vertex of each coupling block of a
  // stencil (support rows, body columns).
  void add_pairs(const contact::Stencil& st, bool forward);
  // The support's deformed surface (3×#surface) and the body's deformed
  // boundary (3×#boundary, its vertex i is body vertex body_vertex_[i]) at y.
  Eigen::Matrix3Xd support_points(const Eigen::VectorXd& y) const;
  Eigen::Matrix3Xd boundary_points(const Eigen::VectorXd& p) const;
  // The columns of a body-vertex field (3×N) at the boundary's vertices, and
  // a boundary field added back to them.
  Eigen::Matrix3Xd gather_boundary(const Eigen::Matrix3Xd& body) const;
  void scatter_boundary(const Eigen::Matrix3Xd& boundary, Eigen::Matrix3Xd& body) const;
  // The support DOF of vertex `v`, component c, or −1 if fixed.
  int support_dof(int v, int c) const { return full_to_free_[static_cast<std::size_t>(3 * v + c)]; }

  body::CoreSystem* body_;
  tet::StaticSystem* support_;
  contact::Obstacle* obstacle_;
  std::vector<int> surface_;
  body::ContactTerm* term_;
  // The body's whole boundary as an obstacle (its vertex i is body vertex
  // body_vertex_[i]), moved with the body, and the reverse pass against it
  // (features on the core's shells excluded).
  std::unique_ptr<contact::Obstacle> body_surface_;
  std::vector<int> body_vertex_;
  contact::PenaltyContact reverse_;
  std::vector<int> full_to_free_;         // support full DOF -> free index or −1
  std::vector<int> body_full_to_free_;    // body full DOF -> CoreSystem DOF or −1
  std::set<std::pair<int, int>> pairs_;  // (support surface vertex, body vertex) ever in contact
};

}  // namespace palpa::rest
