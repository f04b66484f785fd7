// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/stiffness.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>

#include "palpa/core/error.hpp"

namespace palpa::contact {

double stiffness_for_penetration(double load, double contact_points, double target) {
  if (!(load > 0.0) || !(contact_points > 0.0) || !(target > 0.0)) {
    throw_input_error(
        fmt::format("cannot choose a contact stiffness from load {} N, {} contact points and "
                    "target penetration {} m",
                    load, contact_points, target),
        ErrorContext{}.with_field("contact stiffness"), "positive load, point count and target");
  }
  return load / (2.0 * contact_points * target);
}

double stiffness_for_pressure(double pressure, double area, double target) {
  assert(target > 0.0);
  return pressure * area / (2.0 * target);
}

double corrected_stiffness(double k, double max_depth, double target, double max_factor, double exponent) {
  assert(k > 0.0 && target > 0.0 && max_factor >= 1.0 && exponent > 0.0);
  if (!(max_depth > 0.0)) return k;  // no contact: nothing to learn from
  return k * std::clamp(std::pow(max_depth / target, 1.0 / exponent), 1.0 / max_factor, max_factor);
}

double penetration_exponent(double k0, double d0, double k1, double d1, double fallback) {
  if (!(k0 > 0.0) || !(k1 > 0.0) || !(d0 > 0.0) || !(d1 > 0.0)) return fallback;
  const double dk = std::log(k1 / k0);
  if (std::abs(dk) < std::log(1.01)) return fallback;
  return std::clamp(-std::log(d1 / d0) / dk, 0.25, 1.0);
}

StiffnessController::StiffnessController(const StiffnessPolicy& policy) : policy_(policy) {
  if (!(policy.target > 0.0) || !std::isfinite(policy.target)) {
    throw Error(ErrorKind::Input, fmt::format("the target penetration must be > 0 m, got {}", policy.target));
  }
  assert(policy.low <= policy.high && policy.max_factor >= 1.0 && policy.overshoot > 0.0 && policy.exponent > 0.0);
}

bool StiffnessController::accepts(double max_depth) const noexcept {
  const double r = ratio(max_depth);
  return r >= policy_.low && r <= policy_.high;
}

double StiffnessController::next(double k, double max_depth) {
  if (accepts(max_depth)) return k;
  const double exponent = policy_.measure_exponent && last_
                              ? penetration_exponent(last_->first, last_->second, k, max_depth, policy_.exponent)
                              : policy_.exponent;
  if (max_depth > 0.0) last_.emplace(k, max_depth);
  return policy_.overshoot * corrected_stiffness(k, max_depth, policy_.target, policy_.max_factor, exponent);
}

}  // namespace palpa::contact
