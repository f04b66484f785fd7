// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Natural cubic spline through control points (x_k, y_k) (thesis §6.1.2,
// eq. 6.5–6.13), with exact derivatives of its value, slope and curvature with
// respect to every control value y_k (the spline is linear in y, z = M y for
// the knot curvatures).
//
// Outside [x_0, x_n] the spline continues as the parabola that matches value and
// slope at the end knot and has the mean curvature of the end interval
// (z_1/2 on the left, z_(n-1)/2 on the right): C¹ at the ends, and an energy
// built from it keeps growing when the end interval is convex.

#include <Eigen/Core>
#include <vector>

#include "palpa/material/scalar_function.hpp"

namespace palpa::material {

class NaturalCubicSpline {
 public:
  // knots: strictly increasing, at least 3, finite; values: same count, finite.
  // Throws palpa::Error (Input) otherwise, naming `name`.
  NaturalCubicSpline(std::vector<double> knots, std::vector<double> values,
                     std::string_view name = "spline");

  // `count` knots spaced uniformly in log x over [lo, hi] (0 < lo < hi).
  static std::vector<double> log_uniform_knots(double lo, double hi, int count);

  Eigen::Index size() const noexcept { return static_cast<Eigen::Index>(x_.size()); }
  const std::vector<double>& knots() const noexcept { return x_; }
  const std::vector<double>& values() const noexcept { return y_; }
  // Replaces the control values (same count).
  void set_values(const double* values);

  // Value, slope and curvature at x (any real x).
  Scalar3 evaluate(double x) const noexcept;

  // For every k: out[k * stride] += w0 ∂S/∂y_k + w1 ∂S′/∂y_k + w2 ∂S″/∂y_k at x.
  void accumulate_basis(double x, double w0, double w1, double w2, double* out,
                        Eigen::Index stride) const noexcept;

 private:
  // Interval index i with x in [x_i, x_(i+1)] (clamped).
  Eigen::Index interval(double x) const noexcept;
  void update_curvatures();

  std::vector<double> x_;
  std::vector<double> y_;
  std::vector<double> z_;   // second derivatives at the knots (z_0 = z_n = 0)
  Eigen::MatrixXd m_;       // z = M y
};

}  // namespace palpa::material
