// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// How sure a fit is: standard errors, 95% intervals and correlations of the
// fitted parameters and of the small-strain E and ν, from the Jacobian of the
// residuals at the minimum; and of the layer depth, from ε over the searched
// depths. A small pure kernel over numbers the fit already has.
//
// Least squares with m data residuals r(x) and n free coordinates x: near the
// minimum ε(x) ≈ ε̂ + (x − x̂)ᵀ JᵀJ (x − x̂), so with independent errors of one
// standard deviation σ, estimated as s² = ε̂/(m − n), the coordinates'
// covariance is s² (JᵀJ)⁻¹ (Gauss–Newton; the rows of the spline curvature
// regularization count as prior information, and n is then the effective
// number of parameters tr(J_d (JᵀJ)⁻¹ J_dᵀ) over the data rows J_d). A quantity g(x) (a material
// parameter, E, ν) has variance G C Gᵀ with G = ∂g/∂x (the delta method), and
// the 95% interval ĝ ± t(0.975, m − n)·se; ν's interval is the image of its
// coordinate's interval, so it stays inside its range. A parameter at an end
// of its range is held there; a quantity that changes along a direction of
// the parameters the curves do not see (JᵀJ singular there: a spline's
// knots outside the stretches reached) is reported as undetermined.
//
// The layer depth is not a coordinate: ε(D) at the searched depths is a
// profile (every other parameter fitted at each D). A parabola through the
// best depth and its two neighbours gives the minimum D* and the curvature
// ε″, and Var(D) = 2 s²/ε″; E's dependence on D along the profile, dE/dD,
// adds (dE/dD)² Var(D) to E's variance and gives the E–D correlation.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "palpa/fit/optimize.hpp"

namespace palpa::fit {

struct Estimate {
  std::string name;            // "E", "nu", "C10", "alpha[1]", "layer_depth"
  double value = 0.0;          // SI
  double standard_error = 0.0;
  double lo = 0.0, hi = 0.0;   // 95% interval
};

struct Uncertainty {
  bool defined = false;
  std::string why_not;         // when not defined (too few points, a parameter the data do not see)
  int points = 0;              // m (data residuals)
  int free_parameters = 0;     // n (not held at a bound)
  double effective_parameters = 0.0;  // tr H: n, or fewer with regularization
  double sigma = 0.0;          // s = √(ε̂/(m − n)), in the residuals' unit
  double t95 = 0.0;            // t(0.975, m − n)
  // The free material parameters (classic models; not the spline's knot
  // values), then E and nu (small strain), then layer_depth (depth search).
  std::vector<Estimate> estimates;
  Eigen::MatrixXd correlation;  // between estimates, same order
  std::vector<std::string> warnings;  // pairs that trade off (|correlation| > 0.95)
  // Parameters at an end of their range, held there (their estimates, and ν's
  // when it is one of them, have no interval).
  std::vector<std::string> held;
  // Estimates the curves do not determine (they move along a direction of the
  // parameters no curve responds to); no interval.
  std::vector<std::string> undetermined;

  const Estimate* find(const std::string& name) const;
};

// Student's t quantile t(p, dof) for p in (0.5, 1) (Cornish–Fisher expansion
// about the normal quantile, five terms; within 3e-4 relative for dof ≥ 3).
double student_t_quantile(double p, double dof);

// At the minimum x̂ of `p` with its evaluation `e` there (residuals and
// Jacobian). `report_parameters`: list the material parameters (false for a
// spline, whose knot values mean little one by one).
Uncertainty fit_uncertainty(const TrainingProblem& p, const Eigen::VectorXd& x, const Evaluation& e,
                            bool report_parameters);

// Stage 1 alone: the modulus scale s is the one coordinate (E = s E0).
Uncertainty modulus_uncertainty(double objective, int points, double scale, double sum_sim_squared,
                                double young_at_scale_one, double poisson);

// Adds the layer depth from ε and E at the searched depths (index `best` the
// lowest ε; sigma: the residual standard deviation of that profile, dof its
// degrees of freedom): its
// estimate, E's variance along the profile and their correlation; a warning
// when the best depth is an end of the range or ε is not curved there.
void add_depth_uncertainty(Uncertainty& u, const std::vector<double>& depths, const std::vector<double>& objectives,
                           const std::vector<double>& young, std::size_t best, double sigma, double dof);

}  // namespace palpa::fit
