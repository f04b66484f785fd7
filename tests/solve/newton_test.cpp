// SPDX-License-Identifier: AGPL-3.0-or-later
// Newton's method on systems with known minimizers, and its status reporting.

#include "palpa/solve/newton.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/core/interrupt.hpp"
#include "solve/matrices.hpp"
#include "solve/test_systems.hpp"

namespace palpa {
namespace {

using test::derivatives_match;
using test::fd_gradient;
using test::fd_jacobian;
using test::make_rng;
using SpMat = Eigen::SparseMatrix<double>;

// Dense full Hessian of a system at x (from its lower triangle), and a check
// that nothing was stored above the diagonal.
Eigen::MatrixXd dense_hessian(const System& s, const Eigen::VectorXd& x) {
  SpMat H;
  s.hessian(x, H);
  EXPECT_EQ(SpMat(H.triangularView<Eigen::StrictlyUpper>()).nonZeros(), 0)
      << "Hessian must hold the lower triangle only";
  return Eigen::MatrixXd(test::symmetric_from_lower(H));
}

// FD checks of gradient and Hessian at x with step h.
void expect_derivatives_match(const System& s, const Eigen::VectorXd& x, double h, double tol) {
  const Eigen::VectorXd fd_g =
      fd_gradient([&](const Eigen::VectorXd& y) { return s.energy(y); }, x, h);
  Eigen::VectorXd g;
  s.gradient(x, g);
  EXPECT_TRUE(derivatives_match(g, fd_g, tol)) << "gradient";
  Eigen::VectorXd g2;
  EXPECT_DOUBLE_EQ(s.energy_gradient(x, g2), s.energy(x));
  EXPECT_EQ(g2, g);
  const Eigen::MatrixXd fd_H = fd_jacobian(
      [&](const Eigen::VectorXd& y) {
        Eigen::VectorXd gy;
        s.gradient(y, gy);
        return gy;
      },
      x, h);
  EXPECT_TRUE(derivatives_match(dense_hessian(s, x), fd_H, tol)) << "Hessian";
}

// Newton to ‖g‖∞ ≤ 1e-12 absolute, no relative tolerance.
NewtonOptions tight_options() {
  NewtonOptions o;
  o.gradient_abs_tol = 1e-12;
  o.gradient_rel_tol = 0.0;
  return o;
}

// Clears an interrupt request however the test ends.
struct InterruptGuard {
  ~InterruptGuard() { clear_interrupt(); }
};

// --- (a) convex quadratic ----------------------------------------------------

TEST(Newton, SolvesAConvexQuadraticExactlyInOneIteration) {
  auto rng = make_rng(21);
  const SpMat A = test::random_spd(200, 4, rng);
  const Eigen::VectorXd b = Eigen::VectorXd::Random(200);
  test::QuadraticSystem system(A, b);
  NewtonSolver solver;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(200);
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_EQ(r.iterations, 1);
  ASSERT_EQ(r.history.size(), 1u);
  EXPECT_EQ(r.history[0].step, 1.0);
  EXPECT_EQ(r.history[0].shift, 0.0);
  EXPECT_EQ(r.factorizations, 1);
  EXPECT_EQ(r.analyses, 1);
  const Eigen::VectorXd exact = Eigen::MatrixXd(A).llt().solve(b);
  EXPECT_LT((x - exact).norm(), 1e-12 * exact.norm());
  EXPECT_NEAR(r.energy, -0.5 * b.dot(exact), 1e-12 * std::abs(b.dot(exact)));
  EXPECT_EQ(r.initial_energy, 0.0);
  EXPECT_DOUBLE_EQ(r.initial_gradient_norm, b.lpNorm<Eigen::Infinity>());
  EXPECT_LE(r.gradient_norm, r.gradient_tolerance);
  EXPECT_DOUBLE_EQ(r.gradient_tolerance, 1e-8 * r.initial_gradient_norm);
}

TEST(Newton, StartingAtTheMinimumTakesNoStep) {
  const SpMat A = test::laplacian_2d(5);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(25);
  test::QuadraticSystem system(A, b);
  Eigen::VectorXd x = Eigen::MatrixXd(A).llt().solve(b);
  NewtonOptions o;
  o.gradient_abs_tol = 1e-12;
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  EXPECT_TRUE(r.converged());
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.factorizations, 0);
  EXPECT_EQ(r.hessian_evaluations, 0);
}

// --- (b) Rosenbrock ----------------------------------------------------------

TEST(Rosenbrock, GradientAndHessianMatchFiniteDifferences) {
  test::RosenbrockSystem system(7);
  auto rng = make_rng(22);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd x(7);
    for (Eigen::Index i = 0; i < 7; ++i) x[i] = u(rng);
    expect_derivatives_match(system, x, 1e-4, 1e-8);
  }
}

