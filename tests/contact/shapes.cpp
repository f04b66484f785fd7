// SPDX-License-Identifier: AGPL-3.0-or-later
#include "contact/shapes.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "palpa/contact/primitives.hpp"
#include "palpa/geometry/closest_point_on_triangle.hpp"

namespace palpa::test {

SurfaceMesh cube_mesh(double h) {
  return contact::box_surface(Eigen::Vector3d::Constant(h));
}

SurfaceMesh sphere_mesh(double r, int levels) {
  return contact::sphere_surface(r, levels);
}

SurfaceMesh torus_mesh(double R, double r, int nu, int nv) {
  return contact::torus_surface(R, r, nu, nv);
}

SurfaceMesh bowtie_mesh() {
  // Tetrahedra (0, 1, 2, 3) and (0, 1, 4, 5) share the edge 0–1; each face is
  // wound so that its normal points away from its tetrahedron's centre.
  SurfaceMesh m;
  m.V.resize(6, 3);
  m.V << 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0;
  m.F.resize(8, 3);
  int row = 0;
  for (const Eigen::Vector4i& t : {Eigen::Vector4i(0, 1, 2, 3), Eigen::Vector4i(0, 1, 4, 5)}) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) centre += m.V.row(t[k]).transpose() / 4.0;
    for (const Eigen::Vector3i& q :
         {Eigen::Vector3i(t[0], t[1], t[2]), Eigen::Vector3i(t[0], t[1], t[3]),
          Eigen::Vector3i(t[0], t[2], t[3]), Eigen::Vector3i(t[1], t[2], t[3])}) {
      const Eigen::Vector3d a = m.V.row(q[0]);
      const Eigen::Vector3d n =
          (m.V.row(q[1]).transpose() - a).cross(m.V.row(q[2]).transpose() - a);
      m.F.row(row++) = n.dot(a - centre) > 0.0 ? q : Eigen::Vector3i(q[0], q[2], q[1]);
    }
  }
  return m;
}

double winding_number(const SurfaceMesh& mesh, const Eigen::Vector3d& p) {
  double total = 0.0;
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)).transpose() - p;
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1)).transpose() - p;
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2)).transpose() - p;
    const double la = a.norm();
    const double lb = b.norm();
    const double lc = c.norm();
    // Solid angle of the triangle seen from p (Van Oosterom & Strackee).
    total += 2.0 * std::atan2(a.dot(b.cross(c)),
                              la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb);
  }
  return total / (4.0 * std::numbers::pi);
}

double brute_distance(const SurfaceMesh& mesh, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index f = 0; f < mesh.F.rows(); ++f) {
    const auto tp = geometry::closest_on_triangle(
        p, mesh.V.row(mesh.F(f, 0)), mesh.V.row(mesh.F(f, 1)), mesh.V.row(mesh.F(f, 2)));
    best = std::min(best, (p - tp.point).norm());
  }
  return best;
}

}  // namespace palpa::test
