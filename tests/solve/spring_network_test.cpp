// SPDX-License-Identifier: AGPL-3.0-or-later
// Newton on nonlinear spring networks: derivatives against finite differences,
// a chain against its closed-form equilibrium, a pulled 2D mesh against force
// balance and symmetry, analysis reuse across a load continuation, and the
// equilibrium's parameter sensitivities.

#include "solve/spring_network.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/solve/parametric_system.hpp"
#include "solve/matrices.hpp"
#include "solve/test_systems.hpp"

namespace palpa {
namespace {

using test::derivatives_match;
using test::make_rng;
using test::SpringNetwork;
using SpMat = Eigen::SparseMatrix<double>;

constexpr double kSpacing = 1e-3;   // 1 mm [m]
constexpr double kStiffness = 100;  // [N/m]

// A 12×6 grid (1 mm spacing) pulled at its right edge by a total force F [N]
// along +x, shared equally by the right column's nodes except the two corners,
// which take half (a consistent edge load).
SpringNetwork pulled_grid(int nx, int ny, double total_force) {
  SpringNetwork net = SpringNetwork::grid(nx, ny, kSpacing, kStiffness);
  const double per_node = total_force / (ny - 1);
  for (int j = 0; j < ny; ++j) {
    const double share = (j == 0 || j == ny - 1) ? 0.5 * per_node : per_node;
    net.set_force(nx - 1 + nx * j, Eigen::Vector2d(share, 0.0));
  }
  return net;
}

TEST(SpringNetwork, DerivativesMatchFiniteDifferences) {
  SpringNetwork net = pulled_grid(4, 3, 0.3);
  net.set_force(5, Eigen::Vector2d(-0.1, 0.2));
  auto rng = make_rng(31);
  std::uniform_real_distribution<double> jitter(-0.25 * kSpacing, 0.25 * kSpacing);
  Eigen::VectorXd x = net.reference_dofs();
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += jitter(rng);
  const double h = 1e-4 * kSpacing;

  const Eigen::VectorXd fd_g =
      test::fd_gradient([&](const Eigen::VectorXd& y) { return net.energy(y); }, x, h);
  Eigen::VectorXd g;
  net.gradient(x, g);
  EXPECT_TRUE(derivatives_match(g, fd_g, 1e-7));
  EXPECT_DOUBLE_EQ(net.energy_gradient(x, g), net.energy(x));

  SpMat H;
  net.hessian(x, H);
  EXPECT_EQ(SpMat(H.triangularView<Eigen::StrictlyUpper>()).nonZeros(), 0);
  const Eigen::MatrixXd fd_H = test::fd_jacobian(
      [&](const Eigen::VectorXd& y) {
        Eigen::VectorXd gy;
        net.gradient(y, gy);
        return gy;
      },
      x, h);
  const Eigen::MatrixXd full = Eigen::MatrixXd(test::symmetric_from_lower(H));
  EXPECT_TRUE(derivatives_match(full, fd_H, 1e-7));

  // Squeezed to 70% along x, the springs are compressed and the true Hessian
  // is indefinite (they would rather buckle sideways); check it there too.
  Eigen::VectorXd squeezed = net.reference_dofs();
  for (Eigen::Index i = 0; i < squeezed.size(); i += 2) squeezed[i] *= 0.7;
  SpMat Hs;
  net.hessian(squeezed, Hs);
  const Eigen::MatrixXd full_squeezed = Eigen::MatrixXd(test::symmetric_from_lower(Hs));
  EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(full_squeezed).eigenvalues().minCoeff(),
            0.0);
  const Eigen::MatrixXd fd_Hs = test::fd_jacobian(
      [&](const Eigen::VectorXd& y) {
        Eigen::VectorXd gy;
        net.gradient(y, gy);
        return gy;
      },
      squeezed, h);
  EXPECT_TRUE(derivatives_match(full_squeezed, fd_Hs, 1e-7));

  // A second call only overwrites values in the same pattern.
  const int* inner_before = H.innerIndexPtr();
  net.hessian(net.reference_dofs(), H);
  EXPECT_EQ(H.innerIndexPtr(), inner_before);

