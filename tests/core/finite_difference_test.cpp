// SPDX-License-Identifier: AGPL-3.0-or-later
// The finite-difference helper itself must be able to fail.
#include <gtest/gtest.h>

#include <cmath>

#include "common/finite_difference.hpp"

namespace palpa::test {
namespace {

TEST(FiniteDifference, GradientOfAKnownFunction) {
  const ScalarFunction f = [](const Eigen::VectorXd& x) { return std::sin(x[0]) * x[1] * x[1]; };
  Eigen::VectorXd x(2);
  x << 0.3, 1.7;
  Eigen::VectorXd exact(2);
  exact << std::cos(0.3) * 1.7 * 1.7, 2.0 * std::sin(0.3) * 1.7;
  EXPECT_TRUE(derivatives_match(exact, fd_gradient(f, x, 1e-3), 1e-9));
}

TEST(FiniteDifference, DetectsAWrongDerivative) {
  const ScalarFunction f = [](const Eigen::VectorXd& x) { return x[0] * x[0]; };
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 2.0);
  const Eigen::VectorXd wrong = Eigen::VectorXd::Constant(1, 4.01);
  EXPECT_FALSE(derivatives_match(wrong, fd_gradient(f, x, 1e-4), 1e-4));
}

TEST(FiniteDifference, ZeroDerivativeFailsUnlessAllowed) {
  const ScalarFunction f = [](const Eigen::VectorXd&) { return 1.0; };
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(2);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(2);
  EXPECT_FALSE(derivatives_match(zero, fd_gradient(f, x, 1e-3), 1e-6));
  EXPECT_TRUE(derivatives_match(zero, fd_gradient(f, x, 1e-3), 1e-6, ZeroPolicy::MayBeZero));
}

TEST(FiniteDifference, ScaleIsNotFlooredAtOne) {
  // Millimetre-scale values: an absolute error of 1e-7 is large here.
  Eigen::VectorXd a(1), b(1);
  a << 1e-6;
  b << 1.1e-6;
  EXPECT_FALSE(derivatives_match(a, b, 1e-3));
}

TEST(FiniteDifference, JacobianShape) {
  const VectorFunction g = [](const Eigen::VectorXd& x) {
    Eigen::VectorXd y(3);
    y << x[0] * x[1], x[0], std::exp(x[1]);
    return y;
  };
  Eigen::VectorXd x(2);
  x << 0.5, -0.2;
  Eigen::MatrixXd exact(3, 2);
  exact << -0.2, 0.5, 1.0, 0.0, 0.0, std::exp(-0.2);
  EXPECT_TRUE(derivatives_match(exact, fd_jacobian(g, x, 1e-3), 1e-9));
}

}  // namespace
}  // namespace palpa::test
