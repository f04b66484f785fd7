// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/equilibrium.hpp"

#include <spdlog/spdlog.h>

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

EquilibriumLoopResult run_equilibrium_loop(int max_solves, const std::function<void(Pass)>& solve,
                                           const std::function<Resolve(int, bool)>& adjust) {
  assert(max_solves >= 1);
  EquilibriumLoopResult r;
  Pass pass = Pass::Rough;
  for (;;) {
    const bool last = r.solves + 1 >= max_solves;
    if (last) pass = Pass::Final;
    solve(pass);
    ++r.solves;
    r.pending = adjust(r.solves, last);
    spdlog::debug("equilibrium: solve {} ({}): {}", r.solves, pass == Pass::Rough ? "rough" : "final",
                  r.pending == Resolve::None ? std::string("the model is satisfied")
                                             : fmt::format("{} changed", to_string(r.pending)));
    if (last || (r.pending == Resolve::None && pass == Pass::Final)) return r;
    pass = r.pending == Resolve::None ? Pass::Final : Pass::Rough;
  }
}

NewtonResult solve_pass(NewtonSolver& newton, System& system, Eigen::VectorXd& x, Pass pass) {
  const NewtonOptions final_options = newton.options();
  if (pass == Pass::Final || final_options.gradient_accept_tol <= final_options.gradient_abs_tol) {
    return newton.solve(system, x);
  }
  NewtonOptions rough = final_options;
  rough.gradient_abs_tol = final_options.gradient_accept_tol;
  newton.set_options(rough);
  struct Restore {
    NewtonSolver& newton;
    const NewtonOptions& options;
    ~Restore() { newton.set_options(options); }
  } restore{newton, final_options};
  return newton.solve(system, x);
}

void ToleranceModel::apply(NewtonOptions& options) const noexcept {
  options.gradient_abs_tol = tolerance;
  options.gradient_rel_tol = 0.0;
  options.gradient_accept_tol = accept_factor * tolerance;
}

}  // namespace palpa