class NewtonLineSearch : public ::testing::TestWithParam<LineSearchKind> {};

TEST_P(NewtonLineSearch, MinimizesTheRosenbrockFunction) {
  NewtonOptions o;
  o.line_search = GetParam();
  o.gradient_abs_tol = 1e-10;
  o.gradient_rel_tol = 0.0;
  NewtonSolver solver(o);
  // The classic 2D start, then a chained 12-D one.
  test::RosenbrockSystem r2(2);
  Eigen::VectorXd x2(2);
  x2 << -1.2, 1.0;
  const NewtonResult a = solver.solve(r2, x2);
  ASSERT_TRUE(a.converged()) << a.message;
  EXPECT_LT((x2 - Eigen::VectorXd::Ones(2)).lpNorm<Eigen::Infinity>(), 1e-8);
  EXPECT_LT(a.energy, 1e-18);
  EXPECT_GT(a.iterations, 5);  // a curved valley: Newton needs damped steps

  // (From starts with x_0 < 0 it may find the chained function's other local
  // minimum near (−1, 1, ..., 1), E ≈ 3.987; this start leads to the global one.)
  test::RosenbrockSystem r12(12);
  Eigen::VectorXd x12 = Eigen::VectorXd::Constant(12, 0.5);
  const NewtonResult b = solver.solve(r12, x12);
  ASSERT_TRUE(b.converged()) << b.message;
  EXPECT_LT((x12 - Eigen::VectorXd::Ones(12)).lpNorm<Eigen::Infinity>(), 1e-8);
  // Energy decreases monotonically (a line search never accepts an increase;
  // full steps taken at the rounding level of E may move it by a few ulps).
  double previous = b.initial_energy;
  for (const NewtonIteration& it : b.history) {
    EXPECT_LE(it.energy, previous + 1e-14 * std::abs(previous));
    previous = it.energy;
  }
}

// Chord steps reuse the factored Hessian once Newton converges quadratically:
// the same minimizer to the same tolerance, with fewer factorizations.
TEST(Newton, ChordStepsReachTheSameMinimizerWithFewerFactorizations) {
  test::RosenbrockSystem r12(12);
  NewtonOptions o = tight_options();
  NewtonSolver plain(o);
  Eigen::VectorXd x_plain = Eigen::VectorXd::Constant(12, 0.5);
  const NewtonResult a = plain.solve(r12, x_plain);
  ASSERT_TRUE(a.converged()) << a.message;
  o.chord_ratio = 100.0;
  NewtonSolver chord(o);
  Eigen::VectorXd x_chord = Eigen::VectorXd::Constant(12, 0.5);
  const NewtonResult b = chord.solve(r12, x_chord);
  ASSERT_TRUE(b.converged()) << b.message;
  EXPECT_LE(b.gradient_norm, 1e-12);
  EXPECT_LT((x_chord - x_plain).lpNorm<Eigen::Infinity>(), 1e-10);
  int chord_steps = 0;
  for (std::size_t k = 0; k < b.history.size(); ++k) {
    if (b.history[k].factorizations != 0) continue;
    ++chord_steps;
    // Each kept chord step cut the gradient by the chord ratio.
    const double before = k == 0 ? b.initial_gradient_norm : b.history[k - 1].gradient_norm;
    EXPECT_LE(100.0 * b.history[k].gradient_norm, before);
  }
  EXPECT_GT(chord_steps, 0);
  EXPECT_LT(b.factorizations, a.factorizations);
  EXPECT_EQ(b.hessian_evaluations + chord_steps, b.iterations);
}

