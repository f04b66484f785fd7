// SPDX-License-Identifier: AGPL-3.0-or-later
// The cubic interpolation weights that carry simulated forces (and their
// sensitivities) to the measured depths.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/test_support.hpp"
#include "palpa/fit/simulate.hpp"

namespace palpa::fit {
namespace {

double cubic(double x) { return 0.7 - 2.3 * x + 1.9 * x * x - 0.45 * x * x * x; }
double quadratic(double x) { return 0.3 + 1.1 * x - 0.8 * x * x; }

// Interpolates f sampled on `grid` at `x` with the weights; returns the
// largest error relative to max |f| over the points.
double relative_error(const std::vector<double>& grid, const std::vector<double>& x, double (*f)(double)) {
  const Eigen::MatrixXd w = interpolation_weights(grid, x);
  EXPECT_EQ(w.rows(), static_cast<Eigen::Index>(x.size()));
  EXPECT_EQ(w.cols(), static_cast<Eigen::Index>(grid.size()));
  Eigen::VectorXd fg(static_cast<Eigen::Index>(grid.size()));
  for (std::size_t k = 0; k < grid.size(); ++k) fg[static_cast<Eigen::Index>(k)] = f(grid[k]);
  const Eigen::VectorXd fx = w * fg;
  double err = 0.0, scale = 0.0;
  for (std::size_t j = 0; j < x.size(); ++j) {
    err = std::max(err, std::abs(fx[static_cast<Eigen::Index>(j)] - f(x[j])));
    scale = std::max(scale, std::abs(f(x[j])));
  }
  for (Eigen::Index j = 0; j < w.rows(); ++j) EXPECT_NEAR(w.row(j).sum(), 1.0, 1e-14) << "row " << j;
  return err / scale;
}

TEST(InterpolationWeights, ExactForCubicsOnUniformAndNonUniformGrids) {
  std::vector<double> uniform;
  for (int k = 0; k <= 10; ++k) uniform.push_back(0.2 * k);
  auto rng = palpa::test::make_rng(11);
  std::uniform_real_distribution<double> gap(0.05, 0.4);
  std::vector<double> nonuniform{0.0};
  for (int k = 0; k < 9; ++k) nonuniform.push_back(nonuniform.back() + gap(rng));
  for (const auto* grid : {&uniform, &nonuniform}) {
    // Points everywhere: first and last intervals, interior, on grid points, the ends.
    std::vector<double> x{grid->front(), grid->back()};
    std::uniform_real_distribution<double> where(grid->front(), grid->back());
    for (int j = 0; j < 40; ++j) x.push_back(where(rng));
    x.push_back(0.5 * ((*grid)[0] + (*grid)[1]));
    x.push_back(0.5 * ((*grid)[grid->size() - 2] + grid->back()));
    x.push_back((*grid)[3]);
    EXPECT_LT(relative_error(*grid, x, cubic), 1e-12);
  }
}

TEST(InterpolationWeights, UsesTheFourNearestPointsAndIsLocal) {
  const std::vector<double> grid{0, 1, 2, 3, 4, 5, 6};
  const Eigen::MatrixXd w = interpolation_weights(grid, {2.5, 0.25, 5.75, 3.0});
  // Interior: stencil 1..4 with the symmetric cubic weights at the midpoint.
  EXPECT_NEAR(w(0, 1), -1.0 / 16, 1e-15);
  EXPECT_NEAR(w(0, 2), 9.0 / 16, 1e-15);
  EXPECT_NEAR(w(0, 3), 9.0 / 16, 1e-15);
  EXPECT_NEAR(w(0, 4), -1.0 / 16, 1e-15);
  EXPECT_EQ(w(0, 0), 0.0);
  EXPECT_EQ(w(0, 5), 0.0);
  // First interval: stencil 0..3; last interval: stencil 3..6.
  EXPECT_EQ(w.row(1).tail(3).norm(), 0.0);
  EXPECT_NE(w(1, 3), 0.0);
  EXPECT_EQ(w.row(2).head(3).norm(), 0.0);
  EXPECT_NE(w(2, 3), 0.0);
  // A grid point: weight 1 there.
  EXPECT_NEAR(w(3, 3), 1.0, 1e-15);
  EXPECT_NEAR(w.row(3).cwiseAbs().sum(), 1.0, 1e-15);
}

TEST(InterpolationWeights, SmallGridsUseLowerDegree) {
  // Three points: exact for quadratics; two points: linear; one point: constant.
  const std::vector<double> three{0.0, 0.4, 1.0};
  EXPECT_LT(relative_error(three, {0.0, 0.1, 0.4, 0.7, 0.95, 1.0}, quadratic), 1e-12);
  const Eigen::MatrixXd w2 = interpolation_weights({1.0, 3.0}, {1.0, 1.5, 3.0});
  EXPECT_NEAR(w2(1, 0), 0.75, 1e-15);
  EXPECT_NEAR(w2(1, 1), 0.25, 1e-15);
  EXPECT_NEAR(w2(0, 0), 1.0, 1e-15);
  EXPECT_NEAR(w2(2, 1), 1.0, 1e-15);
  const Eigen::MatrixXd w1 = interpolation_weights({2.0}, {2.0});
  EXPECT_EQ(w1(0, 0), 1.0);
}

TEST(InterpolationWeights, ErrorFallsAsTheFourthPowerOfTheSpacing) {
  // sin on [0, 1]: halving the spacing divides the error by about 16.
  auto err = [](int n) {
    std::vector<double> grid, x;
    for (int k = 0; k <= n; ++k) grid.push_back(static_cast<double>(k) / n);
    for (int j = 0; j < 97; ++j) x.push_back((j + 0.5) / 97.0);
    return relative_error(grid, x, [](double t) { return std::sin(3.0 * t) + 1.0; });
  };
  const double e10 = err(10), e20 = err(20);
  EXPECT_LT(e10, 1e-4);
  EXPECT_GT(e10 / e20, 12.0);
  EXPECT_LT(e10 / e20, 20.0);
}

}  // namespace
}  // namespace palpa::fit
