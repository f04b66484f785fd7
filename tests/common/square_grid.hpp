// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// A flat triangulated square for tests of surface quantities.

#include <Eigen/Core>

#include "palpa/geometry/mesh.hpp"

namespace palpa::test {

// n×n squares (two triangles each) of side `size` [m] in total, centred on
// `centre` in the plane z = centre.z, wound so that the normals point up (+z).
inline SurfaceMesh square_grid(int n, double size, const Eigen::Vector3d& centre) {
  SurfaceMesh m;
  m.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      m.V.row(j * (n + 1) + i) << centre.x() + size * (i / double(n) - 0.5), centre.y() + size * (j / double(n) - 0.5),
          centre.z();
    }
  }
  m.F.resize(2 * n * n, 3);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      m.F.row(2 * (j * n + i)) << a, b, d;
      m.F.row(2 * (j * n + i) + 1) << a, d, c;
    }
  }
  return m;
}

}  // namespace palpa::test
