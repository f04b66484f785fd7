// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A smooth curve through scattered noisy pairs (x, y): a cubic B-spline on
// uniform knots whose coefficients pay a penalty on their third differences
// (a P-spline), the penalty's weight chosen by generalized cross-validation.
// With a heavy penalty the curve tends to the least-squares quadratic; with a
// light one it follows the data knot by knot. Used to turn the (indentation,
// force) pairs of a poke into a curve without filtering either signal in time.

#include <Eigen/Core>

#include <cstddef>
#include <span>

namespace palpa::acquire {

struct PenalizedSplineOptions {
  std::size_t segments = 20;  // uniform knot intervals over the pairs' range
  int penalty_order = 3;      // differences of this order are penalized (quadratics are free)
  // GCV with the effective degrees of freedom counted this many times: above
  // 1 it guards against the occasional under-smoothed choice on few pairs.
  double gcv_gamma = 1.4;
};

struct PenalizedSpline {
  double x0 = 0.0, h = 1.0;  // first knot of the range and knot spacing
  Eigen::VectorXd coefficients;
  double lambda = 0.0;        // the penalty weight chosen (relative to the data term's scale)
  double effective_dof = 0.0; // trace of the smoother
  double rms = 0.0;           // residual RMS of the pairs
  std::size_t pairs = 0;      // how many were fitted

  // The curve at x; beyond the range, the end segment's cubic continued.
  double operator()(double x) const;
};

// Fits the pairs (any order; more than penalty_order of them, at no fewer than
// penalty_order distinct x). The range is [min(x, lo), max(x, hi)]: pass the
// interval the curve will be evaluated on. Throws std::invalid_argument on
// fewer pairs or distinct x, or mismatched spans.
PenalizedSpline fit_penalized_spline(std::span<const double> x, std::span<const double> y, double lo, double hi,
                                     const PenalizedSplineOptions& options = {});

}  // namespace palpa::acquire
