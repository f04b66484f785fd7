// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// One-dimensional line searches (thesis §5.4, §7.3.4). Each works on
// φ(s) = E(x + s·d), the energy along a search direction d, with s ≥ 0 in units
// of d (s = 1 is the full Newton step). φ may return +infinity (or NaN, treated
// the same) at inadmissible points, e.g. where an element inverts; the searches
// then shrink toward s = 0, which they assume admissible.
//
//  - backtracking_armijo: s = 1, τ, τ², ... until the Armijo condition holds
//    (5.8). One evaluation when the full step is good: the default for Newton.
//  - brent_minimize: derivative-free minimization on an interval, golden
//    sections plus parabolic interpolation; what the thesis falls back to when
//    backtracking fails (§5.4).
//  - golden_section_minimize: golden sections only, as the thesis's 3D body
//    solver does over the total energy (§7.3.4). Robust, linear convergence.

#include <functional>

namespace palpa {

// φ(s): the objective along a line, evaluated at step s.
using LineFunction = std::function<double(double)>;

struct LineSearchResult {
  double step = 0.0;     // chosen s
  double value = 0.0;    // φ(step) (+inf if no admissible point was found)
  int evaluations = 0;   // calls of φ
  bool success = false;  // see each function
};

struct BacktrackingOptions {
  double initial_step = 1.0;  // first s tried
  double c1 = 1e-4;           // Armijo constant, 0 < c1 < 1
  double shrink = 0.5;        // τ, 0 < τ < 1
  int max_evaluations = 30;
};

// Armijo backtracking. phi0 = φ(0); dphi0 = φ'(0) (= g·d, must be < 0).
// Tries s = s0 τᵏ until φ(s) ≤ phi0 + c1 s dphi0.
// success: that s is returned. Otherwise (max_evaluations reached) step is the
// sampled s with the lowest finite φ if it is below phi0, else 0 with
// value = phi0; the caller decides what to do with it.
LineSearchResult backtracking_armijo(const LineFunction& phi, double phi0, double dphi0,
                                     const BacktrackingOptions& options = {});

struct IntervalOptions {
  // The minimizer is located to within relative_tolerance·|s| + absolute_tolerance.
  double relative_tolerance = 1e-8;
  double absolute_tolerance = 1e-12;
  int max_evaluations = 100;
};

// Minimizes φ on [a, b] (a < b) by golden sections; does not evaluate φ at the
// ends. Where φ is +inf, the interval shrinks away from it (toward a when both
// inner points are inadmissible).
// success: the interval shrank to the tolerance and the best point is finite.
// step/value: the best point seen (also when success is false).
LineSearchResult golden_section_minimize(const LineFunction& phi, double a, double b,
                                         const IntervalOptions& options = {});

// Minimizes φ on [a, b] (a < b) by Brent's method: golden sections combined with
// parabolic interpolation through the three best points; superlinear on smooth
// minima. Parabolas are only fitted through finite values, and while the first
// point is inadmissible the interval shrinks toward a. Same result contract as
// golden_section_minimize.
LineSearchResult brent_minimize(const LineFunction& phi, double a, double b,
                                const IntervalOptions& options = {});

}  // namespace palpa
