// SPDX-License-Identifier: AGPL-3.0-or-later
#include "geometry/test_surfaces.hpp"

#include "palpa/geometry/icosphere.hpp"


namespace palpa::test {

SurfaceMesh icosphere(int level, double radius) {
  SurfaceMesh mesh = geometry::unit_icosphere(level);
  mesh.V *= radius;
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
