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

// Calls solve(), then adjust(solves, last) until adjust returns None or
// max_solves solves have run. `last` is true on the solve that reaches the
// cap: adjust must then change nothing (the last solve always stands with the
// parameters it ran with) and return only what it would have changed.
// Exceptions from either propagate.
EquilibriumLoopResult run_equilibrium_loop(int max_solves, const std::function<void()>& solve,
                                           const std::function<Resolve(int solves, bool last)>& adjust);

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