// A system declared stateless (System::stateless) forwarding to another one:
// Newton then keeps the energy and gradient of a taken full step from the
// line search's first trial instead of evaluating them again.
class StatelessView final : public System {
 public:
  explicit StatelessView(const System& inner) : inner_(&inner) {}
  Eigen::Index num_dofs() const override { return inner_->num_dofs(); }
  double energy(const Eigen::VectorXd& x) const override {
    ++energy_only_;
    return inner_->energy(x);
  }
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override { inner_->gradient(x, g); }
  double energy_gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    ++energy_gradient_;
    return inner_->energy_gradient(x, g);
  }
  void hessian(const Eigen::VectorXd& x, SpMat& H) const override { inner_->hessian(x, H); }
  bool stateless() const noexcept override { return true; }
  int energy_only_calls() const noexcept { return energy_only_; }
  int energy_gradient_calls() const noexcept { return energy_gradient_; }

 private:
  const System* inner_;
  mutable int energy_only_ = 0;
  mutable int energy_gradient_ = 0;
};

// The same iterates, bit for bit, with fewer evaluations: on Rosenbrock
// (backtracking, shifted Hessians, chord steps) every iteration ends at the
// same x with the same E and ‖g‖, and the accepted full steps cost no second
// energy pass.
TEST(Newton, AStatelessSystemReusesTheFullStepsEnergyAndGradient) {
  test::RosenbrockSystem r12(12);
  NewtonOptions o = tight_options();
  o.chord_ratio = 100.0;
  NewtonSolver plain(o);
  Eigen::VectorXd x_plain = Eigen::VectorXd::Constant(12, -0.5);
  const NewtonResult a = plain.solve(r12, x_plain);
  ASSERT_TRUE(a.converged()) << a.message;
  StatelessView view(r12);
  NewtonSolver reuse(o);
  Eigen::VectorXd x_reuse = Eigen::VectorXd::Constant(12, -0.5);
  const NewtonResult b = reuse.solve(view, x_reuse);
  ASSERT_TRUE(b.converged()) << b.message;
  EXPECT_EQ(x_reuse, x_plain);
  ASSERT_EQ(b.history.size(), a.history.size());
  int full_steps = 0;
  for (std::size_t k = 0; k < a.history.size(); ++k) {
    EXPECT_EQ(b.history[k].energy, a.history[k].energy) << "iteration " << k + 1;
    EXPECT_EQ(b.history[k].gradient_norm, a.history[k].gradient_norm) << "iteration " << k + 1;
    EXPECT_EQ(b.history[k].step, a.history[k].step) << "iteration " << k + 1;
    full_steps += a.history[k].step == 1.0 ? 1 : 0;
  }
  ASSERT_GT(full_steps, 3);
  // Every full step (chord steps included) saved one energy evaluation.
  EXPECT_EQ(a.energy_evaluations - b.energy_evaluations, full_steps);
  EXPECT_EQ(view.energy_only_calls() + view.energy_gradient_calls(), b.energy_evaluations);
  // A step shorter than 1 was taken somewhere (so the fallback path ran too).
  EXPECT_LT(full_steps, static_cast<int>(a.history.size()));
}

// --- (d) indefinite Hessian at the start ---------------------------------------

TEST_P(NewtonLineSearch, ShiftsAnIndefiniteHessianAndStillConverges) {
  test::DoubleWellChain system(50, 0.1);
  Eigen::VectorXd x(50);
  for (Eigen::Index i = 0; i < 50; ++i) x[i] = 0.1 + 0.02 * std::sin(static_cast<double>(i));
  // The starting Hessian is indefinite (diagonal 12·0.1² − 4 + 0.4 < 0).
  EXPECT_LT(dense_hessian(system, x).selfadjointView<Eigen::Lower>().eigenvalues().minCoeff(), 0.0);
  NewtonOptions o;
  o.line_search = GetParam();
  o.gradient_abs_tol = 1e-12;
  o.gradient_rel_tol = 0.0;
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_LT((x - Eigen::VectorXd::Ones(50)).lpNorm<Eigen::Infinity>(), 1e-12);
  ASSERT_FALSE(r.history.empty());
  EXPECT_GT(r.history.front().shift, 0.0);
  EXPECT_GE(r.history.front().factorizations, 2);  // unshifted attempt failed first
  EXPECT_EQ(r.history.back().shift, 0.0);          // reset once H is definite again
  EXPECT_EQ(r.history.back().factorizations, 1);
  EXPECT_GT(r.factorizations, r.iterations);
}

