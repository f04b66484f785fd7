// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/design/body_problem.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "palpa/core/error.hpp"
#include "palpa/core/stopwatch.hpp"
#include "palpa/rest/adjoint.hpp"

namespace palpa::design {

BodyProblem::BodyProblem(DesignBody body, const SurfaceMesh& support, const ScoreOptions& score, int slots,
                         int trial_newton_iterations)
    : body_(std::move(body)) {
  const auto t0 = Clock::now();
  sims_.push_back(std::make_unique<rest::RestSimulation>(body_.body, support, body_.rest));
  rest::RestSimulation& first = *sims_.front();
  initial_rest_ = first.solve();
  equilibrium_seconds_ = seconds_since(t0);
  first.freeze_contact_model();
  // One line per design iteration from here on, not one per equilibrium.
  first.set_log_solves(false);
  initial_state_ = first.state();
  body_.rest.log_solves = false;
  rest::RestOptions frozen = body_.rest;
  frozen.stiffness = initial_rest_.stiffness;
  frozen.update_areas = false;
  for (int i = 1; i < slots; ++i) {
    sims_.push_back(std::make_unique<rest::RestSimulation>(body_.body, support, frozen));
    sims_.back()->freeze_contact_model();
  }
  // A trial whose warm-started equilibrium needs many Newton iterations has
  // moved too far: it fails (a shorter step is tried) rather than grinding on.
  for (auto& sim : sims_) {
    NewtonOptions no = sim->newton().options();
    no.max_iterations = std::min(no.max_iterations, trial_newton_iterations);
    sim->newton().set_options(no);
  }
  score_ = std::make_unique<ErgonomicScore>(first, score);
}

BodyProblem::~BodyProblem() = default;

BodyEvaluation BodyProblem::evaluate(const Eigen::MatrixX3d& X, const rest::RestState& warm, bool gradient, int slot) {
  const auto t0 = Clock::now();
  rest::RestSimulation& sim = simulation(slot);
  BodyEvaluation ev;
  sim.restore(warm);
  try {
    sim.set_support_vertices(X);
    ev.rest = sim.solve();
  } catch (const Error& e) {
    if (e.kind() != ErrorKind::Solver) throw;
    ev.failure = e.what();
    ev.seconds = seconds_since(t0);
    return ev;
  }
  ev.state = sim.state();
  ev.score = score_->evaluate(sim, gradient);
  ev.zeta = ev.score.zeta;
  ev.ok = std::isfinite(ev.zeta);
  if (!ev.ok) ev.failure = "the score is not finite";
  if (gradient && ev.ok) {
    const auto ta = Clock::now();
    Eigen::MatrixX3d through;
    if (const AdjointStatus st = rest::shape_derivative(sim, ev.score.d_body, ev.score.d_support, through); !st.ok()) {
      ev.ok = false;
      ev.failure = st.message();
    } else {
      ev.gradient = through + ev.score.d_support_area;
    }
    ev.adjoint_seconds = seconds_since(ta);
  }
  ev.seconds = seconds_since(t0);
  return ev;
}

bool BodyProblem::out_of_band(double max_penetration) const {
  const auto [low, high] = sims_.front()->accepted_penetration();
  const double ratio = max_penetration / body_.rest.target_penetration;
  return max_penetration > 0.0 && (ratio < low || ratio > high);
}

rest::RestResult BodyProblem::refreeze(const Eigen::MatrixX3d& X, const rest::RestState& state) {
  rest::RestSimulation& sim = *sims_.front();
  sim.restore(state);
  sim.set_support_vertices(X);
  return sim.refreeze_contact_model();
}

}  // namespace palpa::design
