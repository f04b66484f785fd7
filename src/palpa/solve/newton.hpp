// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Newton's method with a line search, minimizing a System's energy (the static
// equilibrium of every simulated system: thesis §5.4, §7.3.4).
//
// Each iteration: H = hessian(x); factor H (the analysis of its pattern is done
// once and reused across iterations and across solve() calls); d = −H⁻¹ g; a
// line search on φ(s) = E(x + s d); x ← x + s d; prepare(x); E, g at x.
//
// Convergence: stops when ‖g‖∞ ≤ max(gradient_abs_tol, gradient_rel_tol·‖g(x0)‖∞),
// i.e. when either tolerance is met (the looser one decides). ‖g‖∞ is the
// largest out-of-balance force component [N]. gradient_abs_tol is in the
// system's gradient units; gradient_rel_tol is relative to the gradient at the
// start of that solve() call (so a warm start from a near-equilibrium asks for
// proportionally less; set gradient_abs_tol to guard against that).
//
// Indefinite Hessians: every iteration first factors H as it is. If the
// factorization reports NotPositiveDefinite (or the direction is not a descent
// direction), it steps with the system's positive semi-definite stand-in P
// instead (System::projected_hessian, e.g. each element's Hessian projected to
// PSD), when the system has one and use_projected_hessian is on, as long as
// its steps keep cutting ‖g‖ (projected_progress). Only if that
// fails too, it factors M + σD (M: P, or H without one),
// D = diag(max(|M_ii|, 1e-8·max_j |M_jj|)) (Jacobi scaling, so σ is
// dimensionless and DOFs of different units are shifted alike), with σ growing
// geometrically from shift_initial (or from a tenth of the last shift that
// worked in this solve) until it factors. The next iteration starts from H
// again, so the last steps, where H is definite, converge quadratically. The
// stand-in and the shift change only the step, never the energy.
// A fixed regularization such as the thesis's K + αM (no contact yet) is the
// system's business: it adds it inside hessian() (see system.hpp).
//
// Status, not exceptions: non-convergence, a failed line search, a failed
// factorization or a non-finite energy are reported in NewtonResult; x is left
// at the last accepted iterate. Exceptions thrown by the system (also from
// inside TBB loops) and palpa::Error(Interrupted) from check_interrupt(), which
// is called every iteration, propagate to the caller; x then holds the last
// accepted iterate and the solver stays usable.
//
// Sensitivities: after solve(), factor_hessian(system, x) factors the true,
// unshifted H(x*) with the same (already analysed) factorization, and
// factorization() back-solves with it (see parametric_system.hpp). The last
// factorization made inside solve() is of the Hessian before the last step,
// possibly shifted or projected, so it is not the one to use.

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "palpa/solve/factorization.hpp"
#include "palpa/solve/sparse_cholesky.hpp"
#include "palpa/solve/system.hpp"

namespace palpa {

enum class LineSearchKind {
  Backtracking,           // Armijo backtracking only
  Brent,                  // Brent's method on s ∈ [0, max_step]
  GoldenSection,          // golden sections on s ∈ [0, max_step] (thesis §7.3.4)
  BacktrackingThenBrent,  // Armijo; if that fails, Brent on [0, max_step] (thesis §5.4)
};

enum class LinearSolverKind {
  Cholmod,    // SparseCholesky (CHOLMOD), the default
  EigenLdlt,  // SparseLdlt requiring positive pivots (reference, no CHOLMOD)
};

struct NewtonOptions {
  // Convergence (see above): ‖g‖∞ ≤ max(abs, rel·‖g(x0)‖∞).
  double gradient_abs_tol = 0.0;   // [gradient units, N for positions]
  // Where rounding stops progress first (the line search finds no lower energy
  // along a descent direction), a gradient this small still counts as
  // converged; 0 = no such allowance. Set it to what the caller can accept
  // (e.g. 1e-7 of its force scale) and gradient_abs_tol to what it aims for.
  double gradient_accept_tol = 0.0;
  double gradient_rel_tol = 1e-8;  // [-]
  int max_iterations = 100;

  LineSearchKind line_search = LineSearchKind::BacktrackingThenBrent;
  double armijo_c1 = 1e-4;           // sufficient-decrease constant (5.8)
  double backtracking_shrink = 0.5;  // τ
  int max_backtracking_evaluations = 20;
  // Interval searches (Brent, golden) cover s ∈ [0, max_step] and locate the
  // best s to within interval_relative_tolerance·s + 1e-12.
  double max_step = 1.0;
  double interval_relative_tolerance = 1e-3;
  int max_interval_evaluations = 60;

  // Diagonal shift for Hessians that are not positive definite (dimensionless,
  // relative to the Jacobi diagonal D).
  double shift_initial = 1e-4;
  double shift_growth = 10.0;
  int max_shift_attempts = 30;
  // Step with System::projected_hessian where H is not positive definite,
  // before shifting (see above). Measured on the crushed rim cells of a deep
  // poke: a shift large enough to factor H there (σ ~ 1) makes Newton crawl
  // (tens of iterations at a full step, each with 2–3 factorizations).
  bool use_projected_hessian = true;
  // A projected step that leaves ‖g‖∞ above this fraction of what it was
  // turns the stand-in off for the rest of the solve (measured on a cylinder
  // compressed past its surface instability: projected steps there cut ‖g‖ by
  // only 0.5–0.97 each and never converge; shifted H steps do).
  double projected_progress = 0.5;

