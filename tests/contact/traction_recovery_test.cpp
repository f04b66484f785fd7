// SPDX-License-Identifier: AGPL-3.0-or-later
// The pressure recovered from nodal contact forces: exact for a uniform
// traction, whole in sum, free of the aliasing of point loads finer than the
// samples they come from, kept to one side of a thin sheet, and its pullback
// against finite differences.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/finite_difference.hpp"
#include "common/square_grid.hpp"
#include "palpa/contact/traction_recovery.hpp"
#include "palpa/core/error.hpp"
#include "palpa/geometry/surface_operators.hpp"

namespace palpa {
namespace {

using contact::TractionRecovery;

// The consistent nodal loads of a traction p(x) linear over each triangle
// (∫ p φ_k dA, exact).
Eigen::VectorXd consistent_loads(const SurfaceMesh& m, const std::function<double(const Eigen::Vector3d&)>& p) {
  Eigen::VectorXd F = Eigen::VectorXd::Zero(m.V.rows());
  const Eigen::VectorXd A = geometry::face_areas(m);
  for (Eigen::Index t = 0; t < m.F.rows(); ++t) {
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) F[m.F(t, a)] += A[t] / 12.0 * (a == b ? 2.0 : 1.0) * p(m.V.row(m.F(t, b)).transpose());
    }
  }
  return F;
}

// Point loads of a uniform traction p0 from samples on a square lattice of
// spacing h (each standing for h²) over [−L/2, L/2]², each put on the grid's
// vertices by the barycentric weights of its triangle: what the other side's
// samples leave on a finer support.
Eigen::VectorXd point_loads(const SurfaceMesh& m, int n, double size, double h, double p0) {
  Eigen::VectorXd F = Eigen::VectorXd::Zero(m.V.rows());
  const double cell = size / n;
  for (double y = -0.5 * size + 0.5 * h; y < 0.5 * size; y += h) {
    for (double x = -0.5 * size + 0.5 * h; x < 0.5 * size; x += h) {
      const int i = std::min(n - 1, static_cast<int>((x + 0.5 * size) / cell));
      const int j = std::min(n - 1, static_cast<int>((y + 0.5 * size) / cell));
      const double u = (x + 0.5 * size) / cell - i, v = (y + 0.5 * size) / cell - j;
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      // square_grid's split: (a, b, d) below the diagonal u ≥ v, (a, d, c) above.
      const double f = p0 * h * h;
      if (u >= v) {
        F[a] += f * (1.0 - u);
        F[b] += f * (u - v);
        F[d] += f * v;
      } else {
        F[a] += f * (1.0 - v);
        F[d] += f * u;
        F[c] += f * (v - u);
      }
    }
  }
  return F;
}

TEST(TractionRecovery, LumpedRecoveryOfAUniformTractionIsExact) {
  const SurfaceMesh m = test::square_grid(8, 0.04, Eigen::Vector3d::Zero());
  const Eigen::VectorXd F = consistent_loads(m, [](const Eigen::Vector3d&) { return 2500.0; });
  const Eigen::VectorXd p = TractionRecovery(m.F, m.V.rows(), 0.0).recover(m.V, F);
  EXPECT_NEAR(p.minCoeff(), 2500.0, 1e-9);
  EXPECT_NEAR(p.maxCoeff(), 2500.0, 1e-9);
}

TEST(TractionRecovery, SpreadingKeepsTheForceAndAUniformTractionInside) {
  const SurfaceMesh m = test::square_grid(40, 0.08, Eigen::Vector3d::Zero());
  const Eigen::VectorXd F = consistent_loads(m, [](const Eigen::Vector3d& x) { return 1000.0 + 2e4 * x.x(); });
  const TractionRecovery r(m.F, m.V.rows(), 5e-3);
  const Eigen::VectorXd p = r.recover(m.V, F);
  const Eigen::VectorXd A = geometry::vertex_areas(m);
  EXPECT_NEAR(p.dot(A), F.sum(), 1e-12 * F.sum());
  // Inside (a footprint from the edges) a linear traction is kept.
  double worst = 0.0;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    if (m.V.row(v).cwiseAbs().maxCoeff() > 0.04 - 0.011) continue;
    worst = std::max(worst, std::abs(p[v] - (1000.0 + 2e4 * m.V(v, 0))));
  }
  EXPECT_LT(worst, 1e-9 * 1000.0);
}

