// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// What a resting equilibrium measures (rest.hpp): one set of nodal contact
// forces, the two pressure maps they make, and the RestResult reduced from
// them at the simulation's current state.

#include <Eigen/Core>

#include "palpa/contact/traction_recovery.hpp"
#include "palpa/rest/rest.hpp"

namespace palpa::rest {

// Contact pressure is the normal traction per deformed area, what a
// pressure-mapping mat between the body and the support would read, on both
// sides, recovered from one set of nodal contact forces (both passes on a
// deformable support) by contact::TractionRecovery on the skin and on the
// support's surface where they are now. A side's forces are spread over the
// footprint of the samples that press on it from the other side: none on
// the skin of a body on a rigid support (its own samples, consistent loads:
// the lumped projection), κ·√ā on the support (and on the skin opposite a
// deformable support's samples), ā the mean rest area of the other side's
// samples in contact, κ = 3 (the spread of a uniform traction from samples
// coarser than the mesh within 1%: tests/contact). So both maps converge to the same traction
// under refinement, and each integrates to Σ|f| over the surface it is
// drawn on (the load, where the forces are parallel to it).
struct PressureRecovery {
  contact::TractionRecovery body;     // on the body's vertices, the skin's triangles
  contact::TractionRecovery support;  // on the support's surface vertices
};
// The recoveries with the footprints of the current contacts.
PressureRecovery pressure_recovery(const RestSimulation& sim);
// The footprint factor κ.
inline constexpr double kFootprintSamples = 3.0;

struct ContactPressures {
  Eigen::Matrix3Xd body_force, support_force;  // nodal contact forces, equal and opposite in sum [N]
  Eigen::VectorXd body, support;               // pressure [Pa]
  Eigen::VectorXd body_area, support_area;     // vertex areas where the surfaces are now [m²]
};
ContactPressures contact_pressures(const RestSimulation& sim, const PressureRecovery& recovery);
// With pressure_recovery(sim).
ContactPressures contact_pressures(const RestSimulation& sim);

// The part of each vertex's area in contact on each side [m²] (what the
// maps' contact areas are made of): the samples in contact, their area where
// they are now, recovered as the forces are; cp: contact_pressures() of the
// same recovery.
struct ContactAreas {
  Eigen::VectorXd body, support;
};
ContactAreas contact_areas(const RestSimulation& sim, const PressureRecovery& recovery, const ContactPressures& cp);

// The body's vertex positions (#V×3) and the support's surface vertices,
// where they are now [m].
Eigen::MatrixX3d body_points(const RestSimulation& sim);
Eigen::MatrixX3d support_points(const RestSimulation& sim);

// Fills r's measured figures at the current state: the core's pose, the
// contact force and torque, the load and the balance, the deepest
// penetration, k and the contacts, det F, a deformable support's
// displacement and base force, both pressure maps (contact_pressures) with
// their totals and pressure_metrics. The solve's own figures (iterations, solves, residual,
// message, timings) are left as they are.
void measure(const RestSimulation& sim, RestResult& r);

}  // namespace palpa::rest