  // Near the minimizer the decrease a step can make, |g·d|/2, falls below the
  // rounding error of E and no line search can see it. When |g·d| ≤
  // energy_noise·|E|, the full step is taken (without a line search) if its
  // energy is finite and it lowers ‖g‖∞; otherwise the line search runs as usual.
  double energy_noise = 1e-10;
  // An absolute floor for the same test [J]: a system whose energy sums many
  // near-rest terms knows E only to about (terms) × ε·|term|, which a relative
  // bound cannot express. The test is |g·d| ≤ max(energy_noise·|E|, energy_noise_abs).
  double energy_noise_abs = 0.0;

  // Chord steps (0 = off). Once a full, unshifted Newton step has cut ‖g‖∞
  // by at least this factor (the quadratic phase), the next iteration first
  // tries d = −H⁻¹ g with the Hessian already factored, which costs one
  // gradient instead of a Hessian and a factorization. The chord step is kept
  // when its energy is finite and it cuts ‖g‖∞ by the same factor again
  // (H is then within a quadratically small step of the current Hessian);
  // otherwise the iteration goes on with a fresh Hessian from the same x.
  // Chord steps count as iterations with 0 factorizations.
  double chord_ratio = 0.0;
  LinearSolverKind linear_solver = LinearSolverKind::Cholmod;
  SparseCholesky::Method cholmod_method = SparseCholesky::Method::Auto;
};

enum class NewtonStatus {
  Converged,            // the gradient tolerance was met
  MaxIterations,        // max_iterations steps taken without meeting it
  LineSearchFailed,     // no step along the Newton direction lowered the energy
  NonFiniteEnergy,      // E or g not finite at the start or after prepare()
  FactorizationFailed,  // H could not be factored even with the largest shift
};

std::string_view to_string(NewtonStatus status) noexcept;

// One Newton iteration k: the step from x_k to x_{k+1} and the state it reached.
struct NewtonIteration {
  double energy = 0.0;         // E(x_{k+1}) [J]
  double gradient_norm = 0.0;  // ‖g(x_{k+1})‖∞ [N]
  double step = 0.0;           // s_k: x_{k+1} = x_k + s_k d_k (1 = full Newton step)
  double shift = 0.0;          // σ_k used for d_k (0 = H unshifted)
  int line_search_evaluations = 0;
  int factorizations = 0;  // numeric factorizations this iteration (1 + shift retries)
  bool projected = false;  // d_k came from the PSD stand-in (possibly shifted), not from H
};

struct NewtonResult {
  NewtonStatus status = NewtonStatus::MaxIterations;
  int iterations = 0;                  // accepted steps (= history.size())
  double initial_energy = 0.0;         // E(x0) [J]
  double initial_gradient_norm = 0.0;  // ‖g(x0)‖∞ [N]
  double energy = 0.0;                 // E at the returned x [J]
  double gradient_norm = 0.0;          // ‖g‖∞ at the returned x [N]
  double gradient_tolerance = 0.0;     // the threshold that applied [N]
  std::vector<NewtonIteration> history;
  std::int64_t analyses = 0;        // symbolic analyses during this solve
  std::int64_t factorizations = 0;  // numeric factorizations during this solve
  int energy_evaluations = 0;       // energy() and energy_gradient() calls
  int gradient_evaluations = 0;     // gradient() and energy_gradient() calls
  int hessian_evaluations = 0;
  FactorStatus last_factor_status = FactorStatus::NotFactored;
  std::string message;  // one line: why it stopped, with figures

  bool converged() const noexcept { return status == NewtonStatus::Converged; }
};

class NewtonSolver {
 public:
  explicit NewtonSolver(NewtonOptions options = {});
  ~NewtonSolver();
  NewtonSolver(const NewtonSolver&) = delete;
  NewtonSolver& operator=(const NewtonSolver&) = delete;

  const NewtonOptions& options() const noexcept { return options_; }
  // Replaces the options. Keeps the factorization (and its analysis) unless the
  // linear solver kind or CHOLMOD method changes.
  void set_options(const NewtonOptions& options);

  // Minimizes system.energy starting from x.
  //  x: n = system.num_dofs() [SI], in: starting point (finite energy), out: the
  //     last accepted iterate (the minimizer when converged).
  // Never throws for non-convergence: read the status. The solver keeps the
  // Hessian pattern and the analysis of the last system it solved; solving the
  // same system object again (e.g. each depth of a continuation) reuses both.
  NewtonResult solve(System& system, Eigen::VectorXd& x);

  // Factors the true Hessian H(x) (no shift) with this solver's factorization,
  // reusing its analysis; does not call prepare(). On Ok, factorization() solves
  // with H(x)⁻¹ until the next solve() or factor_hessian() call.
  FactorStatus factor_hessian(const System& system, const Eigen::VectorXd& x);

  const SymmetricFactorization& factorization() const noexcept { return *factor_; }
  // The Hessian last evaluated (lower triangle; see System::hessian).
  const Eigen::SparseMatrix<double>& last_hessian() const noexcept { return hessian_; }

  // Forgets the Hessian pattern kept for the last system. Needed only when a
  // different System object reuses the address of the previous one.
  void reset_system() noexcept;

 private:
  void bind_system(const System& system);

  NewtonOptions options_;
  std::unique_ptr<SymmetricFactorization> factor_;
  Eigen::SparseMatrix<double> hessian_;
  Eigen::SparseMatrix<double> projected_;  // the PSD stand-in, assembled where H fails
  const System* bound_system_ = nullptr;
  Eigen::Index bound_dofs_ = -1;
};

}  // namespace palpa
