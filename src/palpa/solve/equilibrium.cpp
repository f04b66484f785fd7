// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/equilibrium.hpp"

#include <cassert>

namespace palpa {

std::string_view to_string(Resolve r) noexcept {
  switch (r) {
    case Resolve::None: return "none";
    case Resolve::Areas: return "spring areas";
    case Resolve::Stiffness: return "stiffness";
    case Resolve::Anchors: return "stick anchors";
  }
  return "unknown";
}

EquilibriumLoopResult run_equilibrium_loop(int max_solves, const std::function<void()>& solve,
                                           const std::function<Resolve(int, bool)>& adjust) {
  assert(max_solves >= 1);
  EquilibriumLoopResult r;
  for (;;) {
    solve();
    ++r.solves;
    const bool last = r.solves >= max_solves;
    r.pending = adjust(r.solves, last);
    if (r.pending == Resolve::None || last) return r;
  }
}

void ToleranceModel::apply(NewtonOptions& options) const noexcept {
  options.gradient_abs_tol = tolerance;
  options.gradient_rel_tol = 0.0;
  options.gradient_accept_tol = accept_factor * tolerance;
}

}  // namespace palpa
