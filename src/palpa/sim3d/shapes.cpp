#include "palpa/sim3d/shapes.hpp"

#include <cmath>
#include <fmt/format.h>
#include <map>
#include <numbers>
#include <vector>

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
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  const int n = segments;
  for (int ring = 0; ring < 2; ++ring) {
    for (int i = 0; i < n; ++i) {
      const double a = 2.0 * std::numbers::pi * i / n;
      v.emplace_back(radius * std::cos(a), radius * std::sin(a), ring == 0 ? 0.0 : height);
    }
  }
  const int bottom = static_cast<int>(v.size());
  v.emplace_back(0.0, 0.0, 0.0);
  const int top = static_cast<int>(v.size());
  v.emplace_back(0.0, 0.0, height);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    // Side: outward normals (counter-clockwise seen from outside).
    f.emplace_back(i, j, n + j);
    f.emplace_back(i, n + j, n + i);
    f.emplace_back(bottom, j, i);       // normal −z
    f.emplace_back(top, n + i, n + j);  // normal +z
  }
  return from_lists(v, f);
}

SurfaceMesh make_box_surface(const Eigen::Vector3d& size, int n) {
  require(size.allFinite() && size.minCoeff() > 0.0, "box sizes must be > 0 m");
  require(n >= 1, fmt::format("box faces need at least 1 division, got {}", n));
  std::vector<Eigen::Vector3d> v;
  std::vector<Eigen::Vector3i> f;
  std::map<std::array<long, 3>, int> index;  // grid coordinates -> vertex, shared along edges
  const auto vertex = [&](const Eigen::Vector3d& unit) {
    const std::array<long, 3> key{std::lround(unit[0] * n), std::lround(unit[1] * n), std::lround(unit[2] * n)};
    auto [it, inserted] = index.try_emplace(key, static_cast<int>(v.size()));
    if (inserted) {
      v.emplace_back((unit[0] - 0.5) * size[0], (unit[1] - 0.5) * size[1], unit[2] * size[2]);
    }
    return it->second;
  };
  // Each face: an origin corner and two in-face directions whose cross
  // product points outward (unit-cube coordinates).
  struct Face {
    Eigen::Vector3d o, a, b;
  };
  const Face faces[6] = {
      {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},  // z = 0, normal −z
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  // z = 1, +z
      {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},  // y = 0, −y
      {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  // y = 1, +y
      {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}},  // x = 0, −x
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  // x = 1, +x
  };
  for (const Face& face : faces) {
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const auto at = [&](int di, int dj) {
          return vertex(face.o + (double(i + di) / n) * face.a + (double(j + dj) / n) * face.b);
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
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p.normalize();
  std::vector<Eigen::Vector3i> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    const auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto [it, inserted] = mid.try_emplace({key.first, key.second}, static_cast<int>(v.size()));
      if (inserted) v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
      return it->second;
    };
    std::vector<Eigen::Vector3i> next;
    next.reserve(4 * f.size());
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      next.emplace_back(tri[0], a, c);
      next.emplace_back(tri[1], b, a);
      next.emplace_back(tri[2], c, b);
      next.emplace_back(a, b, c);
    }
    f = std::move(next);
  }
  for (auto& p : v) p = radius * p + Eigen::Vector3d(0.0, 0.0, radius);
  return from_lists(v, f);
}

}  // namespace palpa::sim3d
