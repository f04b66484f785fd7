// SPDX-License-Identifier: AGPL-3.0-or-later
// PokeSimulator: depth continuation of the punch (platen) on one mesh, or on
// two nested ones whose forces it extrapolates (PokeSetup::extrapolate).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "palpa/axisym/poke.hpp"
#include "palpa/core/error.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/material/checks.hpp"

namespace palpa::axisym {

namespace {

// PokeOptions::newton.chord_ratio when left at 0.
constexpr double kDefaultChordRatio = 1000.0;

void check_options(const PokeModel& m, const PokeOptions& options) {
  const double thickness = m.setup().geometry.thickness;
  const bool compression = m.setup().test == PokeTest::Compression;
  if (!std::isfinite(options.max_depth) || !(options.max_depth > 0.0)) {
    throw_input_error(fmt::format("maximum depth {} m is not positive", options.max_depth),
                      ErrorContext{"", 0, 0, "depth"}, "a positive indentation depth");
  }
  if (!(options.max_depth < 0.9 * thickness)) {
    throw_input_error(fmt::format("maximum depth {} m is not below 90% of the {} {} m", options.max_depth,
                                  compression ? "sample height" : "layer thickness", thickness),
                      ErrorContext{"", 0, 0, "depth"}, "a depth well below the thickness");
  }
  if (options.steps < 1 || options.steps > 100000) {
    throw_input_error(fmt::format("{} depth steps", options.steps), ErrorContext{"", 0, 0, "steps"},
                      "1 to 100000 steps");
  }
}

// The equilibrium path of one model, one depth of the schedule at a time:
// advance(k) solves depth k (cutting its increment where Newton fails) from
// the path predictor, and returns its sample. Counts Newton iterations,
// factorizations and analyses into `counts`.
class Continuation {
 public:
  Continuation(PokeModel& m, NewtonSolver& solver, const PokeOptions& options, WarmStart& warm, PokeCurve& counts)
      : m_(m), solver_(solver), options_(options), warm_store_(warm), counts_(counts) {
    compression_ = m.setup().test == PokeTest::Compression;
    thickness_ = m.setup().geometry.thickness;
    newton_ = options.newton;
    // Newton uses the true Hessian: where it is not positive definite the
    // factorization says so and Newton steps with the element-projected stand-in
    // (projected_hessian) for that iteration only. Projecting at every iteration
    // changes the Hessian near the crushed rim cells at the solution and makes
    // convergence linear (measured: ~70 iterations per depth instead of 3–4).
    m.set_true_hessian(true);
    auto_tolerance_ = newton_.gradient_abs_tol <= 0.0;
    // Tolerances: ‖g‖∞ (the largest out-of-balance nodal force) below 1e-8 of the
    // force scale at the depth, 4 μ0 a d (indentation), and never below the
    // rounding floor. The force then moves by less than 2e-9 of itself when the
    // tolerance is tightened tenfold (measured on the foam curve); 1e-9 costs a
    // chord step at 8 of its 20 depths. Compression holds 1e-9 of 3 μ0 π R² d/H:
    // a frictionless sample solved to 1e-8 leaves the homogeneous state at its
    // surface instability (55%) with a residual Newton cannot remove (measured:
    // ν = 0.45, CompressionPhysicsDeep), solved to 1e-9 it passes on to creases.
    relative_tolerance_ = compression_ ? 1e-9 : 1e-8;
    const double mu0 = material::small_strain_constants(m.material()).mu;
    const double a = m.setup().geometry.punch_radius;
    force_scale_per_depth_ = compression_ ? 3.0 * mu0 * std::acos(-1.0) * a * a / thickness_ : 4.0 * mu0 * a;
    newton_.gradient_rel_tol = std::min(newton_.gradient_rel_tol, 1e-12);
    // Chord steps finish many depths: the step from ‖g‖ ~ 1e-8 of the force
    // to the tolerance needs no new Hessian (newton.hpp).
    if (newton_.chord_ratio == 0.0) newton_.chord_ratio = kDefaultChordRatio;
    if (newton_.energy_noise_abs <= 0.0) newton_.energy_noise_abs = m.energy_noise_floor();

    x_ = Eigen::VectorXd::Zero(m.num_dofs());
    x_before_ = x_;
    step_ = options.max_depth / options.steps;
    // Contact sets at x and one increment back: the curvature x'' is used only
    // when they agree (across a change the path has a kink).
    m.set_depth(0.0);  // (a model that ran before is still at its last depth)
    contacts_at_x_ = m.contact_set(x_);
    contacts_before_ = contacts_at_x_;
    // The first tangent, at rest: the linear-elastic response to the punch.
    if (solver_.factor_hessian(m, x_) == FactorStatus::Ok) {
      update_tangent();
      ++counts_.factorizations;
    }
    // Warm start (PokeOptions::warm_start): the last run's equilibria, used
    // only on the same schedule; this run's replace them once it succeeds.
    if (options.warm_start && warm.max_depth == options.max_depth &&
        warm.solutions.size() == static_cast<std::size_t>(options.steps) + 1) {
      warm_ = std::move(warm.solutions);
    }
    warm = WarmStart{};
    if (options.warm_start) solutions_.resize(static_cast<std::size_t>(options.steps) + 1);
  }

