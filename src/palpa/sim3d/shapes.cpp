// SPDX-License-Identifier: AGPL-3.0-or-later
#include "palpa/sim3d/shapes.hpp"

#include <cmath>
#include <fmt/format.h>
#include <map>
#include <vector>

#include "palpa/contact/primitives.hpp"
#include "palpa/core/error.hpp"

namespace palpa::sim3d {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw Error(ErrorKind::Input, what);
}

SurfaceMesh from_lists(const std::vector<Eigen::Vector3d>& v, const std::vector<Eigen::Vector3i>& f) {
  SurfaceMesh m;
  m.V.resize(static_cast<Eigen::Index>(v.size()), 3);
  m.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) m.V.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  for (std::size_t i = 0; i < f.size(); ++i) m.F.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  return m;
}

}  // namespace

SurfaceMesh make_cylinder(double radius, double height, int segments) {
  require(std::isfinite(radius) && radius > 0.0, fmt::format("cylinder radius must be > 0 m, got {}", radius));
  require(std::isfinite(height) && height > 0.0, fmt::format("cylinder height must be > 0 m, got {}", height));
  require(segments >= 8, fmt::format("a cylinder needs at least 8 segments, got {}", segments));
  SurfaceMesh m = contact::cylinder_surface(radius, height, segments);
  m.V.col(2).array() += 0.5 * height;
  return m;
}

SurfaceMesh make_box_surface(const Eigen::Vector3d& size, int n) {
  require(n >= 1, fmt::format("box faces need at least 1 division, got {}", n));
  return make_box_surface(size, Eigen::Vector3i::Constant(n));
}

SurfaceMesh make_box_surface(const Eigen::Vector3d& size, const Eigen::Vector3i& n) {
  require(size.allFinite() && size.minCoeff() > 0.0, "box sizes must be > 0 m");
  require(n.minCoeff() >= 1, fmt::format("box faces need at least 1 division, got {} {} {}", n[0], n[1], n[2]));
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  std::map<std::array<long, 3>, int> index;  // grid coordinates -> vertex, shared along edges
  const auto vertex = [&](const Eigen::Vector3d& unit) {
    const std::array<long, 3> key{std::lround(unit[0] * n[0]), std::lround(unit[1] * n[1]),
                                  std::lround(unit[2] * n[2])};
    auto [it, inserted] = index.try_emplace(key, static_cast<int>(v.size()));
    if (inserted) {
      v.emplace_back((unit[0] - 0.5) * size[0], (unit[1] - 0.5) * size[1], unit[2] * size[2]);
    }
    return it->second;
  };
  // Each face: an origin corner and two in-face axes whose cross product
  // points outward (unit-cube coordinates).
  struct Face {
    Eigen::Vector3d o;
    int a, b;
  };
  const Face faces[6] = {
      {{0, 0, 0}, 1, 0},  // z = 0, normal −z
      {{0, 0, 1}, 0, 1},  // z = 1, +z
      {{0, 0, 0}, 0, 2},  // y = 0, −y
      {{0, 1, 0}, 2, 0},  // y = 1, +y
      {{0, 0, 0}, 2, 1},  // x = 0, −x
      {{1, 0, 0}, 1, 2},  // x = 1, +x
  };
  for (const Face& face : faces) {
    const int na = n[face.a], nb = n[face.b];
    const Eigen::Vector3d ea = Eigen::Vector3d::Unit(face.a), eb = Eigen::Vector3d::Unit(face.b);
    for (int i = 0; i < na; ++i) {
      for (int j = 0; j < nb; ++j) {
        const auto at = [&](int di, int dj) {
          return vertex(face.o + (double(i + di) / na) * ea + (double(j + dj) / nb) * eb);
        };
        const int p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
        f.emplace_back(p00, p10, p11);
        f.emplace_back(p00, p11, p01);
      }
    }
  }
  return from_lists(v, f);
}

SurfaceMesh make_sphere(double radius, int level) {
  require(std::isfinite(radius) && radius > 0.0, fmt::format("sphere radius must be > 0 m, got {}", radius));
  require(level >= 0 && level <= 7, fmt::format("sphere subdivision level must be 0…7, got {}", level));
  SurfaceMesh m = contact::sphere_surface(radius, level);
  m.V.col(2).array() += radius;
  return m;
}

}  // namespace palpa::sim3d
