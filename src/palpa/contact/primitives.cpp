// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/contact/primitives.hpp"

#include <cassert>
#include <cmath>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

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
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& p : v) p.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
      const int id = static_cast<int>(v.size()) - 1;
      mid.emplace(key, id);
      return id;
    };
    std::vector<Eigen::Vector3i> next;
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]);
      const int b = midpoint(tri[1], tri[2]);
      const int c = midpoint(tri[2], tri[0]);
      next.emplace_back(tri[0], a, c);
      next.emplace_back(tri[1], b, a);
      next.emplace_back(tri[2], c, b);
      next.emplace_back(a, b, c);
    }
    f = std::move(next);
  }
  for (auto& p : v) p *= radius;
  return from_lists(v, f);
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
