// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/solve/line_search.hpp"

#include <cassert>
#include <cmath>
#include <limits>

namespace palpa {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// (3 − √5)/2: the golden-section fraction of an interval.
const double kGoldenFraction = 0.5 * (3.0 - std::sqrt(5.0));

// φ with NaN mapped to +inf, counting calls.
class Counted {
 public:
  explicit Counted(const LineFunction& phi) : phi_(phi) {}
  double operator()(double s) {
    ++count_;
    const double v = phi_(s);
    return std::isnan(v) ? kInf : v;
  }
  int count() const noexcept { return count_; }

 private:
  const LineFunction& phi_;
  int count_ = 0;
};

double tolerance_at(double s, const IntervalOptions& options) {
  return options.relative_tolerance * std::abs(s) + options.absolute_tolerance;
}

}  // namespace

LineSearchResult backtracking_armijo(const LineFunction& phi, double phi0, double dphi0,
                                     const BacktrackingOptions& options) {
  assert(options.c1 > 0.0 && options.c1 < 1.0);
  assert(options.shrink > 0.0 && options.shrink < 1.0);
  Counted f(phi);
  LineSearchResult best;
  best.step = 0.0;
  best.value = phi0;
  double s = options.initial_step;
  while (f.count() < options.max_evaluations) {
    const double v = f(s);
    if (v <= phi0 + options.c1 * s * dphi0) {
      return LineSearchResult{s, v, f.count(), true};
    }
    if (v < best.value) {
      best.step = s;
      best.value = v;
    }
    s *= options.shrink;
  }
  best.evaluations = f.count();
  best.success = false;
  return best;
}

LineSearchResult golden_section_minimize(const LineFunction& phi, double a, double b,
                                         const IntervalOptions& options) {
  assert(a < b);
  Counted f(phi);
  double c = a + kGoldenFraction * (b - a);
  double d = b - kGoldenFraction * (b - a);
  double fc = f(c);
  double fd = f(d);
  bool converged = false;
  while (f.count() < options.max_evaluations) {
    if (b - a <= tolerance_at(0.5 * (a + b), options)) {
      converged = true;
      break;
    }
    // `<=` also sends the search toward a when both points are +inf.
    if (fc <= fd) {
      b = d;
      d = c;
      fd = fc;
      c = a + kGoldenFraction * (b - a);
      fc = f(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = b - kGoldenFraction * (b - a);
      fd = f(d);
    }
  }
  if (!converged) converged = b - a <= tolerance_at(0.5 * (a + b), options);
  LineSearchResult r;
  r.evaluations = f.count();
  if (fc <= fd) {
    r.step = c;
    r.value = fc;
  } else {
    r.step = d;
    r.value = fd;
  }
  r.success = converged && std::isfinite(r.value);
  return r;
}

LineSearchResult brent_minimize(const LineFunction& phi, double a, double b,
                                const IntervalOptions& options) {
  assert(a < b);
  Counted f(phi);
  // x: best point so far; w: second best; v: the previous w. e: the step taken
  // two iterations ago (a parabolic step must be shorter than half of it).
  double x = a + kGoldenFraction * (b - a);
  double fx = f(x);
  // An inadmissible first point: assume the inadmissible region lies beyond it
  // and shrink toward a until an admissible point is found.
  while (!std::isfinite(fx) && f.count() < options.max_evaluations) {
    b = x;
    if (b - a <= tolerance_at(b, options)) break;
    x = a + kGoldenFraction * (b - a);
    fx = f(x);
  }
  if (!std::isfinite(fx)) {
    return LineSearchResult{x, fx, f.count(), false};
  }
  double w = x;
  double v = x;
  double fw = fx;
  double fv = fx;
  double e = 0.0;
  double step = 0.0;
  bool converged = false;
  while (f.count() < options.max_evaluations) {
    const double mid = 0.5 * (a + b);
    const double tol = tolerance_at(x, options);
    const double tol2 = 2.0 * tol;
    if (std::abs(x - mid) <= tol2 - 0.5 * (b - a)) {
      converged = true;
      break;
    }
    bool golden = true;
    if (std::abs(e) > tol && std::isfinite(fw) && std::isfinite(fv)) {
      // Vertex of the parabola through (x, fx), (w, fw), (v, fv), as x + p/q.
      const double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) {
        p = -p;
      } else {
        q = -q;
      }
      const double e_before = e;
      // Accept the parabolic step only if it falls inside (a, b) and is shorter
      // than half the step before last (else the iteration could stall).
      if (std::abs(p) < std::abs(0.5 * q * e_before) && p > q * (a - x) && p < q * (b - x)) {
        e = step;
        step = p / q;
        const double u = x + step;
        if (u - a < tol2 || b - u < tol2) step = x < mid ? tol : -tol;
        golden = false;
      }
    }
    if (golden) {
      e = x < mid ? b - x : a - x;
      step = kGoldenFraction * e;
    }
    const double u = std::abs(step) >= tol ? x + step : x + (step > 0.0 ? tol : -tol);
    const double fu = f(u);
    if (fu <= fx) {
      if (u < x) {
        b = x;
      } else {
        a = x;
      }
      v = w;
      fv = fw;
      w = x;
      fw = fx;
      x = u;
      fx = fu;
    } else {
      if (u < x) {
        a = u;
      } else {
        b = u;
      }
      if (fu <= fw || w == x) {
        v = w;
        fv = fw;
        w = u;
        fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u;
        fv = fu;
      }
    }
  }
  return LineSearchResult{x, fx, f.count(), converged};
}

}  // namespace palpa
