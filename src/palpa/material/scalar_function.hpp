// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// One-variable functions with two derivatives, and the quadratic continuation
// that keeps energies defined (and restoring) for extreme or inverted stretches.

namespace palpa::material {

// Value and first two derivatives of a scalar function at a point.
struct Scalar3 {
  double v = 0.0;
  double d1 = 0.0;
  double d2 = 0.0;
};

// Below this argument, energies built from ln x, x^(-2/3), x^α ... switch to
// their second-order Taylor expansion at the threshold (C² continuation). It
// keeps the energy finite and growing as J -> 0 and through J < 0 (inverted
// elements), with exact derivatives. A compression to a tenth of the rest volume
// or length is far beyond soft-tissue physiology, so physical results are not
// affected.
inline constexpr double kContinuationThreshold = 0.1;

// Second-order Taylor expansion of a function known at x0 (value/derivatives in
// `at_x0`), evaluated at x.
inline Scalar3 quadratic_continuation(const Scalar3& at_x0, double x0, double x) noexcept {
  const double dx = x - x0;
  return Scalar3{at_x0.v + at_x0.d1 * dx + 0.5 * at_x0.d2 * dx * dx, at_x0.d1 + at_x0.d2 * dx,
                 at_x0.d2};
}

}  // namespace palpa::material
