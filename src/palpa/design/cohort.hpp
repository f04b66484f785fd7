// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// How one support's scores over a cohort of bodies add up to one objective.
//
// Each body i scores ζ_i on a support X; r_i = ζ_i(X) / ζ_i(X0) is its score
// normalized by its own value on the initial support, so that a heavy body
// does not outweigh a light one and every body starts at 1. The objective is
// J(r):
//   mean       (1/n) Σ r_i;
//   quantile   the mean of the worst fraction 1 − q of the bodies (the
//              conditional value at risk at level q: a body straddling the
//              boundary counts with the fraction of it that falls inside),
//              the worst body once (1 − q) n ≤ 1;
//   max        a smooth worst case, τ log((1/n) Σ exp(r_i/τ)): between the
//              mean (τ → ∞) and the largest r_i (τ → 0), within τ log n of
//              the largest.
// Every J(1, …, 1) = 1. dJ/dX = Σ_i (∂J/∂r_i) (dζ_i/dX) / ζ_i(X0): each
// body's adjoint gradient, weighed.

#include <Eigen/Core>
#include <string>

namespace palpa::design {

enum class CohortAggregate { Mean, Quantile, SmoothMax };

struct CohortObjective {
  CohortAggregate aggregate = CohortAggregate::Mean;
  double quantile = 0.9;    // q of `quantile`, in [0, 1)
  double sharpness = 0.05;  // τ of `max`, > 0
};

// J(r) and, if asked, ∂J/∂r. Throws palpa::Error (Input) for a quantile
// outside [0, 1), τ ≤ 0 or no body.
double cohort_value(const CohortObjective& objective, const Eigen::VectorXd& r, Eigen::VectorXd* weights = nullptr);

// "mean", "quantile", "max".
std::string to_string(CohortAggregate a);
// Throws palpa::Error (Input) naming `context` for another name.
CohortAggregate parse_cohort_aggregate(const std::string& name, const std::string& context);

}  // namespace palpa::design
