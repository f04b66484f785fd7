// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The least-squares problem of a fit and the two optimizers that solve it
// (see fit.hpp for the method).

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "palpa/core/termination.hpp"
#include "palpa/fit/coordinates.hpp"
#include "palpa/fit/dataset.hpp"
#include "palpa/fit/simulate.hpp"
#include "palpa/material/material.hpp"

namespace palpa::fit {

// One evaluation of the training residuals r = y_sim − y_meas and their
// Jacobian in the scaled free parameters.
struct Evaluation {
  double objective = 0.0;      // ε = ‖r‖²
  Eigen::VectorXd residuals;
  Eigen::MatrixXd jacobian;    // dr/dx
  int newton_iterations = 0;
  std::string reason;          // why the point was rejected (invalid material, failed simulation)
};

// ε over the training curves of one layer depth, in the coordinates x of
// coordinates.hpp (fixed parameters stay at the start material's values).
class TrainingProblem {
 public:
  // mu0: the shear modulus that scales moduli (see fit.hpp); nu: the range of
  // Poisson's ratio (coordinates.hpp).
  TrainingProblem(const Dataset& d, double layer_depth, const SimulationOptions& so,
                  const material::Material& start, const std::vector<std::string>& fixed, double mu0,
                  PoissonRange nu = {});
  ~TrainingProblem();
  TrainingProblem(const TrainingProblem&) = delete;
  TrainingProblem& operator=(const TrainingProblem&) = delete;

  Eigen::Index num_free() const noexcept { return coords_.size(); }
  Eigen::Index num_residuals() const noexcept { return residuals_ + (curvature_weight_ > 0.0 ? curvature_.rows() : 0); }
  const Coordinates& coordinates() const noexcept { return coords_; }
  Eigen::VectorXd start() const { return coords_.start(); }
  const std::vector<double>& lower() const noexcept { return coords_.lower(); }
  const std::vector<double>& upper() const noexcept { return coords_.upper(); }
  Eigen::VectorXd theta(const Eigen::VectorXd& x) const { return coords_.theta(x); }
  std::unique_ptr<material::Material> material_at(const Eigen::VectorXd& x) const;

  // False (with out.reason) for a parameter out of range, a material that
  // fails the physical checks or a simulation that does not converge; throws
  // for interruption and internal errors. Always computes the Jacobian: the
  // sensitivities cost one factorization and back-solve per simulated depth,
  // little next to the Newton iterations, and every accepted point needs them.
  bool evaluate(const Eigen::VectorXd& x, Evaluation& out);
  int evaluations() const noexcept { return evaluations_; }
  // The training curves' warm starts (CurveSimulator::warm_start), in curve
  // order: what a checkpoint saves so that a resumed fit evaluates exactly as
  // the uninterrupted one. set_warm_starts ignores a list of another length.
  std::vector<axisym::WarmStart> warm_starts() const;
  void set_warm_starts(std::vector<axisym::WarmStart> warm);

  // Spline materials: extra residuals weight·(S″(x_k) − S″₀(x_k)) at every
  // interior knot of f, g and h (S″₀: the start's curvatures), appended after
  // the data residuals. They keep the directions the curves cannot see (a
  // spline's shape outside the stretches a test reaches) near the start
  // instead of arbitrary, where Levenberg–Marquardt would otherwise propose
  // unstable materials. weight [residual unit / Pa]; 0 disables. No effect
  // for the classic models.
  void set_curvature_regularization(double weight);
  // Its share of ε at x (0 without regularization).
  double regularization(const Eigen::VectorXd& x) const;
  Eigen::Index num_data_residuals() const noexcept { return residuals_; }

 private:
  std::unique_ptr<material::Material> material_;
  Eigen::VectorXd theta0_;
  Coordinates coords_;
  std::vector<const MeasuredCurve*> curves_;
  std::vector<std::unique_ptr<CurveSimulator>> sims_;
  std::vector<Eigen::Index> offsets_;
  Eigen::Index residuals_ = 0;
  int evaluations_ = 0;
  Eigen::MatrixXd curvature_;  // rows: S″ at interior knots, over all θ
  double curvature_weight_ = 0.0;
};

// An optimizer's resumable state.
struct GuessState {
  Eigen::VectorXd x;           // scaled free parameters
  // Nonlinear CG (empty until its first iteration).
  Eigen::VectorXd gradient;    // dε/dx at x
  Eigen::VectorXd direction;   // the last search direction
  double objective = 0.0;      // ε at x
  double step = 0.0;           // last accepted step length along `direction`
  double slope = 0.0;          // gradient·direction at the start of the last line search
  int since_restart = 0;
  // Levenberg–Marquardt: the trust-region radius of the next step (0 before
  // the start point is recorded), so that a resumed fit takes the same steps;
  // and the solver's iterations so far, rejected steps included (its
  // iteration limit counts both), so that it stops where it would have.
  double trust_region_radius = 0.0;
  int solver_iterations = 0;
};

struct OptimizeOptions {
  int max_iterations = 50;
  double function_tolerance = 1e-5;
  int done_iterations = 0;      // iterations already done (when resuming)
  bool start_recorded = false;  // the start point was reported before (resuming)
};

struct OptimizerCallbacks {
  // After the start point (unless start_recorded) and after every iteration.
  std::function<void(const Eigen::VectorXd& x, double objective, const GuessState& state)> on_iteration;
};

struct OptimizeOutcome {
  Eigen::VectorXd x;
  double objective = 0.0;
  int iterations = 0;
  Stop stop;  // why it stopped
};

// Ceres' trust-region Levenberg–Marquardt with the exact Jacobian.
OptimizeOutcome levenberg_marquardt(TrainingProblem& p, const GuessState& start, const OptimizeOptions& o,
                                    const OptimizerCallbacks& cb);
// Polak–Ribière+ nonlinear conjugate gradients (thesis §6.2).
OptimizeOutcome nonlinear_cg(TrainingProblem& p, const GuessState& start, const OptimizeOptions& o,
                             const OptimizerCallbacks& cb);

}  // namespace palpa::fit
