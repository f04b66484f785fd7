// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// What a resting equilibrium measures (rest.hpp): one set of nodal contact
// forces, the two pressure maps they make, and the RestResult reduced from
// them at the simulation's current state.

#include <Eigen/Core>

#include "palpa/rest/rest.hpp"

namespace palpa::rest {

// The nodal contact forces (both passes on a deformable support) on the
// body's vertices (3×N) and the support's surface vertices [N], equal and
// opposite in sum, and the pressures they make, force over area (the body's
// ContactTerm::pressure_areas(), the support's vertex areas at rest) [Pa].
struct ContactPressures {
  Eigen::Matrix3Xd body_force, support_force;
  Eigen::VectorXd body, support;
};
ContactPressures contact_pressures(const RestSimulation& sim);

// Fills r's measured figures at the current state: the core's pose, the
// contact force and torque, the load and the balance, the deepest
// penetration, k and the contacts, det F, a deformable support's
// displacement and base force, both pressure maps with their totals and
// pressure_metrics. The solve's own figures (iterations, solves, residual,
// message, timings) are left as they are.
void measure(const RestSimulation& sim, RestResult& r);

}  // namespace palpa::rest
