// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// The rigid punch as a solid in the deformed (r, z) plane: a flat-ended cylinder
// of radius a whose face is at z = −d, with its rim rounded by a fillet of radius
// ρ (0 = sharp), extending upward without end:
//   S = {r <= a, z >= −d}, minus the corner outside the fillet arc centred at
//   C = (a − ρ, −d + ρ).
// The free surface of the layer may touch S but not enter it.

#include <Eigen/Core>

namespace palpa::axisym {

struct PunchShape {
  double radius = 0.0;  // a [m]
  double fillet = 0.0;  // ρ [m], 0 <= ρ < a
  double depth = 0.0;   // d [m], face at z = −d
};

// Signed distance φ from a point to the boundary of S (> 0 outside, < 0
// inside) with its gradient (unit normal pointing out of the punch) and
// Hessian. Inside, φ is minus the distance to the nearest part of the boundary
// (face, side wall or fillet arc).
struct PunchDistance {
  double phi = 0.0;                                // [m]
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();  // ∂φ/∂(r, z)
  Eigen::Matrix2d hessian = Eigen::Matrix2d::Zero();  // ∂²φ/∂(r, z)² [1/m]
};

PunchDistance punch_distance(const PunchShape& punch, const Eigen::Vector2d& p);

}  // namespace palpa::axisym

namespace palpa::axisym {

// A rigid platen in the deformed (r, z) plane: the solid half-space z >= z0
// (Above: the top platen of a compression test) or z <= z0 (Below: the base).
// Same conventions as punch_distance: φ > 0 outside the platen, the normal
// points out of it, and the Hessian is zero (a flat face).
enum class PlatenSide { Above, Below };
PunchDistance platen_distance(double z0, PlatenSide side, const Eigen::Vector2d& p);

}  // namespace palpa::axisym