  // The free DOFs of the last equilibrium.
  const Eigen::VectorXd& x() const noexcept { return x_; }

  PokeSample advance(int k);

  // After the last depth: what the next warm-started run starts from.
  void finish() {
    if (options_.warm_start) warm_store_ = WarmStart{options_.max_depth, std::move(solutions_), {}};
  }

 private:
  // Predictor. The equilibrium path x(d) has the tangent h = dx/dd given by
  // K h = −∂g/∂d (K: the Hessian over the free DOFs at x, ∂g/∂d: how the
  // gradient changes when the punch and the face nodes move down with the free
  // DOFs held, by a central difference in d). K is the factorization Newton
  // made on its last iteration, an unshifted Hessian within one quadratically
  // convergent step of x, so the tangent costs two gradients and a back-solve.
  // The next depth starts from the Taylor step x + Δh + ½Δ²x'', with x'' from
  // the solution one increment back; a contact set that changes on the way is
  // left to Newton. Without a tangent (a shifted last factorization, or no
  // iteration), the last increment is extrapolated.
  void update_tangent() {
    // (Moving the face nodes of a crushed cell by ±eps may invert it: then
    // there is no tangent and the last increment is extrapolated.)
    have_tangent_ = m_.gradient_depth_derivative(x_, 1e-4 * step_, dg_dd_);
    if (!have_tangent_) return;
    tangent_ = -solver_.factorization().solve(dg_dd_);
    have_tangent_ = tangent_.allFinite();
  }

  // The starting point of Newton at depth `next` (delta beyond the current).
  bool predict(double delta, bool first_attempt, int k, Eigen::VectorXd& guess);
  [[noreturn]] void give_up(double next, const NewtonResult& r, bool crushed) const;
  void sensitivities(PokeSample& sample);

