// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Every material model, with representative parameters and the small-strain
// Lamé parameters it must reproduce, for the conformance suite.

#include <functional>
#include <ostream>
#include <memory>
#include <string>
#include <vector>

#include "palpa/material/material.hpp"

namespace palpa::material::test {

struct ModelCase {
  std::string name;
  std::function<std::unique_ptr<Material>()> make;
  ElasticConstants expected;   // small-strain Lamé parameters
  double lame_tolerance;       // relative tolerance on them
  bool inversion_safe = true;  // energy restoring through J <= 0 (false: StVK)
};

std::vector<ModelCase> all_model_cases();

// Size of each parameter: finite-difference steps and comparisons are per
// relative change of θk, so every derivative column of a stress is a stress
// [Pa]. Moduli are floored at `modulus` (spline control values may be near
// zero), other parameters at 1e-3 of their value.
Eigen::VectorXd param_scale(const Material& m, double modulus);

// Test names and messages show the case name only.
inline void PrintTo(const ModelCase& c, std::ostream* os) { *os << c.name; }

}  // namespace palpa::material::test
