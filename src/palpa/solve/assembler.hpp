// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The one assembler of a sum of terms (term.hpp) over a DOF map
// (dof_map.hpp): it builds the Hessian's lower-triangle pattern over x and the
// slot of every stencil entry once, then fills values at every call.
//
// A term's 3×3 block on vertices (a, b) lands at the DOFs of a and b: a free
// vertex's own DOFs (a fixed DOF drops out), or, for a vertex on the rigid
// core, the core's DOFs through the map's Jacobian (P_aᵀ H_ab P_b, block by
// block: never a sparse product). Element stencils are evaluated in parallel
// (TBB), chunk by chunk into a local buffer, and added in stencil order, so
// the same x gives the same bits on every run and any thread count. The PSD
// projection is chosen per call and handed to every term.
//
// The pattern holds: every pair of DOFs of a stencil, of a named vertex pair,
// each vertex's own block, the core's whole block, and the diagonal. It never
// changes; entries that are zero at some x stay as explicit zeros.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "palpa/solve/dof_map.hpp"
#include "palpa/solve/term.hpp"

namespace palpa {

class Assembler {
 public:
  // map and terms must outlive the assembler; a term's stencils and vertex
  // pairs must not change after it is built.
  Assembler(const DofMap& map, std::vector<const Term*> terms);

  // Takes one more term whose Hessian has no element stencils and whose
  // vertex pairs are in the pattern already (contact on a tet body's skin):
  // only its pairs' slots are added. Returns false, and changes nothing,
  // where the pattern would have to grow: build a new assembler then.
  bool extend(const Term* term);

  // The lower-triangle pattern over x (num_dofs × num_dofs).
  const Eigen::SparseMatrix<double>& pattern() const noexcept { return pattern_; }

  // H = Σ terms' Hessians at the state s (positions of x), mapped through
  // the map's Jacobian at x; H takes pattern() if it has another one, else
  // only its values change. Throws palpa::Error (Internal) where a stencil is
  // not admissible (an inverted element).
  void assemble(const Eigen::VectorXd& x, const VertexState& s, PsdProjection projection,
                Eigen::SparseMatrix<double>& H) const;

  // H += scale · Σ_v m_v P_vᵀ P_v (a lumped mass m, N entries [kg], through
  // the map at x), H += scale · diag(d) (d over x), and H += c over the core's
  // rotation DOFs (c: 3×3 over ω_x, ω_y, ω_z; entries of locked ones dropped).
  void add_vertex_mass(const Eigen::VectorXd& x, const Eigen::VectorXd& m, double scale,
                       Eigen::SparseMatrix<double>& H) const;
  void add_diagonal(const Eigen::VectorXd& d, double scale, Eigen::SparseMatrix<double>& H) const;
  void add_rotation_block(const Eigen::Matrix3d& c, Eigen::SparseMatrix<double>& H) const;

 private:
  // The DOFs a vertex's block lands on: its own three (−1 if fixed), or the
  // core's (attached).
  int local_dofs(int v, int* out) const;
  // The core's Jacobian of every attached vertex at x (by attached_index_).
  using CoreJacobian = Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::ColMajor, 3, 6>;
  std::vector<CoreJacobian> core_jacobians(const Eigen::VectorXd& x) const;
  // Adds block K (3×3, rows vertex a) at slots `slots` into values.
  void scatter(const std::vector<CoreJacobian>& jacobians, int a, int b, const Eigen::Matrix3d& K, const int* slots,
               double* values) const;

  struct Stencils {
    const Term* term = nullptr;
    int size = 0;                        // vertices per stencil
    std::vector<std::int64_t> offset;    // per stencil, into slots_
    std::vector<char> on_core;           // per stencil: a vertex is attached
  };

  const DofMap* map_;
  std::vector<int> attached_index_;  // per vertex: its place in the core's attached list, or −1
  std::vector<const Term*> terms_;
  std::vector<Stencils> stencils_;
  std::vector<int> slots_;
  std::vector<std::int64_t> vertex_offset_;                  // (v, v) blocks
  std::unordered_map<std::uint64_t, std::int64_t> pair_offset_;  // ordered (a, b), a ≠ b
  std::vector<int> diagonal_slots_;                          // per DOF of x
  std::vector<int> core_slots_;                              // nc × nc, column-major, −1 above
  Eigen::SparseMatrix<double> pattern_;
};

}  // namespace palpa