TEST(TractionRecovery, PointLoadsFromCoarserSamplesDoNotAlias) {
  // A 1 mm grid under samples 1.7 mm apart: the lumped field is a beat
  // pattern; spread over κ√a = 5.1 mm (κ = 3) it is the traction again.
  const int n = 60;
  const double size = 0.06, h = 1.7e-3, p0 = 1e4;
  const SurfaceMesh m = test::square_grid(n, size, Eigen::Vector3d::Zero());
  const Eigen::VectorXd F = point_loads(m, n, size, h, p0);
  const auto interior_range = [&](const Eigen::VectorXd& p) {
    double lo = 1e300, hi = 0.0;
    for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
      if (m.V.row(v).cwiseAbs().maxCoeff() > 0.02) continue;
      lo = std::min(lo, p[v]);
      hi = std::max(hi, p[v]);
    }
    return std::pair{lo / p0, hi / p0};
  };
  const auto [lumped_lo, lumped_hi] = interior_range(TractionRecovery(m.F, m.V.rows(), 0.0).recover(m.V, F));
  EXPECT_GT(lumped_hi - lumped_lo, 0.5);  // what is fixed
  const TractionRecovery spread(m.F, m.V.rows(), 3.0 * h);
  const Eigen::VectorXd p = spread.recover(m.V, F);
  const auto [lo, hi] = interior_range(p);
  EXPECT_GT(lo, 0.99);
  EXPECT_LT(hi, 1.01);
  EXPECT_NEAR(p.dot(geometry::vertex_areas(m)), F.sum(), 1e-12 * F.sum());
}

TEST(TractionRecovery, StaysOnItsSideOfAThinSheet) {
  // Two parallel 4 cm squares 1 mm apart, joined only far away along their
  // rim (here: not at all): a force on the top stays on the top.
  SurfaceMesh top = test::square_grid(20, 0.04, Eigen::Vector3d(0, 0, 1e-3));
  SurfaceMesh bottom = test::square_grid(20, 0.04, Eigen::Vector3d::Zero());
  SurfaceMesh both;
  both.V.resize(2 * top.V.rows(), 3);
  both.V << top.V, bottom.V;
  both.F.resize(2 * top.F.rows(), 3);
  both.F << top.F, (bottom.F.array() + static_cast<int>(top.V.rows())).matrix();
  Eigen::VectorXd F = Eigen::VectorXd::Zero(both.V.rows());
  F[10 * 21 + 10] = 1.0;  // the top's centre
  const Eigen::VectorXd p = TractionRecovery(both.F, both.V.rows(), 4e-3).recover(both.V, F);
  EXPECT_GT(p.head(top.V.rows()).maxCoeff(), 0.0);
  EXPECT_EQ(p.tail(bottom.V.rows()).maxCoeff(), 0.0);
}

void check_pullback(double radius) {
  SurfaceMesh m = test::square_grid(10, 0.02, Eigen::Vector3d::Zero());
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    m.V.row(v) += Eigen::RowVector3d(0.3e-3 * u(rng), 0.3e-3 * u(rng), 1e-3 * u(rng));
  }
  Eigen::VectorXd F(m.V.rows()), g(m.V.rows());
  for (Eigen::Index v = 0; v < m.V.rows(); ++v) {
    F[v] = (v % 3 == 0) ? 0.0 : 0.5 + 0.5 * u(rng);  // some vertices without force
    g[v] = u(rng);
  }
  const TractionRecovery r(m.F, m.V.rows(), radius);
  Eigen::VectorXd d_force = Eigen::VectorXd::Zero(m.V.rows());
  Eigen::MatrixX3d d_position = Eigen::MatrixX3d::Zero(m.V.rows(), 3);
  r.add_pullback(m.V, F, g, d_force, d_position);

  // With respect to the forces that are not 0 (the others have no direction).
  const auto of_force = [&](const Eigen::VectorXd& f) { return g.dot(r.recover(m.V, f)); };
  Eigen::VectorXd numeric = test::fd_gradient(of_force, F, 1e-3);
  for (Eigen::Index v = 0; v < F.size(); ++v) {
    if (F[v] == 0.0) numeric[v] = 0.0;
  }
  EXPECT_TRUE(test::derivatives_match(d_force, numeric, 1e-8));
  const auto of_position = [&](const Eigen::VectorXd& x) {
    const Eigen::MatrixX3d V = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(x.data(), m.V.rows(), 3);
    return g.dot(r.recover(V, F));
  };
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> Vr = m.V;
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(Vr.data(), Vr.size());
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> dr = d_position;
  EXPECT_TRUE(test::derivatives_match(Eigen::Map<const Eigen::VectorXd>(dr.data(), dr.size()),
                                      test::fd_gradient(of_position, x, 1e-7), 1e-6));
}

TEST(TractionRecovery, LumpedPullbackMatchesFiniteDifferences) { check_pullback(0.0); }
TEST(TractionRecovery, SpreadPullbackMatchesFiniteDifferences) { check_pullback(4.5e-3); }

TEST(TractionRecovery, RefusesANegativeFootprintAndTrianglesOutsideTheVertices) {
  const SurfaceMesh m = test::square_grid(2, 0.01, Eigen::Vector3d::Zero());
  EXPECT_THROW(TractionRecovery(m.F, m.V.rows(), -1e-3), Error);
  EXPECT_THROW(TractionRecovery(m.F, m.V.rows(), std::nan("")), Error);
  EXPECT_THROW(TractionRecovery(m.F, 3, 1e-3), Error);
}

}  // namespace
}  // namespace palpa
