// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/fit/optimize.hpp"

#include <ceres/ceres.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <exception>
#include <limits>

#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/solve/ceres_termination.hpp"

namespace palpa::fit {

namespace {

[[noreturn]] void throw_start_failure(const std::string& reason) {
  throw_solver_error(fmt::format("the fit cannot start: the starting material is rejected ({})", reason));
}

// ---------------------------------------------------------------------------
// Levenberg–Marquardt (Ceres).

// The last evaluation, so that Ceres' request for the Jacobian at a point it
// just evaluated (every accepted step) costs nothing.
struct EvaluationCache {
  TrainingProblem* problem = nullptr;
  Eigen::VectorXd x;
  Evaluation eval;
  bool valid = false;
  bool has = false;
  std::exception_ptr error;  // interruption or internal error inside Ceres' call

  const Evaluation* at(const Eigen::VectorXd& point) {
    if (!(has && x.size() == point.size() && x == point)) {
      x = point;
      has = true;
      valid = problem->evaluate(point, eval);
      if (!valid) spdlog::debug("fit: trial point rejected: {}", eval.reason);
    }
    return valid ? &eval : nullptr;
  }
};

class ResidualCost final : public ceres::CostFunction {
 public:
  explicit ResidualCost(EvaluationCache& cache) : cache_(&cache) {
    set_num_residuals(static_cast<int>(cache.problem->num_residuals()));
    mutable_parameter_block_sizes()->push_back(static_cast<std::int32_t>(cache.problem->num_free()));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    if (cache_->error) return false;
    const Eigen::Index n = cache_->problem->num_free();
    const Eigen::Index m = cache_->problem->num_residuals();
    const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(parameters[0], n);
    const Evaluation* e = nullptr;
    try {
      e = cache_->at(x);
    } catch (...) {
      cache_->error = std::current_exception();
      return false;
    }
    if (e == nullptr) return false;
    Eigen::Map<Eigen::VectorXd>(residuals, m) = e->residuals;
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[0], m, n) =
          e->jacobian;
    }
    return true;
  }

 private:
  EvaluationCache* cache_;
};

class ProgressCallback final : public ceres::IterationCallback {
 public:
  ProgressCallback(const double* x, Eigen::Index n, EvaluationCache& cache, const OptimizeOptions& o,
                   const OptimizerCallbacks& cb, int done)
      : x_(x), n_(n), cache_(&cache), o_(&o), cb_(&cb), done_(done) {}

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (cache_->error || interrupt_requested()) return ceres::SOLVER_ABORT;
    if (s.iteration == 0 || s.step_is_successful) {
      // ε at the point Ceres now stands on, as evaluated when it got there.
      accepted_x_ = Eigen::Map<const Eigen::VectorXd>(x_, n_);
      accepted_objective_ = 2.0 * s.cost;
    }
    const bool record = s.iteration == 0 ? !o_->start_recorded : s.step_is_successful;
    if (record && cb_->on_iteration) {
      GuessState st;
      st.x = Eigen::Map<const Eigen::VectorXd>(x_, n_);
      // (After an accepted step the summary holds the radius already updated
      // by the step's quality: the one the next step is taken with.)
      st.trust_region_radius = s.trust_region_radius;
      st.solver_iterations = done_ + s.iteration;
      // An exception must not cross Ceres: it is rethrown after Solve.
      try {
        cb_->on_iteration(st.x, 2.0 * s.cost, st);
      } catch (...) {
        cache_->error = std::current_exception();
        return ceres::SOLVER_ABORT;
      }
    }
    return ceres::SOLVER_CONTINUE;
  }

  const Eigen::VectorXd& accepted_x() const noexcept { return accepted_x_; }
  double accepted_objective() const noexcept { return accepted_objective_; }

 private:
  const double* x_;
  Eigen::Index n_;
  EvaluationCache* cache_;
  const OptimizeOptions* o_;
  const OptimizerCallbacks* cb_;
  int done_;  // the solver's iterations before this run (resuming)
  Eigen::VectorXd accepted_x_;  // the last point Ceres accepted (the start first)
  double accepted_objective_ = 0.0;
};

}  // namespace

