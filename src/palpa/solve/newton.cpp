// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/newton.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/core/log.hpp"
#include "palpa/solve/line_search.hpp"
#include "palpa/solve/sparse_ldlt.hpp"

namespace palpa {

std::string_view to_string(NewtonStatus status) noexcept {
  switch (status) {
    case NewtonStatus::Converged:
      return "converged";
    case NewtonStatus::MaxIterations:
      return "maximum iterations reached";
    case NewtonStatus::LineSearchFailed:
      return "line search failed";
    case NewtonStatus::NonFiniteEnergy:
      return "non-finite energy or gradient";
    case NewtonStatus::FactorizationFailed:
      return "Hessian factorization failed";
  }
  return "unknown";
}

namespace {

// Diagonal entries of D below this fraction of the largest |H_ii| are raised
// to it, so that DOFs with (near) zero stiffness still get shifted.
constexpr double kShiftDiagonalFloor = 1e-8;
// Absolute part of the interval searches' tolerance on s.
constexpr double kIntervalAbsoluteTolerance = 1e-12;

std::unique_ptr<SymmetricFactorization> make_factorization(const NewtonOptions& options) {
  if (options.linear_solver == LinearSolverKind::EigenLdlt) {
    return std::make_unique<SparseLdlt>(SparseLdlt::Definiteness::RequirePositive);
  }
  return std::make_unique<SparseCholesky>(options.cholmod_method);
}

double inf_norm(const Eigen::VectorXd& v) {
  return v.size() == 0 ? 0.0 : v.lpNorm<Eigen::Infinity>();
}

// D = diag(max(|H_ii|, floor·max_j |H_jj|)), or the identity if H has no
// non-zero diagonal entry.
Eigen::VectorXd shift_diagonal(const Eigen::SparseMatrix<double>& H) {
  Eigen::VectorXd d = H.diagonal().cwiseAbs();
  const double largest = d.size() == 0 ? 0.0 : d.maxCoeff();
  if (!(largest > 0.0) || !std::isfinite(largest)) return Eigen::VectorXd::Ones(d.size());
  return d.cwiseMax(kShiftDiagonalFloor * largest);
}

struct Direction {
  bool ok = false;
  double shift = 0.0;
  bool projected = false;  // the step came from the system's PSD stand-in for H
  int factorizations = 0;
  FactorStatus status = FactorStatus::NotFactored;
};

// d = −A⁻¹ g, first with A = H; where H does not factor or gives no descent
// direction, with A = P (the system's PSD stand-in, when it has one and
// use_projected_hessian is on); then with A = M + σD (M: P if there is one,
// else H) for the smallest σ of the sequence σ0, σ0·growth, ... that factors
// and gives a descent direction (g·d < 0).
using ProjectedHessian = std::function<const Eigen::SparseMatrix<double>*()>;

Direction newton_direction(SymmetricFactorization& factor, const Eigen::SparseMatrix<double>& H,
                           const ProjectedHessian& projected, const Eigen::VectorXd& g,
                           Eigen::VectorXd& d, double& last_shift, const NewtonOptions& options) {
  Direction r;
  auto attempt = [&](const Eigen::SparseMatrix<double>& A, double sigma, const Eigen::VectorXd& D) {
    ++r.factorizations;
    r.status = factor.factorize(A, sigma, D);
    if (r.status != FactorStatus::Ok) return false;
    d = factor.solve(-g);
    return d.allFinite() && g.dot(d) < 0.0;
  };
  auto hopeless = [](FactorStatus s) {
    return s == FactorStatus::NonFiniteInput || s == FactorStatus::OutOfMemory;
  };
  if (attempt(H, 0.0, Eigen::VectorXd())) {
    r.ok = true;
    return r;
  }
  if (hopeless(r.status)) return r;
  const Eigen::SparseMatrix<double>* P = projected();
  if (P != nullptr) {
    r.projected = true;
    if (attempt(*P, 0.0, Eigen::VectorXd())) {
      r.ok = true;
      return r;
    }
    if (hopeless(r.status)) return r;
  }
  const Eigen::SparseMatrix<double>& M = P != nullptr ? *P : H;
  const Eigen::VectorXd D = shift_diagonal(M);
  double sigma = last_shift > 0.0
                     ? std::max(options.shift_initial, last_shift / options.shift_growth)
                     : options.shift_initial;
  for (int k = 0; k < options.max_shift_attempts; ++k, sigma *= options.shift_growth) {
    if (attempt(M, sigma, D)) {
      r.ok = true;
      r.shift = sigma;
      last_shift = sigma;
      return r;
    }
    if (hopeless(r.status)) return r;
  }
  return r;
}

// Runs the configured line search on φ. The result is usable when `success`:
// a finite φ(step) below phi0 (Armijo's condition is preferred where it applies).
LineSearchResult search_line(const NewtonOptions& o, const LineFunction& phi, double phi0,
                             double slope) {
  const BacktrackingOptions backtracking{1.0, o.armijo_c1, o.backtracking_shrink,
                                         o.max_backtracking_evaluations};
  const IntervalOptions interval{o.interval_relative_tolerance, kIntervalAbsoluteTolerance,
                                 o.max_interval_evaluations};
  auto lowers = [&](LineSearchResult r) {
    r.success = std::isfinite(r.value) && r.value < phi0 && r.step > 0.0;
    return r;
  };
  switch (o.line_search) {
    case LineSearchKind::Backtracking:
      return lowers(backtracking_armijo(phi, phi0, slope, backtracking));
    case LineSearchKind::Brent:
      return lowers(brent_minimize(phi, 0.0, o.max_step, interval));
    case LineSearchKind::GoldenSection:
      return lowers(golden_section_minimize(phi, 0.0, o.max_step, interval));
    case LineSearchKind::BacktrackingThenBrent: {
      const LineSearchResult armijo = backtracking_armijo(phi, phi0, slope, backtracking);
      if (armijo.success) return armijo;
      LineSearchResult brent = lowers(brent_minimize(phi, 0.0, o.max_step, interval));
      const LineSearchResult best_sampled = lowers(armijo);
      if (best_sampled.success && (!brent.success || best_sampled.value < brent.value)) {
        brent.step = best_sampled.step;
        brent.value = best_sampled.value;
        brent.success = true;
      }
      brent.evaluations += armijo.evaluations;
      return brent;
    }
  }
  return LineSearchResult{};
}

}  // namespace

NewtonSolver::NewtonSolver(NewtonOptions options)
    : options_(options), factor_(make_factorization(options_)) {}

NewtonSolver::~NewtonSolver() = default;

void NewtonSolver::set_options(const NewtonOptions& options) {
  const bool same_factor = options.linear_solver == options_.linear_solver &&
                           options.cholmod_method == options_.cholmod_method;
  options_ = options;
  if (!same_factor) factor_ = make_factorization(options_);
}

void NewtonSolver::reset_system() noexcept {
  hessian_ = Eigen::SparseMatrix<double>();
  projected_ = Eigen::SparseMatrix<double>();
  bound_system_ = nullptr;
  bound_dofs_ = -1;
}

void NewtonSolver::bind_system(const System& system) {
  const Eigen::Index n = system.num_dofs();
  if (&system != bound_system_ || n != bound_dofs_) {
    // A new system builds its own pattern into an empty matrix.
    hessian_ = Eigen::SparseMatrix<double>();
    projected_ = Eigen::SparseMatrix<double>();
    bound_system_ = &system;
    bound_dofs_ = n;
  }
}

FactorStatus NewtonSolver::factor_hessian(const System& system, const Eigen::VectorXd& x) {
  bind_system(system);
  system.hessian(x, hessian_);
  return factor_->factorize(hessian_);
}

NewtonResult NewtonSolver::solve(System& system, Eigen::VectorXd& x) {
  const Eigen::Index n = system.num_dofs();
  if (x.size() != n) {
    throw Error(
        ErrorKind::Internal,
        fmt::format("NewtonSolver::solve: x has {} entries, the system {} DOFs", x.size(), n));
  }
  bind_system(system);
  const FactorCounts counts_before = factor_->counts();
  NewtonResult r;

  system.prepare(x);
  Eigen::VectorXd g(n);
  double energy = system.energy_gradient(x, g);
  ++r.energy_evaluations;
  ++r.gradient_evaluations;
  double gnorm = inf_norm(g);
  r.initial_energy = energy;
  r.initial_gradient_norm = gnorm;
  r.gradient_tolerance = std::max(options_.gradient_abs_tol, options_.gradient_rel_tol * gnorm);

  Eigen::VectorXd d(n);
  Eigen::VectorXd trial(n);
  Eigen::VectorXd g_trial(n);
  double last_shift = 0.0;
  bool chord_ready = false;  // the factorization holds the last unshifted H (see chord_ratio)
  NewtonStatus status = NewtonStatus::MaxIterations;
  std::string message;

  // A stateless system's E and g at the full step x + d, evaluated together
  // by the first line-search trial, become those of the next iterate when
  // that step is taken (System::stateless): one energy pass fewer per step.
  // A full step whose E is finite but whose g is not counts as inadmissible
  // (E = +inf), so the line search shortens it instead of stopping there.
  const bool stateless = system.stateless();
  Eigen::VectorXd g_full(stateless ? n : 0);
  double energy_full = 0.0;
  bool have_full = false;
  const LineFunction phi = [&](double s) {
    trial.noalias() = x + s * d;
    if (stateless && s == 1.0) {
      if (!have_full) {
        ++r.energy_evaluations;
        ++r.gradient_evaluations;
        energy_full = system.energy_gradient(trial, g_full);
        have_full = std::isfinite(energy_full) && g_full.allFinite();
        if (!have_full) return std::numeric_limits<double>::infinity();
      }
      return energy_full;
    }
    ++r.energy_evaluations;
    return system.energy(trial);
  };
  // g at trial = x + d, right after phi(1.0) returned a finite energy.
  const auto gradient_at_full_step = [&]() -> const Eigen::VectorXd& {
    if (have_full) return g_full;
    system.gradient(trial, g_trial);
    ++r.gradient_evaluations;
    return g_trial;
  };

  // After x moved: prepare, evaluate E and g there (or, for a stateless
  // system, take `known`, E and g already evaluated at this x) and record the
  // iteration (its energy and gradient norm filled in). False, with the
  // status set, when E or g is not finite.
  struct Known {
    double energy;
    const Eigen::VectorXd* gradient;
  };
  const auto commit_step = [&](NewtonIteration it, std::string_view what, std::optional<Known> known = {}) {
    system.prepare(x);
    if (stateless && known) {
      energy = known->energy;
      g = *known->gradient;
    } else {
      energy = system.energy_gradient(x, g);
      ++r.energy_evaluations;
      ++r.gradient_evaluations;
    }
    gnorm = inf_norm(g);
    ++r.iterations;
    it.energy = energy;
    it.gradient_norm = gnorm;
    r.history.push_back(it);
    spdlog::debug("newton {:3d}: E = {:.12g}  |g| = {:.3e}  {} = {:.4g}  shift = {:.1e}  ({} trials)",
                  r.iterations, energy, gnorm, what, it.step, it.shift, it.line_search_evaluations);
    if (std::isfinite(energy) && g.allFinite()) return true;
    status = NewtonStatus::NonFiniteEnergy;
    message = fmt::format("iteration {}: energy {} or its gradient is not finite after the {}", r.iterations,
                          energy, what);
    return false;
  };

  if (!std::isfinite(energy) || !g.allFinite()) {
    status = NewtonStatus::NonFiniteEnergy;
    message = fmt::format("energy {} or its gradient is not finite at the starting point", energy);
  }
  bool projection_helps = options_.use_projected_hessian;
  // A full step taken on the noise test below whose committed ‖g‖∞ came out
  // no lower: the trial's gradient, taken before the step's contact set was
  // committed, misled it. Newton then cycles between two contact sets at a
  // kink of E (a sample on the fold of a concave support), below E's rounding.
  bool noise_step_misled = false;
  bool noise_step = false;
  // Where rounding stops progress, an acceptable gradient counts as converged.
  const auto converged_to_rounding = [&](std::string_view why) {
    status = NewtonStatus::Converged;
    message = fmt::format("converged to rounding in {} iterations: |g| = {:.3e} <= {:.3e} (acceptable){}",
                          r.iterations, gnorm, options_.gradient_accept_tol, why);
  };
  while (status != NewtonStatus::NonFiniteEnergy) {
    check_interrupt();
    if (gnorm <= r.gradient_tolerance) {
      status = NewtonStatus::Converged;
      message = fmt::format("converged in {} iterations: |g| = {:.3e} <= {:.3e}", r.iterations,
                            gnorm, r.gradient_tolerance);
      break;
    }
    if (r.iterations >= options_.max_iterations) {
      status = NewtonStatus::MaxIterations;
      message = fmt::format("no convergence in {} iterations: |g| = {:.3e} > {:.3e}", r.iterations,
                            gnorm, r.gradient_tolerance);
      break;
    }

    have_full = false;  // (a new direction d follows)
    if (chord_ready) {
      chord_ready = false;
      d = factor_->solve(-g);
      const double e1 = d.allFinite() ? phi(1.0) : std::numeric_limits<double>::infinity();
      if (std::isfinite(e1)) {
        const Eigen::VectorXd& g1 = gradient_at_full_step();
        const double gnorm_trial = inf_norm(g1);
        if (g1.allFinite() && gnorm_trial * options_.chord_ratio <= gnorm) {
          x = trial;
          if (!commit_step(NewtonIteration{0.0, 0.0, 1.0, 0.0, 1, 0}, "chord step", Known{e1, &g1})) break;
          chord_ready = true;
          continue;
        }
      }
      have_full = false;
    }

    system.hessian(x, hessian_);
    ++r.hessian_evaluations;
    // The PSD stand-in is assembled only if H fails.
    const ProjectedHessian projected = [&]() -> const Eigen::SparseMatrix<double>* {
      if (!projection_helps) return nullptr;
      if (projected_.rows() != hessian_.rows() || projected_.nonZeros() != hessian_.nonZeros()) projected_ = hessian_;
      if (!system.projected_hessian(x, projected_)) return nullptr;
      ++r.hessian_evaluations;
      return &projected_;
    };
    const Direction dir = newton_direction(*factor_, hessian_, projected, g, d, last_shift, options_);
    r.last_factor_status = dir.status;
    if (!dir.ok) {
      status = NewtonStatus::FactorizationFailed;
      message = fmt::format(
          "iteration {}: no descent direction from the Hessian ({}) after {} factorizations",
          r.iterations, to_string(dir.status), dir.factorizations);
      break;
    }

    const double slope = g.dot(d);
    LineSearchResult ls;
    const bool at_noise = std::abs(slope) <= std::max(options_.energy_noise * std::abs(energy), options_.energy_noise_abs);
    if (at_noise && noise_step_misled && gnorm <= options_.gradient_accept_tol) {
      converged_to_rounding("; the step a Newton model predicts lowers E by less than its rounding, and such a "
                            "step did not lower |g| before (a contact kink)");
      break;
    }
    noise_step = false;
    if (at_noise) {
      // The decrease the quadratic model predicts is below the rounding error
      // of E, so no line search can see it: judge the full step by the gradient.
      const double e1 = phi(1.0);
      ls.evaluations = 1;
      if (std::isfinite(e1)) {
        const Eigen::VectorXd& g1 = gradient_at_full_step();
        if (g1.allFinite() && inf_norm(g1) < gnorm) {
          ls.step = 1.0;
          ls.value = e1;
          ls.success = true;
          noise_step = true;
        }
      }
    }
    if (!ls.success) {
      const int noise_evaluations = ls.evaluations;
      ls = search_line(options_, phi, energy, slope);
      ls.evaluations += noise_evaluations;
    }
    if (!ls.success && gnorm <= options_.gradient_accept_tol) {
      converged_to_rounding(", no lower energy along the Newton direction");
      break;
    }
    if (!ls.success) {
      status = NewtonStatus::LineSearchFailed;
      message = fmt::format(
          "line search failed at iteration {}: no step along the Newton direction lowered "
          "E = {:.10g} "
          "(|g| = {:.3e}, g.d = {:.3e}, {} trials)",
          r.iterations, energy, gnorm, slope, ls.evaluations);
      break;
    }

    x += ls.step * d;
    const double gnorm_before = gnorm;
    NewtonIteration it{0.0, 0.0, ls.step, dir.shift, ls.evaluations, dir.factorizations};
    it.projected = dir.projected;
    const std::optional<Known> known =
        ls.step == 1.0 && have_full ? std::optional<Known>(Known{energy_full, &g_full}) : std::nullopt;
    if (!commit_step(it, dir.projected ? "projected step" : "step", known)) break;
    if (noise_step && gnorm >= gnorm_before) noise_step_misled = true;
    // Near a saddle or an instability the stand-in, blind to the negative
    // curvature, creeps (‖g‖ falling by a constant factor near 1 per step):
    // from then on this solve shifts H, which can move along that curvature.
    if (dir.projected && gnorm > options_.projected_progress * gnorm_before) projection_helps = false;
    chord_ready = options_.chord_ratio > 0.0 && ls.step == 1.0 && dir.shift == 0.0 && !dir.projected &&
                  gnorm * options_.chord_ratio <= gnorm_before;
  }

  r.status = status;
  r.message = std::move(message);
  r.energy = energy;
  r.gradient_norm = gnorm;
  const FactorCounts counts_after = factor_->counts();
  r.analyses = counts_after.analyses - counts_before.analyses;
  r.factorizations = counts_after.factorizations - counts_before.factorizations;
  spdlog::debug("newton: {}", r.message);
  return r;
}

}  // namespace palpa