  PokeModel& m_;
  NewtonSolver& solver_;
  const PokeOptions& options_;
  WarmStart& warm_store_;
  PokeCurve& counts_;
  NewtonOptions newton_;
  bool compression_ = false;
  bool auto_tolerance_ = false;
  double thickness_ = 0.0;
  double force_scale_per_depth_ = 0.0;
  double relative_tolerance_ = 0.0;
  double step_ = 0.0;
  Eigen::VectorXd x_;
  Eigen::VectorXd x_before_;  // solution one increment back (for extrapolation)
  double depth_ = 0.0;
  double last_increment_ = 0.0;
  Eigen::VectorXd tangent_;
  bool have_tangent_ = false;
  Eigen::VectorXd dg_dd_;
  std::vector<char> contacts_at_x_;
  std::vector<char> contacts_before_;
  std::vector<Eigen::VectorXd> warm_;
  std::vector<Eigen::VectorXd> solutions_;
  Eigen::VectorXd g_guess_;
  Eigen::VectorXd g_warm_;
};

bool Continuation::predict(double delta, bool first_attempt, int k, Eigen::VectorXd& guess) {
  // Start from the predictor (see above); fall back to cruder ones while a
  // guess inverts a cell.
  guess = x_;
  bool admissible = false;
  const auto try_guess = [&](Eigen::VectorXd candidate) {
    if (admissible) return;
    m_.separate_new_contacts(candidate, contacts_at_x_);
    if (std::isfinite(m_.energy(candidate))) {
      guess = candidate;
      admissible = true;
    }
  };
  if (have_tangent_) {
    const Eigen::VectorXd first_order = x_ + delta * tangent_;
    if (last_increment_ > 0.0 && contacts_before_ == contacts_at_x_) {
      const Eigen::VectorXd curvature =
          (2.0 / (last_increment_ * last_increment_)) * (x_before_ - x_ + last_increment_ * tangent_);
      try_guess(first_order + (0.5 * delta * delta) * curvature);
    }
    try_guess(first_order);
  }
  if (last_increment_ > 0.0) try_guess(x_ + (x_ - x_before_) * (delta / last_increment_));
  try_guess(x_);
  if (admissible && first_attempt && !warm_.empty()) {
    const Eigen::VectorXd& w = warm_[static_cast<std::size_t>(k)];
    if (w.size() == guess.size() && std::isfinite(m_.energy_gradient(w, g_warm_)) &&
        std::isfinite(m_.energy_gradient(guess, g_guess_)) &&
        g_warm_.lpNorm<Eigen::Infinity>() < g_guess_.lpNorm<Eigen::Infinity>()) {
      guess = w;
    }
  }
  return admissible;
}

void Continuation::give_up(double next, const NewtonResult& r, bool crushed) const {
  const auto diag = m_.diagnostics(x_);
  const std::string why = r.message.empty() ? std::string("the starting point was inadmissible") : r.message;
  // What would help. A material that gives way in compression localizes
  // under the punch, and a sharp rim crushes the cells beside it: in both a
  // finer mesh follows the punch less far, not further (measured with the
  // 1.03 mm punch of the foam example to 4 mm: its true material, 25 steps,
  // stops at 3.52 mm on level 2 and 3.04 mm on level 3; a stable neo-Hookean
  // of ν = 0.25, 20 steps, at 3.41 mm extrapolated from levels 1–2 and at
  // 3.01 mm from levels 2–3, and reaches 4 mm on level 2 with a 0.05 mm fillet).
  const double limit = material::uniaxial_compression_limit(m_.material());
  const bool crushed_at_sharp_rim = !compression_ && m_.setup().fillet_radius == 0.0 && diag.min_jacobian < 0.2;
  std::string advice;
  if (limit > 0.0) {
    advice = fmt::format(
        "This material stops resisting compression below a uniaxial stretch of {:.3g} (palpa material show): "
        "cells compressed past it localize, and a finer --mesh-level stops sooner, not later; shallower "
        "depths, a fillet radius or a material stable in compression would help",
        limit);
  } else if (crushed_at_sharp_rim) {
    advice =
        "The sharp rim of the punch crushes the cells beside it, and a finer --mesh-level crushes them sooner: "
        "a fillet radius (--fillet, a few percent of the punch radius) or shallower depths would help";
  } else {
    advice = compression_ ? "Try a finer --mesh-level or a smaller final compression"
                          : "Try a finer --mesh-level or fewer extreme depths";
  }
  if (crushed) {
    throw_solver_error(fmt::format(
        "the equilibrium at depth {:.6g} mm was not found ({}), and halving the step would not help: "
        "at {:.6g} mm the most crushed cell keeps {:.3g}% of its volume (det F {:.3g}), "
        "so this mesh cannot follow the material much deeper. {}",
        next * 1e3, why, depth_ * 1e3, 100.0 * diag.min_jacobian, diag.min_jacobian,
        advice));
  }
  throw_solver_error(fmt::format(
      "the equilibrium at depth {:.6g} mm{} was not found after {} halvings of the step "
      "(last attempt from {:.6g} mm: {}); at {:.6g} mm the smallest det F was {:.3g}, "
      "{} surface nodes touched the {}, largest penetration {:.3g} um. {}",
      next * 1e3, compression_ ? fmt::format(" ({:.3g}% compression)", 100.0 * next / thickness_) : "",
      options_.max_step_cuts, depth_ * 1e3, why, depth_ * 1e3, diag.min_jacobian, diag.contact_nodes,
      compression_ ? "platens" : "punch", diag.max_penetration * 1e6,
      advice));
}

void Continuation::sensitivities(PokeSample& sample) {
  Eigen::VectorXd dfdx;
  Eigen::VectorXd dfdtheta;
  const FactorStatus status = solver_.factor_hessian(m_, x_);
  if (status != FactorStatus::Ok) {
    throw_solver_error(fmt::format(
        "the stiffness at depth {:.6g} mm could not be factored for the sensitivities ({}){}", depth_ * 1e3,
        to_string(status),
        compression_ && status == FactorStatus::NotPositiveDefinite
            ? fmt::format(": the equilibrium at {:.3g}% compression is unstable (with frictionless platens "
                          "the uniform state of a sample gives way to creases of its side wall beyond "
                          "about 55%)",
                          100.0 * depth_ / thickness_)
            : std::string()));
  }
  m_.punch_force_derivatives(x_, dfdx, dfdtheta);
  const Eigen::VectorXd lambda = solver_.factorization().solve(dfdx);
  sample.dforce_dparams = dfdtheta - m_.gradient_param_adjoint(x_, lambda);
}

PokeSample Continuation::advance(int k) {
  const double target = k == options_.steps ? options_.max_depth : k * step_;
  PokeSample sample;
  sample.substeps = 0;
  double increment = target - depth_;
  int cuts = 0;
  while (depth_ < target) {
    check_interrupt();
    const double next = std::min(target, depth_ + increment);
    m_.set_depth(next);
    if (auto_tolerance_) {
      newton_.gradient_abs_tol = std::max(relative_tolerance_ * force_scale_per_depth_ * next, m_.gradient_noise_floor());
      newton_.gradient_accept_tol = 1e-6 * force_scale_per_depth_ * next;
    }
    solver_.set_options(newton_);
    Eigen::VectorXd guess;
    const bool admissible = predict(next - depth_, cuts == 0, k, guess);
    NewtonResult r;
    if (admissible) {
      r = solver_.solve(m_, guess);
      sample.newton_iterations += r.iterations;
      counts_.factorizations += r.factorizations;
      counts_.analyses += r.analyses;
    }
    if (r.converged()) {
      x_before_ = x_;
      x_ = guess;
      last_increment_ = next - depth_;
      depth_ = next;
      ++sample.substeps;
      sample.residual = r.gradient_norm;
      contacts_before_ = std::move(contacts_at_x_);
      contacts_at_x_ = m_.contact_set(x_);
      have_tangent_ = false;
      if (r.iterations > 0 && r.history.back().shift == 0.0 && !r.history.back().projected &&
          r.last_factor_status == FactorStatus::Ok) {
        update_tangent();
      }
      continue;
    }
    m_.set_depth(depth_);
    // (A guess that inverts a cell costs no Newton iterations: a shorter step
    // is tried even then.)
    if (admissible && options_.give_up_below_jacobian > 0.0 &&
        m_.diagnostics(x_).min_jacobian < options_.give_up_below_jacobian) {
      give_up(next, r, true);
    }
    if (++cuts > options_.max_step_cuts) give_up(next, r, false);
    increment *= 0.5;
    spdlog::debug("depth {:.6g} mm: step cut to {:.4g} um", next * 1e3, increment * 1e6);
  }
  counts_.newton_iterations += sample.newton_iterations;
  sample.depth = depth_;
  sample.force = m_.punch_force(x_);
  const auto diag = m_.diagnostics(x_);
  sample.max_penetration = diag.max_penetration;
  sample.min_jacobian = diag.min_jacobian;
  sample.contact_nodes = diag.contact_nodes;
  if (options_.sensitivities) sensitivities(sample);
  spdlog::debug("depth {:.6g} mm: force {:.6g} N, {} Newton iterations, residual {:.3g} N", depth_ * 1e3,
                sample.force, sample.newton_iterations, sample.residual);
  if (!solutions_.empty()) solutions_[static_cast<std::size_t>(k)] = x_;
  return sample;
}

}  // namespace

bool extrapolates(const PokeSetup& setup) noexcept {
  return setup.extrapolate && setup.test == PokeTest::Indentation && setup.fillet_radius == 0.0 &&
         setup.mesh_level >= 1;
}

PokeSimulator::PokeSimulator(const material::Material& material, const PokeSetup& setup)
    : model_(std::make_unique<PokeModel>(material, setup)) {
  if (axisym::extrapolates(setup)) {
    PokeSetup coarse = setup;
    --coarse.mesh_level;
    coarse_ = std::make_unique<PokeModel>(material, coarse);
  }
}

PokeSimulator::~PokeSimulator() = default;

void PokeSimulator::set_material_params(const Eigen::VectorXd& theta) {
  model_->set_material_params(theta);
  if (coarse_) coarse_->set_material_params(theta);
}

PokeCurve PokeSimulator::run(const PokeOptions& options, const DepthCallback& on_depth) {
  PokeModel& m = *model_;
  check_options(m, options);
  PokeCurve curve;
  curve.samples.push_back(PokeSample{});
  curve.samples.back().min_jacobian = 1.0;
  if (options.sensitivities) curve.samples.back().dforce_dparams = Eigen::VectorXd::Zero(m.num_params());
  WarmStart fine_warm{warm_.max_depth, std::move(warm_.solutions), {}};
  WarmStart coarse_warm{warm_.max_depth, std::move(warm_.coarse_solutions), {}};
  warm_ = WarmStart{};
  Continuation fine(m, solver_, options, fine_warm, curve);
  std::unique_ptr<Continuation> coarse;
  if (coarse_) coarse = std::make_unique<Continuation>(*coarse_, coarse_solver_, options, coarse_warm, curve);
  for (int k = 1; k <= options.steps; ++k) {
    // The coarser mesh first: it is the cheaper of the two, and usually the
    // one that can follow the punch deeper.
    const PokeSample c = coarse ? coarse->advance(k) : PokeSample{};
    PokeSample s = fine.advance(k);
    if (coarse) {
      // 2 F_L − F_{L−1} (PokeSetup::extrapolate)
      s.mesh_correction = s.force - c.force;
      s.force += s.mesh_correction;
      s.newton_iterations += c.newton_iterations;
      if (options.sensitivities) s.dforce_dparams = 2.0 * s.dforce_dparams - c.dforce_dparams;
    }
    curve.samples.push_back(std::move(s));
    if (on_depth) on_depth(m, fine.x(), curve.samples.back());
  }
  fine.finish();
  if (coarse) coarse->finish();
  warm_ = WarmStart{fine_warm.max_depth, std::move(fine_warm.solutions), std::move(coarse_warm.solutions)};
  return curve;
}

}  // namespace palpa::axisym