OptimizeOutcome levenberg_marquardt(TrainingProblem& p, const GuessState& start, const OptimizeOptions& o,
                                    const OptimizerCallbacks& cb) {
  EvaluationCache cache;
  cache.problem = &p;
  // The start must be valid: say why if not.
  if (cache.at(start.x) == nullptr) throw_start_failure(cache.eval.reason);
  const double start_objective = cache.eval.objective;

  Eigen::VectorXd x = start.x;
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  problem.AddResidualBlock(new ResidualCost(cache), nullptr, x.data());
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (std::isfinite(p.lower()[k])) problem.SetParameterLowerBound(x.data(), static_cast<int>(i), p.lower()[k]);
    if (std::isfinite(p.upper()[k])) problem.SetParameterUpperBound(x.data(), static_cast<int>(i), p.upper()[k]);
  }
  ceres::Solver::Options opt;
  opt.minimizer_type = ceres::TRUST_REGION;
  opt.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  opt.linear_solver_type = ceres::DENSE_QR;
  // Damping in the already scaled parameters (fit.hpp), not Jacobi-scaled:
  // Jacobi scaling would blow up steps along parameters the data hardly sees
  // (a nearly incompressible sample's volumetric spline under uniaxial load),
  // which then leave the physically valid set.
  opt.jacobi_scaling = false;
  // The limit counts rejected steps too: a resumed fit has what was left
  // (a checkpoint without the count: its accepted iterations).
  const int done = start.solver_iterations > 0 ? start.solver_iterations : o.done_iterations;
  opt.max_num_iterations = std::max(0, o.max_iterations - done);
  opt.function_tolerance = o.function_tolerance;
  opt.gradient_tolerance = 1e-14;
  opt.parameter_tolerance = 1e-9;
  opt.max_num_consecutive_invalid_steps = 8;
  opt.logging_type = ceres::SILENT;
  opt.minimizer_progress_to_stdout = false;
  opt.update_state_every_iteration = true;
  opt.num_threads = 1;
  // A resumed fit goes on with the radius the interrupted one had reached.
  if (start.trust_region_radius > 0.0) opt.initial_trust_region_radius = start.trust_region_radius;
  ProgressCallback progress(x.data(), x.size(), cache, o, cb, done);
  opt.callbacks.push_back(&progress);
  ceres::Solver::Summary summary;
  ceres::Solve(opt, &problem, &summary);
  if (cache.error) std::rethrow_exception(cache.error);
  check_interrupt();

  OptimizeOutcome out;
  out.x = x;
  out.iterations = static_cast<int>(summary.num_successful_steps + summary.num_unsuccessful_steps);
  out.objective = 2.0 * summary.final_cost;
  switch (summary.termination_type) {
    case ceres::CONVERGENCE: out.stop.detail = "converged: " + summary.message; break;
    case ceres::NO_CONVERGENCE: out.stop.detail = "iteration limit reached"; break;
    default: out.stop.detail = "stopped: " + summary.message; break;
  }
  out.stop.termination = termination_of(summary.termination_type);
  // Ceres returns the last point it accepted (the start after a failure) and
  // its final_cost may be a rejected trial's. ε is the one recorded when x was
  // accepted: simulating x again now would warm-start from the last (rejected)
  // trial, and where the equilibrium is not unique that lands elsewhere.
  if (progress.accepted_x().size() == x.size() && x == progress.accepted_x()) {
    out.objective = progress.accepted_objective();
  } else if (x == start.x) {
    out.objective = start_objective;
  } else if (const Evaluation* e = cache.at(x)) {
    out.objective = e->objective;
  }
  return out;
}

// ---------------------------------------------------------------------------
// Nonlinear conjugate gradients.

