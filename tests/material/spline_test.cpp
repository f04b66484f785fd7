// SPDX-License-Identifier: AGPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/material/spline.hpp"

namespace palpa::material {
namespace {

NaturalCubicSpline sample_spline() {
  std::vector<double> x = NaturalCubicSpline::log_uniform_knots(0.5, 2.0, 7);
  std::vector<double> y;
  for (double xi : x) y.push_back(0.3 * std::sin(2.0 * xi) + xi * xi);
  return NaturalCubicSpline(x, y);
}

TEST(Spline, LogUniformKnots) {
  const auto x = NaturalCubicSpline::log_uniform_knots(0.5, 2.0, 5);
  ASSERT_EQ(x.size(), 5u);
  EXPECT_DOUBLE_EQ(x.front(), 0.5);
  EXPECT_DOUBLE_EQ(x.back(), 2.0);
  for (std::size_t k = 1; k < x.size(); ++k) EXPECT_NEAR(x[k] / x[k - 1], std::sqrt(2.0), 1e-12);
}

TEST(Spline, InterpolatesWithNaturalEndsAndContinuousDerivatives) {
  const NaturalCubicSpline s = sample_spline();
  const auto& x = s.knots();
  for (std::size_t k = 0; k < x.size(); ++k) EXPECT_NEAR(s.evaluate(x[k]).v, s.values()[k], 1e-12);
  EXPECT_NEAR(s.evaluate(x.front()).d2, 0.0, 1e-12);
  EXPECT_NEAR(s.evaluate(x.back()).d2, 0.0, 1e-12);
  for (std::size_t k = 1; k + 1 < x.size(); ++k) {
    const Scalar3 a = s.evaluate(x[k] - 1e-9);
    const Scalar3 b = s.evaluate(x[k] + 1e-9);
    EXPECT_NEAR(a.d1, b.d1, 1e-6);
    EXPECT_NEAR(a.d2, b.d2, 1e-6);
  }
}

TEST(Spline, ExtrapolationIsC1AndConvexWhereTheEndIsConvex) {
  const NaturalCubicSpline s = sample_spline();
  const double lo = s.knots().front();
  const double hi = s.knots().back();
  for (double end : {lo, hi}) {
    const Scalar3 in = s.evaluate(end + (end == lo ? 1e-10 : -1e-10));
    const Scalar3 out = s.evaluate(end + (end == lo ? -1e-10 : 1e-10));
    EXPECT_NEAR(in.v, out.v, 1e-8);
    EXPECT_NEAR(in.d1, out.d1, 1e-7);
  }
  // x² dominates (y'' = 2 − 1.2 sin 2x > 0): the ends are convex, so the
  // continuation has positive curvature.
  EXPECT_GT(s.evaluate(0.1).d2, 0.0);
  EXPECT_GT(s.evaluate(5.0).d2, 0.0);
  // Derivatives of the continuation are consistent.
  const auto f = [&](const Eigen::VectorXd& x) { return s.evaluate(x[0]).v; };
  for (double x : {0.2, 3.0}) {
    EXPECT_TRUE(palpa::test::derivatives_match(Eigen::VectorXd::Constant(1, s.evaluate(x).d1),
                                               palpa::test::fd_gradient(f, Eigen::VectorXd::Constant(1, x), 1e-3), 1e-9));
  }
}

TEST(Spline, BasisDerivativesMatchFiniteDifferencesInTheValues) {
  const NaturalCubicSpline s0 = sample_spline();
  const Eigen::Index n = s0.size();
  const Eigen::VectorXd y0 = Eigen::Map<const Eigen::VectorXd>(s0.values().data(), n);
  for (double x : {0.3, 0.5, 0.55, 0.9, 1.0, 1.7, 2.0, 2.6}) {
    for (int which = 0; which < 3; ++which) {
      Eigen::VectorXd analytic = Eigen::VectorXd::Zero(n);
      s0.accumulate_basis(x, which == 0, which == 1, which == 2, analytic.data(), 1);
      const auto g = [&](const Eigen::VectorXd& y) {
        NaturalCubicSpline s = s0;
        s.set_values(y.data());
        const Scalar3 v = s.evaluate(x);
        return which == 0 ? v.v : which == 1 ? v.d1 : v.d2;
      };
      // The natural end conditions make S'' vanish at the end knots for any y.
      const bool end_knot = x == s0.knots().front() || x == s0.knots().back();
      EXPECT_TRUE(palpa::test::derivatives_match(
          analytic, palpa::test::fd_gradient(g, y0, 1e-3), 1e-9,
          which == 2 && end_knot ? palpa::test::ZeroPolicy::MayBeZero
                                 : palpa::test::ZeroPolicy::MustBeNonZero,
          1.0))
          << "x = " << x << ", derivative order " << which;
    }
  }
}

TEST(Spline, RejectsBadKnots) {
  using palpa::test::throws_error;
  EXPECT_TRUE(throws_error([] { NaturalCubicSpline({1.0, 2.0}, {0.0, 1.0}, "f"); }, ErrorKind::Input,
                           {"f has 2 knots", "at least 3"}));
  EXPECT_TRUE(throws_error([] { NaturalCubicSpline({1.0, 0.9, 2.0}, {0.0, 1.0, 2.0}, "g"); },
                           ErrorKind::Input, {"not increasing"}));
  EXPECT_TRUE(throws_error([] { NaturalCubicSpline({1.0, 1.5, 2.0}, {0.0, NAN, 2.0}, "h"); },
                           ErrorKind::Input, {"not finite"}));
  EXPECT_TRUE(throws_error([] { NaturalCubicSpline::log_uniform_knots(0.0, 2.0, 5); },
                           ErrorKind::Input, {"range"}));
}

}  // namespace
}  // namespace palpa::material
