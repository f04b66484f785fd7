// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The checkpoint file of a design run (JSON, written atomically after every
// accepted iteration; `palpa design --resume` reads it): the iterate θ, the
// optimizer's direction and gradient, the equilibrium it stands on, the
// scores and the history so far, with what makes it this run's (method, γ,
// step lengths, filter radius, the sizes of θ and of the state).

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "palpa/core/json.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/rest/rest.hpp"

namespace palpa::design {

// Where one body of the design stands.
struct BodyCheckpoint {
  std::string name;              // a cohort's body (empty: a one-body design)
  rest::RestState state;
  double max_penetration = 0.0;  // [m]
  bool refreeze_failed = false;  // its contact model could not be chosen anew: it stays frozen
};

struct DesignCheckpoint {
  // What makes it this run's.
  DesignMethod method = DesignMethod::Lbfgs;
  double gamma = 0.0;
  std::vector<double> moves;   // [m]
  double filter_radius = 0.0;  // [m]; 0: per-vertex moves
  // Where the run stands.
  int iteration = 0;  // the last accepted iteration
  Eigen::VectorXd theta, direction, gradient;
  bool steepest = true;
  std::vector<BodyCheckpoint> bodies;
  double phi = 0.0, zeta = 0.0, psi = 0.0;
  std::vector<IterationRecord> history;
  int evaluations = 0;
  int newton_iterations = 0;
  double seconds = 0.0;  // the run's wall time up to the checkpoint
};

Json checkpoint_json(const DesignCheckpoint& c);

// Reads a checkpoint that must belong to a run like `like`: the same method,
// γ, step lengths and filter radius, θ of like.theta's size and the bodies of
// like.bodies (names, and states of their sizes) (members a file from an older version lacks keep like's
// values). Throws palpa::Error (Input) naming the file and field otherwise,
// and for anything malformed.
DesignCheckpoint read_design_checkpoint(const std::filesystem::path& path, const DesignCheckpoint& like);

}  // namespace palpa::design
