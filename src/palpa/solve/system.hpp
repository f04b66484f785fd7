// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The interface every simulated system implements so that Newton, the line
// searches and the sensitivity code can be written once: a total energy E(x)
// over the system's free degrees of freedom x ∈ Rⁿ, its gradient and its sparse
// Hessian. Everything is SI: x in metres (or radians for rotational DOFs),
// E in joules, g = ∂E/∂x in newtons (g = −force: external loads enter E as
// −f·x), H = ∂²E/∂x² in N/m.
//
// State and threads.
//  * energy(), gradient(), energy_gradient() and hessian() are functions of x
//    and of the system's *committed state* (e.g. the contact anchors of the
//    current Newton iterate). They are const and must be safe to call
//    concurrently on one object: keep per-evaluation scratch in locals, not in
//    members, so that line-search trials may run in parallel.
//  * prepare(x) is the only call that may change committed state. The solver
//    calls it once at the starting point and once at every accepted iterate,
//    before it evaluates the gradient and Hessian there; never at line-search
//    trials. A contact system redoes collision detection here and keeps the
//    contact set (and sliding anchors) that its Hessian and gradient use at x.
//  * A line-search trial only calls energy(x). For contact systems, energy(x)
//    must therefore do its own collision detection at the trial point (the
//    thesis, §7.3.4: "for each η, we perform collision detection again"): the
//    energy of a trial point may depend on a detection done inside energy(x)
//    itself, into local scratch. Nothing is cached from trials.
//  * gradient(x) and hessian(x) must be correct at any x for the committed
//    state (finite-difference tests call them without prepare()); prepare() may
//    only make them faster at the prepared point.
//
// Invalid points. energy(x) returns +infinity (NaN is treated the same) where x
// is not admissible, e.g. an inverted element; the line search then shrinks the
// step. gradient() and hessian() are only called at points of finite energy.
//
// Regularization. A system that needs a fixed regularization of its Hessian
// (the thesis's K + αM while the body touches nothing, §7.3.4) adds it itself
// inside hessian(): only the system knows when it applies. The solver adds its
// own diagonal shift only when the factorization reports the Hessian is not
// positive definite (see newton.hpp).

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace palpa {

class System {
 public:
  virtual ~System();

  // n: the number of free degrees of freedom (the length of x).
  virtual Eigen::Index num_dofs() const = 0;

  // E(x) [J]. x: n. Returns +infinity where x is not admissible.
  virtual double energy(const Eigen::VectorXd& x) const = 0;

  // g = ∂E/∂x at x [N] (minus the net force on each DOF). x: n; g: resized to n.
  virtual void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const = 0;

  // E(x) and g(x) together (returns E). Override when both share work (they
  // usually do: kinematics, collision detection); the default calls both.
  virtual double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const;

  // H = ∂²E/∂x² at x [N/m], n×n, LOWER TRIANGLE ONLY (entries with row ≥ col,
  // diagonal included; the solvers never read the upper triangle).
  //
  // The sparsity pattern is fixed per topology: the system builds it once (when
  // H is empty, or is not a pattern this system built) and afterwards only
  // overwrites the values of H, keeping its index arrays. The caller keeps H
  // between calls and does not touch its structure. When the system's topology
  // changes (new coupling terms), it rebuilds the pattern; the factorization
  // notices by comparing index arrays and analyses again. Entries that are zero
  // at some x stay in the pattern as explicit zeros.
  //
  // A system may project element Hessians to positive semi-definite for Newton
  // (see the PSD projection notes in the style guide); sensitivity code needs
  // the true Hessian, so such a system should let the caller switch that off.
  virtual void hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const = 0;

  // A positive semi-definite stand-in for H at x, in the pattern hessian()
  // builds (e.g. the sum of each element's Hessian projected to PSD). Newton
  // steps with it where H itself is not positive definite, before it shifts H
  // (see newton.hpp): far from a minimizer it is a far better model of the
  // energy than H + σD with a large σ. Returns false when the system has none
  // (the default); H is then untouched.
  virtual bool projected_hessian(const Eigen::VectorXd& x, Eigen::SparseMatrix<double>& H) const;

  // Commits state at x: called by the solver at the start and at each accepted
  // iterate, before gradient/Hessian there (see above). Default: nothing.
  virtual void prepare(const Eigen::VectorXd& x);

  // True when E, g and H depend on x alone: prepare() commits nothing that
  // changes them. The solver may then keep the energy and gradient it
  // evaluated at a trial point as those of the iterate it accepts there,
  // instead of evaluating them again after prepare(). Default: false.
  virtual bool stateless() const noexcept { return false; }

 protected:
  System() = default;
  System(const System&) = default;
  System& operator=(const System&) = default;
};

// The index into pattern.valuePtr() of entry (row, col) of a compressed,
// lower-triangular pattern (row and col are swapped when row < col), or −1
// if the pattern has no such entry. Systems use it once per topology to map
// element matrix entries to their slots.
int lower_slot(const Eigen::SparseMatrix<double>& pattern, int row, int col);

}  // namespace palpa
