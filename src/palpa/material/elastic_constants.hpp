// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Lamé parameters of (E, ν) with their derivatives, for models parametrized by
// Young's modulus and Poisson's ratio.

namespace palpa::material {

struct LameWithDerivatives {
  double mu = 0.0;       // E / (2 (1 + ν))
  double lambda = 0.0;   // E ν / ((1 + ν)(1 − 2ν))
  double dmu_dE = 0.0;
  double dmu_dnu = 0.0;
  double dlambda_dE = 0.0;
  double dlambda_dnu = 0.0;
};

inline LameWithDerivatives lame_with_derivatives(double young, double nu) noexcept {
  LameWithDerivatives l;
  const double onu = 1.0 + nu;
  const double den = onu * (1.0 - 2.0 * nu);
  l.mu = young / (2.0 * onu);
  l.lambda = young * nu / den;
  l.dmu_dE = 1.0 / (2.0 * onu);
  l.dmu_dnu = -young / (2.0 * onu * onu);
  l.dlambda_dE = nu / den;
  l.dlambda_dnu = young * (1.0 + 2.0 * nu * nu) / (den * den);
  return l;
}

}  // namespace palpa::material
