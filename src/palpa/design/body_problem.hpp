// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// One body resting on the support being designed (thesis §7.4): its
// simulations, its ergonomic score, and ζ with its shape gradient dζ/dX at a
// support shape X. A design optimizes over one of these, or over a cohort of
// them sharing one support (design/optimizer.hpp).
//
// The contact model is chosen on the initial support by the automatic
// stiffness rule (rest/rest.hpp) and then frozen, so that ζ is one smooth
// function of X between changes of the contact set; `refreeze` chooses it
// anew at another shape. Every simulation (one per slot: trials solved at
// once) shares the model.
//
// Gradient (7.17–7.20), one extra linear solve: at the equilibrium y(X),
//   dζ/dX = ∂ζ/∂X − (∂g/∂X)ᵀ z,   K z = Pᵀ ∂ζ/∂Y
// (rest::shape_derivative; design/optimizer.hpp has the whole derivation).

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "palpa/core/error.hpp"
#include "palpa/design/score.hpp"
#include "palpa/rest/rest.hpp"

namespace palpa::design {

// One body's equilibrium on a support shape and what it scores.
struct BodyEvaluation {
  bool ok = false;
  std::string failure;          // why not ok (the equilibrium failed)
  double zeta = 0.0;            // score.zeta
  Eigen::MatrixX3d gradient;    // dζ/dX (#V×3), when asked for
  rest::RestState state;
  rest::RestResult rest;
  Score score;
  double seconds = 0.0;
  double adjoint_seconds = 0.0;
  // An error other than a failed equilibrium (Ctrl-C, a bad input), kept to
  // be raised on every rank once the ranks have shared their bodies.
  std::optional<ErrorKind> error;
};

// What the other ranks need of a body's evaluation, as bytes: ok, failure,
// error, ζ and its parts, the deepest penetration, Newton iterations, the
// stiffness, the times and (with `gradient`) dζ/dX. The state, the fields
// and the pressures stay with the rank that solved it.
std::string pack_shared(const BodyEvaluation& e, bool gradient);
BodyEvaluation unpack_shared(const std::string& bytes);
// A body's equilibrium as bytes (for the checkpoint, which rank 0 writes).
std::string pack_state(const rest::RestState& s);
rest::RestState unpack_state(const std::string& bytes);

// A body as one member of a design: its name (empty for a one-body design),
// as placed, and the rest settings it is solved with.
struct DesignBody {
  std::string name;
  rest::RestBody body;
  rest::RestOptions rest;
};

class BodyProblem {
 public:
  // Solves the initial equilibrium on `support` with the automatic contact
  // stiffness, freezes the contact model and builds slots − 1 more
  // simulations with it. A warm-started trial may take at most
  // `trial_newton_iterations` Newton iterations (more: it failed).
  BodyProblem(DesignBody body, const SurfaceMesh& support, const ScoreOptions& score, int slots,
              int trial_newton_iterations);
  ~BodyProblem();
  BodyProblem(const BodyProblem&) = delete;
  BodyProblem& operator=(const BodyProblem&) = delete;

  const std::string& name() const noexcept { return body_.name; }
  const rest::RestBody& body() const noexcept { return body_.body; }
  // The scene's rest settings (with log_solves off): how a shape is solved
  // from scratch.
  const rest::RestOptions& rest_options() const noexcept { return body_.rest; }
  int slots() const noexcept { return static_cast<int>(sims_.size()); }
  rest::RestSimulation& simulation(int slot = 0) { return *sims_[static_cast<std::size_t>(slot)]; }
  const rest::RestSimulation& simulation(int slot = 0) const { return *sims_[static_cast<std::size_t>(slot)]; }
  const ErgonomicScore& score() const noexcept { return *score_; }
  // The initial equilibrium, as solved with the automatic stiffness.
  const rest::RestState& initial_state() const noexcept { return initial_state_; }
  const rest::RestResult& initial_rest() const noexcept { return initial_rest_; }
  double equilibrium_seconds() const noexcept { return equilibrium_seconds_; }

  // ζ at X, warm-started from `warm`, on simulation `slot`; with dζ/dX when
  // `gradient`. A failed equilibrium gives ok = false; other errors (Ctrl-C)
  // propagate.
  BodyEvaluation evaluate(const Eigen::MatrixX3d& X, const rest::RestState& warm, bool gradient, int slot);

  // Whether a deepest penetration is outside the band the automatic
  // stiffness rule accepts.
  bool out_of_band(double max_penetration) const;
  // The contact model chosen anew at support X from `state` (on slot 0; the
  // other slots take it too). Throws palpa::Error (Solver) when that fails.
  rest::RestResult refreeze(const Eigen::MatrixX3d& X, const rest::RestState& state);

 private:
  DesignBody body_;
  std::vector<std::unique_ptr<rest::RestSimulation>> sims_;
  std::unique_ptr<ErgonomicScore> score_;
  rest::RestState initial_state_;
  rest::RestResult initial_rest_;
  double equilibrium_seconds_ = 0.0;
};

}  // namespace palpa::design
