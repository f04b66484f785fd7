// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Why an iterative method stopped (the fit's Levenberg–Marquardt and
// conjugate gradients, the design's L-BFGS and step ladder), typed so that a
// caller acts on it — a resume goes on only from the iteration limit — and
// never reads the message meant for people.

#include <string>
#include <string_view>

#include "palpa/core/error.hpp"

namespace palpa {

enum class Termination {
  Converged,       // a convergence test held
  IterationLimit,  // the iteration limit: more iterations could go on
  NoProgress,      // no step lowered the objective (line search or trust region exhausted)
  Failed,          // the method could not go on (a numerical failure)
  NotRun,          // not run: e.g. a layer depth the depth search did not choose
};

struct Stop {
  Termination termination = Termination::IterationLimit;
  std::string detail;  // for people, with the figures: "relative decrease below 1e-05 twice"
};

// "converged", "iteration_limit", "no_progress", "failed", "not_run".
std::string_view to_string(Termination t) noexcept;
// The inverse; an input error at `where` for anything else.
Termination parse_termination(std::string_view text, const ErrorContext& where = {});

}  // namespace palpa
