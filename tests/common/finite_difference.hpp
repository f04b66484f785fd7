// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The one finite-difference helper every derivative test uses.
//  - fd_gradient / fd_jacobian: central differences with one Richardson step
//    (error O(h^4)), with a step h in the units of x (choose it relative to the
//    scale of x: SI positions are millimetres, stretches are ~1).
//  - derivatives_match: compares analytic vs numeric with a tolerance relative to
//    the larger of the two magnitudes (never floored at 1: SI values are small),
//    and fails if both are zero unless that is explicitly allowed, so a test whose
//    derivative vanishes cannot pass by accident.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <functional>

namespace palpa::test {

using ScalarFunction = std::function<double(const Eigen::VectorXd&)>;
using VectorFunction = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

// d f / d x at x, one entry per component of x.
Eigen::VectorXd fd_gradient(const ScalarFunction& f, const Eigen::VectorXd& x, double h);

// d g / d x at x: rows are outputs of g, columns are components of x.
Eigen::MatrixXd fd_jacobian(const VectorFunction& g, const Eigen::VectorXd& x, double h);

enum class ZeroPolicy { MustBeNonZero, MayBeZero };

// max|analytic - numeric| <= rel_tol * max(max|analytic|, max|numeric|, reference).
// `reference` is the magnitude the derivative is judged against where it may be
// (nearly) zero: e.g. the shear modulus for stresses of a material.
::testing::AssertionResult derivatives_match(const Eigen::MatrixXd& analytic,
                                             const Eigen::MatrixXd& numeric, double rel_tol,
                                             ZeroPolicy zero = ZeroPolicy::MustBeNonZero,
                                             double reference = 0.0);

}  // namespace palpa::test
