// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The outer loop around Newton that every contact driver runs (rest, sim3d):
// solve the equilibrium, then let the model decide whether its own parameters
// (the penalty stiffness, the contact spring areas) must change and the
// equilibrium be solved again, up to a cap. And the tolerance model that turns
// a problem's force scale into Newton's tolerances.

#include <functional>
#include <string_view>

#include "palpa/solve/newton.hpp"

namespace palpa {

// What a model changed after an equilibrium, so that it must be solved again.
enum class Resolve {
  None,       // nothing: the equilibrium stands
  Areas,      // contact spring areas followed the contact set
  Stiffness,  // the penalty stiffness was corrected toward the target depth
  Anchors,    // contacts that stick were anchored where they met the obstacle
};
std::string_view to_string(Resolve r) noexcept;

struct EquilibriumLoopResult {
  int solves = 0;
  // Why the last solve would have been followed by another: None when the
  // loop ended because the model was satisfied; otherwise the cap was reached.
  Resolve pending = Resolve::None;
  bool capped() const noexcept { return pending != Resolve::None; }
};

// How far a solve of the loop converges. A pass that the model may still
// follow with a change only has to show what to change (the deepest
// penetration, the contact set, where contacts stick): it stops at the
// gradient Newton accepts where rounding stops it
// (NewtonOptions::gradient_accept_tol). The solve that ends the loop
// converges to gradient_abs_tol.
enum class Pass { Rough, Final };

// Calls solve(pass), then adjust(solves, last), until adjust returns None
// after a Final pass or max_solves solves have run. Passes are Rough until
// adjust first returns None; then the same equilibrium is solved again,
// Final, and adjust asked again (a change it then asks for starts Rough
// passes anew). The solve that reaches the cap is Final, and `last` is true
// for it: adjust must then change nothing (the last solve always stands with
// the parameters it ran with) and return only what it would have changed.
// Exceptions from either propagate.
EquilibriumLoopResult run_equilibrium_loop(int max_solves, const std::function<void(Pass)>& solve,
                                           const std::function<Resolve(int solves, bool last)>& adjust);

// newton.solve(system, x) to the pass's tolerance (the solver's own options
// are those of a Final pass, and are kept).
NewtonResult solve_pass(NewtonSolver& newton, System& system, Eigen::VectorXd& x, Pass pass);

// Newton's tolerances from a force scale [N] (the largest out-of-balance force
// component that does not matter): converged at ‖g‖∞ ≤ tolerance; where
// rounding stops progress first, accepted at ‖g‖∞ ≤ accept_factor·tolerance
// (NewtonOptions::gradient_accept_tol). No relative criterion: a warm start
// asks for the same forces as a cold one.
struct ToleranceModel {
  double tolerance = 0.0;  // [N]
  double accept_factor = 100.0;

  // Writes the tolerances into `options` (gradient_abs_tol,
  // gradient_accept_tol, gradient_rel_tol = 0).
  void apply(NewtonOptions& options) const noexcept;
};

}  // namespace palpa