  // ∂g/∂k (stiffness parameters).
  SpMat J;
  net.gradient_param_jacobian(x, J);
  ASSERT_EQ(J.rows(), net.num_dofs());
  ASSERT_EQ(J.cols(), net.num_params());
  Eigen::VectorXd theta(net.num_params());
  theta.setConstant(kStiffness);
  const Eigen::MatrixXd fd_J = test::fd_jacobian(
      [&](const Eigen::VectorXd& k) {
        SpringNetwork copy = net;
        for (int s = 0; s < copy.num_springs(); ++s) copy.set_stiffness(s, k[s]);
        Eigen::VectorXd gy;
        copy.gradient(x, gy);
        return gy;
      },
      theta, 1e-3 * kStiffness);
  EXPECT_TRUE(derivatives_match(Eigen::MatrixXd(J), fd_J, 1e-7));
}

// Chain: node 0 pinned, load F along +x at the end. Every spring carries F, so
// x_j = Σ_{i<j} (L_i + F/k_i), y_j = 0, whatever the nonlinearity elsewhere.
struct Chain {
  std::vector<double> rest{1.0e-3, 2.5e-3, 1.5e-3, 3.0e-3, 2.0e-3, 1.2e-3, 2.2e-3, 1.8e-3};
  std::vector<double> stiffness{60, 250, 120, 400, 80, 150, 300, 90};
  double force = 0.1;  // [N]: strains from 8% to 120%
};

TEST(SpringNetwork, ChainReachesItsClosedFormEquilibrium) {
  const Chain c;
  SpringNetwork net = SpringNetwork::chain(c.rest, c.stiffness);
  const int last = net.num_nodes() - 1;
  net.set_force(last, Eigen::Vector2d(c.force, 0.0));
  // Start at rest with the nodes displaced sideways (a stress-free chain has
  // no lateral stiffness, so its Hessian starts singular).
  auto rng = make_rng(32);
  std::uniform_real_distribution<double> sideways(-0.2e-3, 0.2e-3);
  Eigen::VectorXd x = net.reference_dofs();
  for (int node = 1; node <= last; ++node) x[net.dof_of(node) + 1] = sideways(rng);

  NewtonOptions o;
  o.gradient_abs_tol = 1e-13;  // [N]
  o.gradient_rel_tol = 0.0;
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(net, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_GT(r.iterations, 2);

  const Eigen::MatrixX2d p = net.positions(x);
  double expected = 0.0;
  for (int node = 1; node <= last; ++node) {
    const auto i = static_cast<std::size_t>(node - 1);
    expected += c.rest[i] + c.force / c.stiffness[i];
    EXPECT_NEAR(p(node, 0), expected, 1e-12) << "node " << node;
    EXPECT_NEAR(p(node, 1), 0.0, 1e-12) << "node " << node;
  }
  const Eigen::Vector2d reaction = net.support_reaction(x);
  EXPECT_NEAR(reaction.x(), -c.force, 1e-12);
  EXPECT_NEAR(reaction.y(), 0.0, 1e-12);
}

class PulledGrid : public ::testing::TestWithParam<LineSearchKind> {};

TEST_P(PulledGrid, ReachesAnEquilibriumInForceBalanceAndMirrorSymmetry) {
  constexpr int nx = 12;
  constexpr int ny = 6;
  constexpr double total = 0.3;  // [N]: about 30% stretch, clearly nonlinear
  SpringNetwork net = pulled_grid(nx, ny, total);
  Eigen::VectorXd x = net.reference_dofs();
  NewtonOptions o;
  o.line_search = GetParam();
  o.gradient_abs_tol = 1e-11;  // [N]
  NewtonSolver solver(o);
  const NewtonResult r = solver.solve(net, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_GT(r.iterations, 2);  // geometrically nonlinear
  EXPECT_EQ(r.analyses, 1);

  // Supports hold the load.
  const Eigen::Vector2d reaction = net.support_reaction(x);
  EXPECT_NEAR(reaction.x(), -total, 1e-9 * total);
  EXPECT_NEAR(reaction.y(), 0.0, 1e-9 * total);
  // The pull stretched the mesh: the right edge moved by tens of percent.
  const Eigen::MatrixX2d p = net.positions(x);
  const double right_edge = p(nx - 1 + nx * (ny / 2), 0);
  EXPECT_GT(right_edge, 1.2 * (nx - 1) * kSpacing);
  // Mirror symmetry about the mid line y = (ny − 1) h / 2.
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int a = i + nx * j;
      const int b = i + nx * (ny - 1 - j);
      // ‖g‖∞ ≤ 1e-11 N over a stiffness of order 1 N/m leaves ~1e-11 m.
      EXPECT_NEAR(p(a, 0), p(b, 0), 1e-10) << i << "," << j;
      EXPECT_NEAR(p(a, 1) + p(b, 1), (ny - 1) * kSpacing, 1e-10) << i << "," << j;
    }
  }
}

TEST(PulledGrid, AllLineSearchesAgreeOnTheEquilibrium) {
  SpringNetwork net = pulled_grid(10, 5, 0.4);
  Eigen::VectorXd reference = net.reference_dofs();
  NewtonOptions o;
  o.gradient_abs_tol = 1e-12;
  o.gradient_rel_tol = 0.0;
  NewtonSolver solver(o);
  ASSERT_TRUE(solver.solve(net, reference).converged());
  for (LineSearchKind kind :
       {LineSearchKind::Backtracking, LineSearchKind::Brent, LineSearchKind::GoldenSection}) {
    o.line_search = kind;
    solver.set_options(o);
    Eigen::VectorXd x = net.reference_dofs();
    ASSERT_TRUE(solver.solve(net, x).converged());
    EXPECT_LT((x - reference).lpNorm<Eigen::Infinity>(), 1e-10);
  }
}

INSTANTIATE_TEST_SUITE_P(AllKinds, PulledGrid,
                         ::testing::Values(LineSearchKind::BacktrackingThenBrent,
                                           LineSearchKind::Backtracking, LineSearchKind::Brent,
                                           LineSearchKind::GoldenSection),
                         test::line_search_test_name);

// --- (g) symbolic analysis once ----------------------------------------------

TEST(NewtonContinuation, AnalysesTheHessianPatternOnceAcrossRepeatedSolves) {
  constexpr int nx = 16;
  constexpr int ny = 8;
  SpringNetwork net = pulled_grid(nx, ny, 0.0);
  Eigen::VectorXd x = net.reference_dofs();
  NewtonOptions o;
  o.gradient_abs_tol = 1e-11;
  NewtonSolver solver(o);
  std::int64_t factorizations = 0;
  double previous_edge = 0.0;
  constexpr int kSteps = 10;
  for (int step = 1; step <= kSteps; ++step) {
    const double total = 0.05 * step;  // up to 0.5 N
    const double per_node = total / (ny - 1);
    for (int j = 0; j < ny; ++j) {
      const double share = (j == 0 || j == ny - 1) ? 0.5 * per_node : per_node;
      net.set_force(nx - 1 + nx * j, Eigen::Vector2d(share, 0.0));
    }
    const NewtonResult r = solver.solve(net, x);  // warm start from the last load
    ASSERT_TRUE(r.converged()) << "step " << step << ": " << r.message;
    EXPECT_EQ(r.analyses, step == 1 ? 1 : 0) << "step " << step;
    factorizations += r.factorizations;
    const double edge = net.positions(x)(nx - 1, 0);
    EXPECT_GT(edge, previous_edge);
    previous_edge = edge;
  }
  EXPECT_EQ(solver.factorization().counts().analyses, 1);
  EXPECT_EQ(solver.factorization().counts().factorizations, factorizations);

  // A new system object with the same topology builds the same pattern: still
  // no new analysis. Another topology is analysed once.
  SpringNetwork twin = pulled_grid(nx, ny, 1.0);
  Eigen::VectorXd y = twin.reference_dofs();
  ASSERT_TRUE(solver.solve(twin, y).converged());
  EXPECT_EQ(solver.factorization().counts().analyses, 1);
  SpringNetwork other = pulled_grid(nx + 1, ny, 1.0);
  Eigen::VectorXd z = other.reference_dofs();
  ASSERT_TRUE(solver.solve(other, z).converged());
  EXPECT_EQ(solver.factorization().counts().analyses, 2);
}

// --- sensitivities at the equilibrium -----------------------------------------

TEST(Sensitivity, SolutionParameterJacobianMatchesTheChainsClosedForm) {
  const Chain c;
  SpringNetwork net = SpringNetwork::chain(c.rest, c.stiffness);
  const int last = net.num_nodes() - 1;
  net.set_force(last, Eigen::Vector2d(c.force, 0.0));
  Eigen::VectorXd x = net.reference_dofs();
  x[net.dof_of(last) + 1] = 1e-4;
  NewtonOptions o;
  o.gradient_abs_tol = 1e-13;
  NewtonSolver solver(o);
  ASSERT_TRUE(solver.solve(net, x).converged());

  const std::int64_t analyses = solver.factorization().counts().analyses;
  ASSERT_EQ(solver.factor_hessian(net, x), FactorStatus::Ok);
  EXPECT_EQ(solver.factorization().counts().analyses, analyses);
  SpMat J;
  net.gradient_param_jacobian(x, J);
  const Eigen::MatrixXd S = solution_param_jacobian(solver.factorization(), J);
  ASSERT_EQ(S.rows(), net.num_dofs());
  ASSERT_EQ(S.cols(), net.num_params());

  // ∂x_j/∂k_i = −F/k_i² for springs i before node j; y does not move.
  Eigen::MatrixXd exact = Eigen::MatrixXd::Zero(S.rows(), S.cols());
  for (int node = 1; node <= last; ++node) {
    for (int i = 0; i < node; ++i) {
      const double k = c.stiffness[static_cast<std::size_t>(i)];
      exact(net.dof_of(node), i) = -c.force / (k * k);
    }
  }
  EXPECT_TRUE(derivatives_match(S, exact, 1e-9));

  // End to end: central differences of whole Newton solves.
  Eigen::MatrixXd fd(S.rows(), S.cols());
  for (int i = 0; i < net.num_params(); ++i) {
    const double k = c.stiffness[static_cast<std::size_t>(i)];
    const double dk = 1e-4 * k;
    Eigen::VectorXd xp = x;
    Eigen::VectorXd xm = x;
    net.set_stiffness(i, k + dk);
    ASSERT_TRUE(solver.solve(net, xp).converged());
    net.set_stiffness(i, k - dk);
    ASSERT_TRUE(solver.solve(net, xm).converged());
    net.set_stiffness(i, k);
    fd.col(i) = (xp - xm) / (2.0 * dk);
  }
  EXPECT_TRUE(derivatives_match(S, fd, 1e-6));
}

}  // namespace
}  // namespace palpa
