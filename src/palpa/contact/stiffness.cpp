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

double corrected_stiffness(double k, double max_depth, double target, double max_factor) {
  assert(k > 0.0 && target > 0.0 && max_factor >= 1.0);
  if (!(max_depth > 0.0)) return k;  // no contact: nothing to learn from
  return k * std::clamp(max_depth / target, 1.0 / max_factor, max_factor);
}

StiffnessController::StiffnessController(const StiffnessPolicy& policy) : policy_(policy) {
  if (!(policy.target > 0.0) || !std::isfinite(policy.target)) {
    throw Error(ErrorKind::Input, fmt::format("the target penetration must be > 0 m, got {}", policy.target));
  }
  assert(policy.low <= policy.high && policy.max_factor >= 1.0 && policy.overshoot > 0.0);
}

bool StiffnessController::accepts(double max_depth) const noexcept {
  const double r = ratio(max_depth);
  return r >= policy_.low && r <= policy_.high;
}

double StiffnessController::next(double k, double max_depth) const {
  if (accepts(max_depth)) return k;
  return policy_.overshoot * corrected_stiffness(k, max_depth, policy_.target, policy_.max_factor);
}

}  // namespace palpa::contact
