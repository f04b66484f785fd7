// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/axisym/punch.hpp"

#include <cmath>

namespace palpa::axisym {

namespace {

// Distance to a point (the fillet centre, or the sharp corner) minus `radius`.
PunchDistance from_point(const Eigen::Vector2d& v, double radius) {
  PunchDistance out;
  const double len = v.norm();
  if (len == 0.0) {  // the fillet centre itself: any outward direction
    out.phi = -radius;
    out.normal = Eigen::Vector2d(1.0, -1.0).normalized();
    return out;
  }
  out.phi = len - radius;
  out.normal = v / len;
  out.hessian = (Eigen::Matrix2d::Identity() - out.normal * out.normal.transpose()) / len;
  return out;
}

PunchDistance side_wall(double to_wall) {
  PunchDistance out;
  out.phi = to_wall;
  out.normal = Eigen::Vector2d(1.0, 0.0);
  return out;
}

PunchDistance face(double to_face) {
  PunchDistance out;
  out.phi = to_face;
  out.normal = Eigen::Vector2d(0.0, -1.0);
  return out;
}

}  // namespace

PunchDistance punch_distance(const PunchShape& s, const Eigen::Vector2d& p) {
  const double a = s.radius;
  const double rho = s.fillet;
  const double face_z = -s.depth;
  const Eigen::Vector2d corner(a - rho, face_z + rho);
  if (rho > 0.0 && p[0] > a - rho && p[1] < face_z + rho) {
    // The nearest boundary is the fillet arc (inside or outside the punch).
    return from_point(p - corner, rho);
  }
  const double to_wall = p[0] - a;       // > 0 beside the punch
  const double to_face = face_z - p[1];  // > 0 below the face
  if (to_wall > 0.0 && to_face > 0.0) return from_point(p - corner, 0.0);  // off a sharp rim
  if (to_wall > 0.0) return side_wall(to_wall);
  if (to_face > 0.0) return face(to_face);
  // Inside: the nearer of the side wall and the face.
  return to_wall > to_face ? side_wall(to_wall) : face(to_face);
}

PunchDistance platen_distance(double z0, PlatenSide side, const Eigen::Vector2d& p) {
  PunchDistance out;
  if (side == PlatenSide::Above) {
    out.phi = z0 - p[1];
    out.normal = Eigen::Vector2d(0.0, -1.0);
  } else {
    out.phi = p[1] - z0;
    out.normal = Eigen::Vector2d(0.0, 1.0);
  }
  return out;
}

}  // namespace palpa::axisym
