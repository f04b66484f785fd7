#include "geometry/test_surfaces.hpp"

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace palpa::test {

SurfaceMesh icosphere(int level, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> V = {{-1, t, 0}, {1, t, 0},   {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t},   {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1},   {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> F = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : V) v.normalize();
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> midpoint;
    const auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      V.push_back((V[a] + V[b]).normalized());
      const int index = static_cast<int>(V.size()) - 1;
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<std::array<int, 3>> next;
    for (const auto& f : F) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    F = std::move(next);
  }
  SurfaceMesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(V.size()), 3);
  for (std::size_t i = 0; i < V.size(); ++i) mesh.V.row(Eigen::Index(i)) = radius * V[i].transpose();
  mesh.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (std::size_t f = 0; f < F.size(); ++f) {
    mesh.F.row(Eigen::Index(f)) << F[f][0], F[f][1], F[f][2];
  }
  return mesh;
}

SurfaceMesh square_grid(int n, double size) {
  SurfaceMesh mesh;
  mesh.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      mesh.V.row(j * (n + 1) + i) << size * (double(i) / n - 0.5), size * (double(j) / n - 0.5), 0.0;
    }
  }
  mesh.F.resize(2 * n * n, 3);
  int f = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      if ((i + j) % 2 == 0) {
        mesh.F.row(f++) << a, b, d;
        mesh.F.row(f++) << a, d, c;
      } else {
        mesh.F.row(f++) << a, b, c;
        mesh.F.row(f++) << b, d, c;
      }
    }
  }
  return mesh;
}

}  // namespace palpa::test