TEST(Newton, ShiftsAnIndefiniteHessianWithTheEigenFallbackToo) {
  test::DoubleWellChain system(30, 0.1);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(30, 0.2);
  NewtonOptions o;
  o.linear_solver = LinearSolverKind::EigenLdlt;
  o.gradient_abs_tol = 1e-12;
  o.gradient_rel_tol = 0.0;
  NewtonSolver solver(o);
  EXPECT_EQ(solver.factorization().name(), "eigen-ldlt");
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_LT((x - Eigen::VectorXd::Ones(30)).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_GT(r.history.front().shift, 0.0);
}

// Wells alternately inside (|x| < 1/√3, negative curvature) and outside the
// concave region, so H is indefinite but the clamped stand-in is definite.
Eigen::VectorXd mixed_wells(Eigen::Index n) {
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) x[i] = (i % 4 == 0) ? 1.3 : 0.1 + 0.02 * std::sin(static_cast<double>(i));
  return x;
}

TEST(Newton, StepsWithTheProjectedStandInWhereHIsIndefinite) {
  const Eigen::Index n = 40;
  test::DoubleWellChain system(n, 0.1);
  system.offer_projected_hessian(test::DoubleWellChain::StandIn::Clamp);
  EXPECT_LT(dense_hessian(system, mixed_wells(n)).selfadjointView<Eigen::Lower>().eigenvalues().minCoeff(), 0.0);
  NewtonOptions o = tight_options();

  Eigen::VectorXd x = mixed_wells(n);
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_LT((x - Eigen::VectorXd::Ones(n)).lpNorm<Eigen::Infinity>(), 1e-12);
  ASSERT_FALSE(r.history.empty());
  EXPECT_TRUE(r.history.front().projected);
  EXPECT_EQ(r.history.front().shift, 0.0);           // the stand-in factors as it is
  EXPECT_EQ(r.history.front().factorizations, 2);    // H failed, then P
  EXPECT_FALSE(r.history.back().projected);          // H again near the minimizer
  EXPECT_EQ(r.history.back().factorizations, 1);

  // The same solve shifting H instead: the same minimizer, more work.
  Eigen::VectorXd y = mixed_wells(n);
  o.use_projected_hessian = false;
  NewtonSolver shifting(o);
  const NewtonResult s = shifting.solve(system, y);
  ASSERT_TRUE(s.converged()) << s.message;
  EXPECT_LT((y - x).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_FALSE(s.history.front().projected);
  EXPECT_GT(s.history.front().shift, 0.0);
  EXPECT_LT(r.factorizations, s.factorizations);
}

// From the wells' maxima the |curvature| stand-in steps outward but the
// gradient grows: after that one step Newton shifts H instead.
TEST(Newton, StopsProjectingWhenTheStandInStopsCuttingTheGradient) {
  const Eigen::Index n = 10;
  test::DoubleWellChain system(n, 0.1);
  system.offer_projected_hessian(test::DoubleWellChain::StandIn::Absolute);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(n, 0.1);
  NewtonOptions o = tight_options();
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_LT((x - Eigen::VectorXd::Ones(n)).lpNorm<Eigen::Infinity>(), 1e-12);
  ASSERT_GE(r.history.size(), 3u);
  EXPECT_TRUE(r.history[0].projected);
  EXPECT_GT(r.history[0].gradient_norm, o.projected_progress * 4.0 * 0.1 * (1.0 - 0.01));  // did not cut |g|
  bool shifted = false;
  for (std::size_t k = 1; k < r.history.size(); ++k) {
    EXPECT_FALSE(r.history[k].projected) << "iteration " << k;
    shifted = shifted || r.history[k].shift > 0.0;
  }
  EXPECT_TRUE(shifted) << "H was still indefinite after the projected step";
}

TEST(Newton, IgnoresASystemWithoutAStandIn) {
  test::DoubleWellChain system(20, 0.1);  // offers none
  Eigen::VectorXd x = mixed_wells(20);
  NewtonOptions o = tight_options();
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  for (const NewtonIteration& it : r.history) EXPECT_FALSE(it.projected);
  EXPECT_GT(r.history.front().shift, 0.0);
}

TEST(DoubleWellChain, TheStandInIsTheHessianWithEachWellClampedAtZero) {
  test::DoubleWellChain system(6, 0.3);
  Eigen::VectorXd x(6);
  x << 0.1, 1.2, -0.3, 0.9, 0.0, -1.1;
  SpMat P;
  EXPECT_FALSE(system.projected_hessian(x, P));
  system.offer_projected_hessian(test::DoubleWellChain::StandIn::Clamp);
  ASSERT_TRUE(system.projected_hessian(x, P));
  const Eigen::MatrixXd H = dense_hessian(system, x);
  const Eigen::MatrixXd Pd(test::symmetric_from_lower(P));
  for (Eigen::Index i = 0; i < 6; ++i) {
    const double well = 12.0 * x[i] * x[i] - 4.0;
    EXPECT_NEAR(Pd(i, i) - H(i, i), std::max(0.0, -well), 1e-14) << i;
  }
  EXPECT_GE(Pd.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff(), -1e-12);
}

TEST(DoubleWellChain, GradientAndHessianMatchFiniteDifferences) {
  test::DoubleWellChain system(6, 0.3);
  auto rng = make_rng(23);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  Eigen::VectorXd x(6);
  for (Eigen::Index i = 0; i < 6; ++i) x[i] = u(rng);
  expect_derivatives_match(system, x, 1e-4, 1e-8);
}

// --- (e) +inf region -----------------------------------------------------------

TEST_P(NewtonLineSearch, StaysInsideTheAdmissibleRegion) {
  Eigen::VectorXd c(8);
  c << 1.0, 2.0, 0.5, 4.0, 3.0, 1.5, 0.25, 8.0;
  test::BarrierSystem system(c);
  // From x = 3/c the full Newton step lands at −3/c: inadmissible.
  Eigen::VectorXd x = 3.0 * c.cwiseInverse();
  NewtonOptions o;
  o.line_search = GetParam();
  o.gradient_abs_tol = 1e-12;
  o.gradient_rel_tol = 0.0;
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  const Eigen::VectorXd exact = c.cwiseInverse();
  EXPECT_LT(((x - exact).array() / exact.array()).abs().maxCoeff(), 1e-10);
  EXPECT_GT(system.inadmissible_energy_calls(), 0);      // it did hit the wall
  EXPECT_EQ(system.inadmissible_derivative_calls(), 0);  // never differentiated there
  EXPECT_EQ(system.prepare_calls(), r.iterations + 1);
  EXPECT_EQ(system.hessian_distance_from_prepared(), 0.0);
  EXPECT_LT(r.history.front().step, 1.0);
}

TEST(BarrierSystem, GradientAndHessianMatchFiniteDifferences) {
  Eigen::VectorXd c(4);
  c << 1.0, 2.0, 0.5, 4.0;
  test::BarrierSystem system(c);
  Eigen::VectorXd x(4);
  x << 0.7, 0.2, 3.0, 0.1;
  expect_derivatives_match(system, x, 1e-5, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(AllKinds, NewtonLineSearch,
                         ::testing::Values(LineSearchKind::BacktrackingThenBrent,
                                           LineSearchKind::Backtracking, LineSearchKind::Brent,
                                           LineSearchKind::GoldenSection),
                         test::line_search_test_name);

// --- (f) statuses instead of exceptions ---------------------------------------

TEST(Newton, ReportsMaxIterationsAsAStatus) {
  test::RosenbrockSystem system(2);
  Eigen::VectorXd x(2);
  x << -1.2, 1.0;
  NewtonOptions o;
  o.max_iterations = 3;
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  EXPECT_EQ(r.status, NewtonStatus::MaxIterations);
  EXPECT_FALSE(r.converged());
  EXPECT_EQ(r.iterations, 3);
  EXPECT_EQ(r.history.size(), 3u);
  EXPECT_GT(r.gradient_norm, r.gradient_tolerance);
  EXPECT_NE(r.message.find("3 iterations"), std::string::npos) << r.message;
  // x is the third iterate and the result describes it.
  EXPECT_EQ(system.energy(x), r.energy);
  EXPECT_EQ(r.history.back().energy, r.energy);
  EXPECT_LT(r.energy, r.initial_energy);
}

TEST(Newton, ReportsANonFiniteStartingEnergy) {
  Eigen::VectorXd c = Eigen::VectorXd::Ones(3);
  test::BarrierSystem system(c);
  Eigen::VectorXd x(3);
  x << 1.0, -1.0, 1.0;
  NewtonSolver solver;
  const NewtonResult r = solver.solve(system, x);
  EXPECT_EQ(r.status, NewtonStatus::NonFiniteEnergy);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(x[1], -1.0);
}

// E = ½|x|² with a wrong-signed gradient: the "descent" direction climbs.
class WrongGradientSystem final : public System {
 public:
  Eigen::Index num_dofs() const override { return 3; }
  double energy(const Eigen::VectorXd& x) const override { return 0.5 * x.squaredNorm(); }
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override { g = -x; }
  void hessian(const Eigen::VectorXd&, SpMat& H) const override {
    H = Eigen::MatrixXd::Identity(3, 3).sparseView();
  }
};

TEST(Newton, ReportsAFailedLineSearch) {
  WrongGradientSystem system;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(3, 1.0);
  NewtonSolver solver;
  const NewtonResult r = solver.solve(system, x);
  EXPECT_EQ(r.status, NewtonStatus::LineSearchFailed);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(x, Eigen::VectorXd::Constant(3, 1.0));  // unchanged
  EXPECT_NE(r.message.find("line search"), std::string::npos);
  EXPECT_NE(r.message.find("no step"), std::string::npos);
}

// E = ½x² + ε|x| with a committed feature, as a penalty contact on the fold
// of a concave support: prepare(x) commits the side s = sign(x) and the
// gradient x + εs uses it (a trial's gradient sees the side of the last
// commit). The minimum sits on the kink at 0, where no gradient is below ε:
// Newton's full steps hop across it. Every step's predicted decrease is
// below E's rounding (energy_noise_abs), so the noise test judges them.
class KinkSystem final : public System {
 public:
  static constexpr double kEps = 1e-3;
  Eigen::Index num_dofs() const override { return 1; }
  double energy(const Eigen::VectorXd& x) const override { return 0.5 * x[0] * x[0] + kEps * std::abs(x[0]); }
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override { g = Eigen::VectorXd::Constant(1, x[0] + kEps * side_); }
  void hessian(const Eigen::VectorXd&, SpMat& H) const override { H = Eigen::MatrixXd::Identity(1, 1).sparseView(); }
  void prepare(const Eigen::VectorXd& x) override { side_ = x[0] >= 0.0 ? 1.0 : -1.0; }

 private:
  double side_ = 1.0;
};

TEST(Newton, StopsAtAContactKinkWhereTheNoiseTestWasMisled) {
  NewtonOptions o;
  o.gradient_abs_tol = 1e-12;
  o.gradient_rel_tol = 0.0;
  o.energy_noise_abs = 1.0;
  o.max_iterations = 40;
  // Without an acceptable gradient the hops never end.
  {
    KinkSystem system;
    Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 0.3);
    const NewtonResult r = NewtonSolver(o).solve(system, x);
    EXPECT_FALSE(r.converged()) << r.message;
    EXPECT_EQ(r.iterations, o.max_iterations);
  }
  // With one, Newton stops after the first misleading step, within it.
  o.gradient_accept_tol = 3.0 * KinkSystem::kEps;
  KinkSystem system;
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 0.3);
  const NewtonResult r = NewtonSolver(o).solve(system, x);
  EXPECT_TRUE(r.converged()) << r.message;
  EXPECT_LE(r.iterations, 4);
  EXPECT_LE(r.gradient_norm, o.gradient_accept_tol);
  EXPECT_LE(std::abs(x[0]), KinkSystem::kEps * (1 + 1e-12));
  EXPECT_NE(r.message.find("contact kink"), std::string::npos) << r.message;
}

// A Hessian that cannot be factored whatever the shift.
class NanHessianSystem final : public System {
 public:
  Eigen::Index num_dofs() const override { return 2; }
  double energy(const Eigen::VectorXd& x) const override { return 0.5 * x.squaredNorm(); }
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override { g = x; }
  void hessian(const Eigen::VectorXd&, SpMat& H) const override {
    H = Eigen::MatrixXd::Identity(2, 2).sparseView();
    H.coeffRef(1, 1) = std::numeric_limits<double>::quiet_NaN();
  }
};

TEST(Newton, ReportsAFailedFactorization) {
  NanHessianSystem system;
  Eigen::VectorXd x = Eigen::VectorXd::Ones(2);
  NewtonSolver solver;
  const NewtonResult r = solver.solve(system, x);
  EXPECT_EQ(r.status, NewtonStatus::FactorizationFailed);
  EXPECT_EQ(r.last_factor_status, FactorStatus::NonFiniteInput);
  EXPECT_NE(r.message.find("non-finite"), std::string::npos) << r.message;
}

TEST(Newton, ReportsFactorizationFailureWhenTheShiftBudgetRunsOut) {
  test::DoubleWellChain system(10, 0.1);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(10, 0.1);
  NewtonOptions o;
  o.max_shift_attempts = 1;
  o.shift_initial = 1e-12;  // far too small for an eigenvalue of about −4
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  EXPECT_EQ(r.status, NewtonStatus::FactorizationFailed);
  EXPECT_EQ(r.last_factor_status, FactorStatus::NotPositiveDefinite);
  EXPECT_EQ(r.factorizations, 2);
}

// E = E0 + ½ Σ a_i (x_i − t_i)² with a large offset E0: near t the decrease of
// a step is far below the rounding error of E.
class OffsetQuadraticSystem final : public System {
 public:
  explicit OffsetQuadraticSystem(double offset) : offset_(offset) {}
  Eigen::Index num_dofs() const override { return 4; }
  double energy(const Eigen::VectorXd& x) const override {
    return offset_ + 0.5 * (a_.array() * (x - t_).array().square()).sum();
  }
  void gradient(const Eigen::VectorXd& x, Eigen::VectorXd& g) const override {
    g = a_.cwiseProduct(x - t_);
  }
  void hessian(const Eigen::VectorXd&, SpMat& H) const override {
    H = Eigen::MatrixXd(a_.asDiagonal()).sparseView();
  }
  Eigen::VectorXd target() const { return t_; }

 private:
  double offset_;
  Eigen::Vector4d a_{1.0, 2.0, 3.0, 4.0};
  Eigen::Vector4d t_{0.1, -0.2, 0.3, 0.4};
};

TEST(Newton, JudgesStepsBelowTheRoundingOfTheEnergyByTheGradient) {
  OffsetQuadraticSystem system(1e6);
  const Eigen::VectorXd x0 = system.target() + Eigen::VectorXd::Constant(4, 1e-6);
  NewtonOptions o;
  o.gradient_abs_tol = 1e-14;
  o.gradient_rel_tol = 0.0;
  // E changes by ~1e-11 while one ulp of E is ~1e-10: the full step is judged
  // by the gradient at the trial point (one extra gradient evaluation).
  Eigen::VectorXd x = x0;
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_EQ(r.iterations, 1);
  EXPECT_EQ(r.history[0].step, 1.0);
  EXPECT_EQ(r.history[0].line_search_evaluations, 1);
  EXPECT_EQ(r.gradient_evaluations, 3);  // start, trial, accepted point
  EXPECT_LT((x - system.target()).lpNorm<Eigen::Infinity>(), 1e-15);
  // With the rule off, only energies are compared.
  o.energy_noise = 0.0;
  solver.set_options(o);
  x = x0;
  const NewtonResult blind = solver.solve(system, x);
  EXPECT_EQ(blind.gradient_evaluations, 1 + blind.iterations);
}

// --- (h) interruption ----------------------------------------------------------

TEST(Newton, ThrowsInterruptedWhenAnInterruptIsRequested) {
  InterruptGuard guard;
  test::RosenbrockSystem system(4);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(4);
  NewtonSolver solver;
  request_interrupt();
  EXPECT_TRUE(test::throws_error([&] { (void)solver.solve(system, x); }, ErrorKind::Interrupted,
                                 {"interrupted"}));
  clear_interrupt();
  const NewtonResult r = solver.solve(system, x);
  EXPECT_TRUE(r.converged()) << r.message;
}

// --- (i) exceptions from parallel loops ----------------------------------------

TEST(Newton, AnExceptionInAParallelGradientReachesTheCallerAndLeavesTheSolverUsable) {
  auto rng = make_rng(24);
  constexpr int n = 20000;
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  std::uniform_real_distribution<double> target(-1.0, 1.0);
  Eigen::VectorXd w(n);
  Eigen::VectorXd t(n);
  for (int i = 0; i < n; ++i) {
    w[i] = weight(rng);
    t[i] = target(rng);
  }
  test::ParallelQuarticSystem system(w, t);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(n, 3.0);
  Eigen::VectorXd x = x0;
  NewtonOptions o = tight_options();
  NewtonSolver solver(o);
  system.fail_at_gradient_call = 3;  // the start, one step, then the failure
  EXPECT_THROW((void)solver.solve(system, x), std::runtime_error);
  // x holds the last accepted iterate: moved, and lower in energy.
  EXPECT_GT((x - x0).norm(), 0.0);
  EXPECT_LT(system.energy(x), system.energy(x0));

  system.fail_at_gradient_call = 0;
  const NewtonResult r = solver.solve(system, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_LT((x - t).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_EQ(solver.factorization().counts().analyses, 1);
}

}  // namespace
}  // namespace palpa
