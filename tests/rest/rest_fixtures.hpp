// SPDX-License-Identifier: AGPL-3.0-or-later
#pragma once
// Bodies and supports of the rest tests.

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <memory>

#include "palpa/material/models.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "palpa/tet/mesh.hpp"
#include "rest/block_constants.hpp"

namespace palpa::rest::test {

// A 40 × 40 × 20 mm block (E 20 kPa) hanging from its top face, its bottom
// `gap` above z = 0.
inline RestBody hanging_block(int n, double nu, double gap) {
  RestBody b;
  tet::BoxMesh box = tet::make_box_mesh(Eigen::Vector3d(-kW / 2, -kW / 2, gap),
                                        Eigen::Vector3d(kW / 2, kW / 2, kH + gap), Eigen::Vector3i(n, n, n / 2));
  b.mesh = box.mesh;
  b.attached = box.vertex_sets.at("top");
  b.materials = {{std::make_shared<material::NeoHookean>(20e3, nu), kRho}};
  return b;
}

// A `side` × `side` × `thickness` slab, top face at z = 0, its faces cut
// into near-squares of side/divisions.
inline SurfaceMesh square_slab(double side, double thickness, int divisions) {
  const int up = std::max(1, static_cast<int>(std::lround(thickness / side * divisions)));
  SurfaceMesh s =
      sim3d::make_box_surface(Eigen::Vector3d(side, side, thickness), Eigen::Vector3i(divisions, divisions, up));
  s.V.col(2).array() -= thickness;
  return s;
}

}  // namespace palpa::rest::test
