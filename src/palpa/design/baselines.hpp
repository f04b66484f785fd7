#pragma once
// Pressure estimates without elasticity, to set beside palpa's (thesis §7.8).
//
// Pose-to-Seat-style estimate: the body's undeformed skin, placed by the
// core's pose at an equilibrium, touches the support wherever a skin vertex
// lies inside it or within `threshold` of it; those vertices carry the load
// with a pressure field linear over the contact patch,
//   p_i = a + b (x_i − x̄) + c (y_i − ȳ)      (x, y across gravity),
// whose resultant is the equilibrium's contact force, acting through the same
// point as palpa's contact forces (force and moment balance, no elasticity);
// negative values are cut to 0 and the rest rescaled to the force. On the
// support, each vertex takes the pressure of the nearest contact skin vertex
// within 1.5 mean skin edges.

#include <Eigen/Core>

#include "palpa/rest/rest.hpp"

namespace palpa::design {

struct PressureEstimate {
  Eigen::VectorXd body_pressure;     // per body vertex [Pa]
  Eigen::VectorXd support_pressure;  // per support vertex [Pa]
  int contacts = 0;                  // skin vertices in the contact set
};

// sim: solved (its state is the equilibrium r). threshold [m] > 0.
PressureEstimate pose_to_seat(const rest::RestSimulation& sim, const rest::RestResult& r, double threshold);

}  // namespace palpa::design
