// SPDX-License-Identifier: AGPL-3.0-or-later
// The outer equilibrium loop (re-solve while the model adjusts, capped), the
// tolerance model, and the adjoint solve (H⁻¹ rhs at the solution; a Hessian
// that cannot be factored is a status with a message).

#include "palpa/solve/equilibrium.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "palpa/solve/adjoint.hpp"
#include "solve/test_systems.hpp"

namespace palpa {
namespace {

TEST(EquilibriumLoop, StopsWhenTheModelIsSatisfiedByAFinalPass) {
  std::vector<Pass> passes;
  std::vector<bool> lasts;
  const EquilibriumLoopResult r = run_equilibrium_loop(
      12, [&](Pass p) { passes.push_back(p); },
      [&](int n, bool last) {
        lasts.push_back(last);
        EXPECT_EQ(n, static_cast<int>(passes.size()));
        return n < 3 ? Resolve::Areas : Resolve::None;
      });
  // Rough passes while the model changes; once satisfied, the same
  // equilibrium converged and the model asked again.
  EXPECT_EQ(r.solves, 4);
  EXPECT_FALSE(r.capped());
  EXPECT_EQ(passes, (std::vector<Pass>{Pass::Rough, Pass::Rough, Pass::Rough, Pass::Final}));
  EXPECT_EQ(lasts, (std::vector<bool>{false, false, false, false}));
}

TEST(EquilibriumLoop, AChangeAfterTheFinalPassStartsRoughPassesAnew) {
  std::vector<Pass> passes;
  const std::vector<Resolve> says{Resolve::None, Resolve::Anchors, Resolve::None, Resolve::None};
  const EquilibriumLoopResult r = run_equilibrium_loop(
      12, [&](Pass p) { passes.push_back(p); }, [&](int n, bool) { return says[static_cast<std::size_t>(n - 1)]; });
  EXPECT_EQ(r.solves, 4);
  EXPECT_FALSE(r.capped());
  EXPECT_EQ(passes, (std::vector<Pass>{Pass::Rough, Pass::Final, Pass::Rough, Pass::Final}));
}

TEST(EquilibriumLoop, CapsTheSolvesAndSaysWhatWasPending) {
  int changed = 0;
  std::vector<Pass> passes;
  const EquilibriumLoopResult r = run_equilibrium_loop(
      4, [&](Pass p) { passes.push_back(p); },
      [&](int, bool last) {
        if (!last) ++changed;  // the last solve stands with what it ran with
        return Resolve::Stiffness;
      });
  EXPECT_EQ(r.solves, 4);
  EXPECT_TRUE(r.capped());
  EXPECT_EQ(r.pending, Resolve::Stiffness);
  EXPECT_EQ(changed, 3);
  EXPECT_EQ(to_string(r.pending), "stiffness");
  EXPECT_EQ(passes.back(), Pass::Final);  // the solve that stands converged
  // One solve allowed: it is the last, and Final.
  const EquilibriumLoopResult one = run_equilibrium_loop(
      1, [](Pass p) { EXPECT_EQ(p, Pass::Final); },
      [](int, bool last) {
        EXPECT_TRUE(last);
        return Resolve::None;
      });
  EXPECT_EQ(one.solves, 1);
  EXPECT_FALSE(one.capped());
}

TEST(EquilibriumLoop, ExceptionsPropagate) {
  EXPECT_THROW(run_equilibrium_loop(3, [](Pass) { throw Error(ErrorKind::Solver, "no"); }, [](int, bool) {
    return Resolve::None;
  }),
               Error);
}

// A rough pass stops at the accepted gradient, a final one goes on to the
// aimed one; the solver's options are those of a final pass after either.
TEST(SolvePass, RoughStopsAtTheAcceptedGradientAndFinalAtTheAimedOne) {
  // E = Σ (x − t)⁴/4 + (x − t)²/2: Newton's ‖g‖ falls as its cube, over
  // several steps (2, 0.63, 0.15, 5.5e-3, 3.3e-7, 7e-20 from x − t = 1).
  test::ParallelQuarticSystem sys(Eigen::Vector3d::Ones(), Eigen::Vector3d(1.0, 0.5, -1.0));
  NewtonOptions o;
  ToleranceModel{1e-12, 1e6}.apply(o);
  NewtonSolver newton{o};
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  const NewtonResult rough = solve_pass(newton, sys, x, Pass::Rough);
  ASSERT_TRUE(rough.converged());
  EXPECT_LE(rough.gradient_norm, 1e-6);
  EXPECT_GT(rough.gradient_norm, 1e-12);
  EXPECT_EQ(newton.options().gradient_abs_tol, 1e-12);
  const NewtonResult final_pass = solve_pass(newton, sys, x, Pass::Final);
  ASSERT_TRUE(final_pass.converged());
  EXPECT_LE(final_pass.gradient_norm, 1e-12);
  EXPECT_GE(final_pass.iterations, 1);
}

TEST(ToleranceModel, SetsAbsoluteAndAcceptTolerances) {
  NewtonOptions o;
  o.gradient_rel_tol = 1e-3;
  ToleranceModel{2e-6, 50.0}.apply(o);
  EXPECT_EQ(o.gradient_abs_tol, 2e-6);
  EXPECT_DOUBLE_EQ(o.gradient_accept_tol, 1e-4);
  EXPECT_EQ(o.gradient_rel_tol, 0.0);
}

TEST(Adjoint, SolvesWithTheHessianAtTheSolution) {
  // E = ½xᵀAx − bᵀx: H = A everywhere, so z = A⁻¹ rhs.
  Eigen::SparseMatrix<double> A(3, 3);
  A.insert(0, 0) = 4.0;
  A.insert(1, 1) = 3.0;
  A.insert(2, 2) = 2.0;
  A.insert(0, 1) = A.insert(1, 0) = 1.0;
  const Eigen::Vector3d b(1.0, -2.0, 0.5);
  test::QuadraticSystem sys(A, b);
  NewtonSolver newton{NewtonOptions{}};
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  ASSERT_TRUE(newton.solve(sys, x).converged());
  const Eigen::Vector3d rhs(0.3, 1.0, -4.0);
  Eigen::VectorXd z;
  const AdjointStatus st = solve_adjoint(newton, sys, x, rhs, z);
  ASSERT_TRUE(st.ok());
  EXPECT_TRUE(st.message().empty());
  const Eigen::Vector3d expected = Eigen::Matrix3d(A).ldlt().solve(rhs);
  EXPECT_LT((z - expected).norm(), 1e-12 * expected.norm());
}

TEST(Adjoint, AnIndefiniteHessianIsAStatusWithAMessage) {
  Eigen::SparseMatrix<double> A(2, 2);
  A.insert(0, 0) = 1.0;
  A.insert(1, 1) = -1.0;
  test::QuadraticSystem sys(A, Eigen::Vector2d(1.0, 1.0));
  NewtonSolver newton{NewtonOptions{}};
  Eigen::VectorXd z = Eigen::VectorXd::Constant(2, 7.0);
  const AdjointStatus st = solve_adjoint(newton, sys, Eigen::VectorXd::Zero(2), Eigen::Vector2d(1.0, 0.0), z);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("could not be factored for the adjoint"), std::string::npos);
  EXPECT_EQ(z, Eigen::VectorXd::Constant(2, 7.0));  // untouched
}

}  // namespace
}  // namespace palpa
