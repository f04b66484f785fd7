#include "contact/shapes.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "palpa/contact/detail/triangle.hpp"
#include "palpa/contact/primitives.hpp"

namespace palpa::test {

namespace {
SurfaceMesh from_lists(const std::vector<Eigen::Vector3d>& v,
                       const std::vector<Eigen::Vector3i>& f) {
  SurfaceMesh m;
  m.V.resize(static_cast<Eigen::Index>(v.size()), 3);
  m.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = v[i];
  for (std::size_t i = 0; i < f.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = f[i];
  return m;
}
}  // namespace

SurfaceMesh cube_mesh(double h) {
  return contact::box_surface(Eigen::Vector3d::Constant(h));
}

SurfaceMesh sphere_mesh(double r, int levels) {
  return contact::sphere_surface(r, levels);
}

SurfaceMesh torus_mesh(double R, double r, int nu, int nv) {
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  const double two_pi = 2.0 * std::numbers::pi;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = two_pi * i / nu;
      const double w = two_pi * j / nv;
      v.emplace_back((R + r * std::cos(w)) * std::cos(u), (R + r * std::cos(w)) * std::sin(u),
                     r * std::sin(w));
    }
  }
  auto id = [&](int i, int j) { return ((i + nu) % nu) * nv + (j + nv) % nv; };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      f.emplace_back(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      f.emplace_back(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  }
  return from_lists(v, f);
}

SurfaceMesh bowtie_mesh() {
  // Tetrahedra (0, 1, 2, 3) and (0, 1, 4, 5) share the edge 0–1.
  const std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {0, 0, 1},  {1, 0, 0},
                                          {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  std::vector<Eigen::Vector3i> f;
  for (const auto& t : {Eigen::Vector4i(0, 1, 2, 3), Eigen::Vector4i(0, 1, 4, 5)}) {
    const Eigen::Vector3d centre =
        (v[static_cast<std::size_t>(t[0])] + v[static_cast<std::size_t>(t[1])] +
         v[static_cast<std::size_t>(t[2])] + v[static_cast<std::size_t>(t[3])]) /
        4.0;
    const int faces[4][3] = {
        {t[0], t[1], t[2]}, {t[0], t[1], t[3]}, {t[0], t[2], t[3]}, {t[1], t[2], t[3]}};
    for (const auto& q : faces) {
      const Eigen::Vector3d& a = v[static_cast<std::size_t>(q[0])];
      const Eigen::Vector3d n =
          (v[static_cast<std::size_t>(q[1])] - a).cross(v[static_cast<std::size_t>(q[2])] - a);
      if (n.dot(a - centre) > 0.0) {
        f.emplace_back(q[0], q[1], q[2]);
      } else {
        f.emplace_back(q[0], q[2], q[1]);
      }
    }
  }
  return from_lists(v, f);
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
    const auto tp = contact::detail::closest_on_triangle(
        p, mesh.V.row(mesh.F(f, 0)), mesh.V.row(mesh.F(f, 1)), mesh.V.row(mesh.F(f, 2)));
    best = std::min(best, (p - tp.point).norm());
  }
  return best;
}

}  // namespace palpa::test
