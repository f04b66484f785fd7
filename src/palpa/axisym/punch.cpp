#include "palpa/axisym/punch.hpp"

#include <cmath>

namespace palpa::axisym {

PunchDistance punch_distance(const PunchShape& s, const Eigen::Vector2d& p) {
  const double a = s.radius;
  const double rho = s.fillet;
  const double face = -s.depth;
  const Eigen::Vector2d corner(a - rho, face + rho);
  PunchDistance out;
  const bool in_corner_zone = p[0] > a - rho && p[1] < face + rho;
  if (in_corner_zone && rho > 0.0) {
    // Nearest boundary is the fillet arc (inside or outside the punch).
    const Eigen::Vector2d v = p - corner;
    const double len = v.norm();
    if (len > 0.0) {
      out.phi = len - rho;
      out.normal = v / len;
      out.hessian = (Eigen::Matrix2d::Identity() - out.normal * out.normal.transpose()) / len;
      return out;
    }
    out.phi = -rho;
    out.normal = Eigen::Vector2d(1.0, -1.0).normalized();
    return out;
  }
  const double to_wall = p[0] - a;     // > 0 beside the punch
  const double to_face = face - p[1];  // > 0 below the face
  if (to_wall > 0.0 || to_face > 0.0) {
    // Outside: below the face (r <= a − ρ), beside the wall (z >= −d + ρ), or,
    // for a sharp rim, diagonally off the corner.
    if (to_wall > 0.0 && to_face > 0.0) {
      const Eigen::Vector2d v(to_wall, -to_face);
      const double len = v.norm();
      out.phi = len;
      out.normal = v / len;
      out.hessian = (Eigen::Matrix2d::Identity() - out.normal * out.normal.transpose()) / len;
    } else if (to_wall > 0.0) {
      out.phi = to_wall;
      out.normal = Eigen::Vector2d(1.0, 0.0);
    } else {
      out.phi = to_face;
      out.normal = Eigen::Vector2d(0.0, -1.0);
    }
    return out;
  }
  // Inside: the nearer of the side wall and the face.
  if (-to_wall < -to_face) {
    out.phi = to_wall;
    out.normal = Eigen::Vector2d(1.0, 0.0);
  } else {
    out.phi = to_face;
    out.normal = Eigen::Vector2d(0.0, -1.0);
  }
  return out;
}

}  // namespace palpa::axisym