OptimizeOutcome nonlinear_cg(TrainingProblem& p, const GuessState& start, const OptimizeOptions& o,
                             const OptimizerCallbacks& cb) {
  constexpr double kArmijo = 1e-4;
  constexpr int kMaxTrials = 12;
  GuessState s = start;
  Evaluation e;
  if (s.gradient.size() != s.x.size()) {
    if (!p.evaluate(s.x, e)) throw_start_failure(e.reason);
    s.objective = e.objective;
    s.gradient = 2.0 * e.jacobian.transpose() * e.residuals;
    s.direction = -s.gradient;
    s.step = 0.0;
    s.slope = 0.0;
    s.since_restart = 0;
    if (!o.start_recorded && cb.on_iteration) cb.on_iteration(s.x, s.objective, s);
  }
  OptimizeOutcome out;
  out.stop = Stop{Termination::IterationLimit, "iteration limit reached"};
  int small_decreases = 0;
  const auto n = s.x.size();
  for (int it = o.done_iterations + 1; it <= o.max_iterations; ++it) {
    check_interrupt();
    double slope = s.gradient.dot(s.direction);
    if (!(slope < 0.0)) {  // not a descent direction: restart
      s.direction = -s.gradient;
      slope = s.gradient.dot(s.direction);
      s.since_restart = 0;
    }
    if (!(slope < 0.0)) {
      out.stop = Stop{Termination::Converged, "converged: zero gradient"};
      break;
    }
    const double dmax = s.direction.cwiseAbs().maxCoeff();
    // Initial step: keep the last step's first-order change (Nocedal & Wright
    // §3.5); the first time, move the largest parameter by 10% of its scale.
    double alpha = (s.step > 0.0 && s.slope < 0.0) ? s.step * s.slope / slope : 0.1 / dmax;
    alpha = std::min(alpha, 1.0 / dmax);  // no parameter moves by more than its scale
    bool accepted = false;
    Evaluation best;
    double best_alpha = 0.0;
    for (int trial = 0; trial < kMaxTrials && !accepted; ++trial) {
      Evaluation t;
      if (!p.evaluate(s.x + alpha * s.direction, t)) {
        alpha *= 0.3;
        continue;
      }
      if (t.objective <= s.objective + kArmijo * alpha * slope) {
        accepted = true;
        best = std::move(t);
        best_alpha = alpha;
        // Still descending steeply at the accepted point: one cubic step
        // further (Hermite interpolation of φ on [0, α]).
        const Eigen::VectorXd gt = 2.0 * best.jacobian.transpose() * best.residuals;
        const double slope_t = gt.dot(s.direction);
        if (slope_t < 0.5 * slope) {
          const double d1 = slope + slope_t - 3.0 * (s.objective - best.objective) / (0.0 - alpha);
          const double disc = d1 * d1 - slope * slope_t;
          double next = 2.0 * alpha;
          if (disc >= 0.0) {
            const double d2 = std::sqrt(disc);
            const double cand = alpha - alpha * (slope_t + d2 - d1) / (slope_t - slope + 2.0 * d2);
            if (std::isfinite(cand) && cand > alpha) next = std::min(cand, 4.0 * alpha);
          }
          next = std::min(next, 1.0 / dmax);
          if (next > alpha * 1.05) {
            Evaluation t2;
            if (p.evaluate(s.x + next * s.direction, t2) && t2.objective < best.objective) {
              best = std::move(t2);
              best_alpha = next;
            }
          }
        }
      } else {
        // Minimum of the quadratic through φ(0), φ'(0), φ(α), kept in [0.1α, 0.5α].
        const double denom = 2.0 * (t.objective - s.objective - slope * alpha);
        double next = denom > 0.0 ? -slope * alpha * alpha / denom : 0.5 * alpha;
        alpha = std::clamp(next, 0.1 * alpha, 0.5 * alpha);
      }
    }
    if (!accepted) {
      out.stop = Stop{Termination::NoProgress, "stopped: the line search found no lower objective"};
      break;
    }
    const Eigen::VectorXd g_new = 2.0 * best.jacobian.transpose() * best.residuals;
    const double decrease = (s.objective - best.objective) / s.objective;
    double beta = std::max(0.0, g_new.dot(g_new - s.gradient) / s.gradient.squaredNorm());
    if (++s.since_restart >= n) {
      beta = 0.0;
      s.since_restart = 0;
    }
    s.x += best_alpha * s.direction;
    s.step = best_alpha;
    s.slope = slope;
    s.direction = -g_new + beta * s.direction;
    s.gradient = g_new;
    s.objective = best.objective;
    if (cb.on_iteration) cb.on_iteration(s.x, s.objective, s);
    out.iterations = it;
    small_decreases = decrease < o.function_tolerance ? small_decreases + 1 : 0;
    if (small_decreases >= 2) {
      out.stop = Stop{Termination::Converged,
                      fmt::format("converged: relative decrease below {:g} twice", o.function_tolerance)};
      break;
    }
  }
  out.x = s.x;
  out.objective = s.objective;
  return out;
}

}  // namespace palpa::fit
