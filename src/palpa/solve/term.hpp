// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// One energy of a body's vertices, the unit a TermSystem (term_system.hpp)
// sums: the elastic energy of its tets, gravity, external loads, penalty
// contact with an obstacle.
//
// A term sees the vertices only: the nodal displacement u and the deformed
// positions p = X + u of every vertex (3N each, vertex-major), never the free
// DOFs of the system it is in. Which DOFs are free, held or carried by a rigid
// core is the DofMap's business (dof_map.hpp), and the Assembler
// (assembler.hpp) maps the term's Hessian blocks through it.
//
// Hessians come in one of two shapes, both on fixed stencils so that the
// sparsity pattern is built once:
//  * element stencils: num_stencils() lists of at most stencil_size()
//    vertices each (a tet's four corners, a vertex's patch of tets), each
//    with a dense (3K)×(3K) Hessian that the assembler evaluates in parallel
//    and adds in stencil order;
//  * vertex-pair blocks: 3×3 blocks on single vertices and on the pairs the
//    term names up front (vertex_pairs(): the corners of a skin triangle whose
//    traction is integrated over it), for terms whose active stencils change
//    from call to call (contact).
//
// State. energy(), add_gradient() and the Hessians are const functions of the
// state passed in and of the term's committed state, safe to call from several
// threads at once; prepare() is the only call that commits state (contact
// detection at an accepted iterate), see solve/system.hpp.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "palpa/core/psd_projection.hpp"

namespace palpa {

// The vertices' state: displacement u and deformed positions p = X + u
// (3N each, vertex-major) [m].
struct VertexState {
  const Eigen::VectorXd& u;
  const Eigen::VectorXd& p;
};

// ∂²E/∂p_row∂p_col [N/m], one 3×3 block of a term's Hessian.
struct VertexBlock {
  int row = -1;
  int col = -1;
  Eigen::Matrix3d block = Eigen::Matrix3d::Zero();
};

class Term {
 public:
  virtual ~Term();

  // E at the state [J]; +infinity where it is not admissible.
  virtual double energy(const VertexState& s) const = 0;
  // E, and adds ∂E/∂p into g (3N) [N] (g untouched past a +infinity).
  virtual double add_gradient(const VertexState& s, Eigen::VectorXd& g) const = 0;

  // Element stencils: at most stencil_size() vertices per stencil (0: none);
  // stencil(i, vertices) writes the K vertices of stencil i and returns K,
  // and stencil_hessian its Hessian (3K × 3K, column-major, rows 3a + c for
  // vertex a, component c) into h; it returns false where the state is not
  // admissible there.
  virtual int stencil_size() const noexcept { return 0; }
  virtual Eigen::Index num_stencils() const noexcept { return 0; }
  virtual int stencil(Eigen::Index i, int* vertices) const;
  virtual bool stencil_hessian(const VertexState& s, Eigen::Index i, PsdProjection projection, double* h) const;

  // Vertex-pair blocks: the pairs of distinct vertices whose blocks
  // add_blocks() may add (each once, in either order), and the blocks at the
  // state: (v, v) blocks and (a, b) blocks of named pairs in both orders.
  virtual std::vector<std::array<int, 2>> vertex_pairs() const;
  virtual void add_blocks(const VertexState& s, PsdProjection projection, std::vector<VertexBlock>& blocks) const;

  // Commits the state at an accepted iterate. Default: nothing.
  virtual void prepare(const VertexState& s);
  // Whether the committed state touches anything (a contact): the system's
  // K + αM regularization applies only while no term is active.
  virtual bool active() const;

 protected:
  Term() = default;
  Term(const Term&) = default;
  Term& operator=(const Term&) = default;
};

// E = c·u: a constant load on the vertices (gravity's potential −Σ m g·u, or
// −f·u for external nodal forces f). c: 3N [N].
class LinearTerm final : public Term {
 public:
  explicit LinearTerm(Eigen::VectorXd c) : c_(std::move(c)) {}
  const Eigen::VectorXd& coefficients() const noexcept { return c_; }
  void set_coefficients(Eigen::VectorXd c) { c_ = std::move(c); }
  double energy(const VertexState& s) const override { return c_.dot(s.u); }
  double add_gradient(const VertexState& s, Eigen::VectorXd& g) const override {
    g += c_;
    return c_.dot(s.u);
  }

 private:
  Eigen::VectorXd c_;
};

}  // namespace palpa
