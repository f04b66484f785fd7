// SPDX-License-Identifier: AGPL-3.0-or-later
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

namespace palpa::design {

class DesignSpace;

// A Sit & Relax-style support (thesis §7.7): the pressures of the body on
// its negative image (`frozen`, per body vertex [Pa], from an equilibrium
// there) are frozen and the design vertices are moved along their normals to
// meet the body's undeformed skin as it rests on the initial support
// (`sim`'s state: the core's pose), each vertex weighted by the frozen
// pressure where its normal line meets the skin, with a smoothness term:
//   min_t Σ_v w_v (t_v − h_v)² + λ w̄ Σ_v (L t)_v²,
// h_v the signed distance along n_v to the skin, w̄ the mean weight, L the
// umbrella Laplacian over the design vertices (the others stay put). No
// physics in the loop: one sparse solve. Where the fitted moves would make
// the support cross itself (a crease of the initial shape closing up), they
// are scaled back, halving, to the largest share that does not (as a
// workshop's shape cannot cross itself); scale 0 is refused.
struct SitAndRelaxFit {
  Eigen::MatrixX3d vertices;  // the support's vertices
  double scale = 1.0;         // the share of the fitted moves they make
};
SitAndRelaxFit sit_and_relax(const rest::RestSimulation& sim, const DesignSpace& space, const Eigen::VectorXd& frozen,
                             double lambda);

}  // namespace palpa::design
