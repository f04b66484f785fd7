// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/material/material.hpp"

#include <fmt/format.h>

#include <cmath>

#include "palpa/core/error.hpp"

namespace palpa::material {

double ElasticConstants::young() const noexcept {
  return mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu);
}

double ElasticConstants::poisson() const noexcept { return lambda / (2.0 * (lambda + mu)); }

double ElasticConstants::bulk() const noexcept { return lambda + 2.0 * mu / 3.0; }

double Material::psi(const Vec3& lambda) const {
  StretchEnergy e;
  evaluate(lambda, EvalOrder::Energy, e);
  return e.psi;
}

Vec3 Material::dpsi_dlambda(const Vec3& lambda) const {
  StretchEnergy e;
  evaluate(lambda, EvalOrder::Gradient, e);
  return e.grad;
}

Mat3 Material::d2psi_dlambda2(const Vec3& lambda) const {
  StretchEnergy e;
  evaluate(lambda, EvalOrder::Hessian, e);
  return e.hess;
}

ElasticConstants small_strain_constants(const Material& m) {
  const Mat3 h = m.d2psi_dlambda2(Vec3::Ones());
  const double diag = h.diagonal().mean();
  const double off = (h(0, 1) + h(0, 2) + h(1, 2)) / 3.0;
  return ElasticConstants{0.5 * (diag - off), off};
}

ElasticConstants lame_from_young(double young, double poisson) {
  require_positive(young, "E");
  require_poisson(poisson);
  return ElasticConstants{young / (2.0 * (1.0 + poisson)),
                          young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson))};
}

void require_finite(double value, std::string_view name) {
  if (!std::isfinite(value)) {
    throw_input_error(fmt::format("parameter {} is not finite", name), ErrorContext{},
                      "a finite value");
  }
}

void require_positive(double value, std::string_view name) {
  require_finite(value, name);
  if (!(value > 0.0)) {
    throw_input_error(fmt::format("parameter {} = {} must be positive", name, value),
                      ErrorContext{}, "a value > 0");
  }
}

void require_poisson(double nu, std::string_view name) {
  require_finite(nu, name);
  if (!(nu > -1.0 && nu < 0.5)) {
    throw_input_error(fmt::format("Poisson's ratio {} = {} is outside (-1, 0.5)", name, nu),
                      ErrorContext{}, "-1 < nu < 0.5 (0.5 would be exactly incompressible)");
  }
}

}  // namespace palpa::material
