// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/primitives.hpp"

#include <cassert>
#include <cmath>
#include <numbers>
#include <vector>

#include "palpa/geometry/icosphere.hpp"

namespace palpa::contact {

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

SurfaceMesh box_surface(const Eigen::Vector3d& half) {
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < 8; ++i)
    v.emplace_back((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                   (i & 4) ? half.z() : -half.z());
  // Each face as a quad (counter-clockwise from outside), split in two.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<Eigen::Vector3i> f;
  for (const auto& q : quads) {
    f.emplace_back(q[0], q[1], q[2]);
    f.emplace_back(q[0], q[2], q[3]);
  }
  return from_lists(v, f);
}

SurfaceMesh sphere_surface(double radius, int levels) {
  SurfaceMesh m = geometry::unit_icosphere(levels);
  m.V *= radius;
  return m;
}

SurfaceMesh cylinder_surface(double radius, double length, int segments) {
  assert(segments >= 3 && radius > 0.0 && length > 0.0);
  std::vector<Eigen::Vector3d> v;
  for (int side = 0; side < 2; ++side) {
    const double z = side == 0 ? -0.5 * length : 0.5 * length;
    for (int i = 0; i < segments; ++i) {
      const double a = 2.0 * std::numbers::pi * i / segments;
      v.emplace_back(radius * std::cos(a), radius * std::sin(a), z);
    }
  }
  const int bottom = 2 * segments;
  const int top = bottom + 1;
  v.emplace_back(0.0, 0.0, -0.5 * length);
  v.emplace_back(0.0, 0.0, 0.5 * length);
  std::vector<Eigen::Vector3i> f;
  for (int i = 0; i < segments; ++i) {
    const int j = (i + 1) % segments;
    f.emplace_back(i, j, segments + j);  // side, counter-clockwise seen from outside
    f.emplace_back(i, segments + j, segments + i);
    f.emplace_back(bottom, j, i);  // bottom cap, normal −z
    f.emplace_back(top, segments + i, segments + j);
  }
  return from_lists(v, f);
}

SurfaceMesh torus_surface(double R, double r, int nu, int nv) {
  assert(nu >= 3 && nv >= 3 && R > r && r > 0.0);
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

}  // namespace palpa::contact
