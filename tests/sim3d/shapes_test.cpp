// SPDX-License-Identifier: AGPL-3.0-or-later
// Rigid indenter shapes: closed, outward, with the analytic volumes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <numbers>

#include "palpa/contact/obstacle.hpp"
#include "palpa/core/error.hpp"
#include "palpa/sim3d/shapes.hpp"

namespace palpa::sim3d {
namespace {

double volume_of(const SurfaceMesh& m) {
  double v = 0.0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    v += a.dot(b.cross(c)) / 6.0;
  }
  return v;
}

TEST(Shapes, CylinderBoxAndSphereAreClosedOutwardWithTheirVolumes) {
  const int n = 48;
  const SurfaceMesh cyl = make_cylinder(0.004, 0.01, n);
  // A regular n-gon prism: (n/2) r² sin(2π/n) h.
  const double prism = 0.5 * n * 0.004 * 0.004 * std::sin(2.0 * std::numbers::pi / n) * 0.01;
  EXPECT_NEAR(volume_of(cyl), prism, 1e-12 * prism);
  const SurfaceMesh box = make_box_surface(Eigen::Vector3d(0.02, 0.01, 0.005), 3);
  EXPECT_NEAR(volume_of(box), 0.02 * 0.01 * 0.005, 1e-18);
  EXPECT_EQ(box.F.rows(), 6 * 2 * 3 * 3);
  EXPECT_NEAR(box.V.col(2).minCoeff(), 0.0, 1e-18);
  const SurfaceMesh sphere = make_sphere(0.01, 4);
  const double ball = 4.0 / 3.0 * std::numbers::pi * 1e-6;
  EXPECT_NEAR(volume_of(sphere), ball, 0.01 * ball);
  EXPECT_NEAR(sphere.V.col(2).minCoeff(), 0.0, 1e-15);
  // Each is accepted as an obstacle without flipping (closed, manifold, outward).
  for (const SurfaceMesh* m : {&cyl, &box, &sphere}) {
    const contact::Obstacle o(*m, "shape", {.flip_inward = false});
    EXPECT_FALSE(o.flipped());
    EXPECT_NEAR(o.volume(), volume_of(*m), 1e-12 * volume_of(*m));
  }
}

TEST(Shapes, RefuseBadSizes) {
  EXPECT_THROW(make_cylinder(0.0, 0.01), Error);
  EXPECT_THROW(make_cylinder(0.01, 0.01, 4), Error);
  EXPECT_THROW(make_box_surface(Eigen::Vector3d(0.01, -1.0, 0.01)), Error);
  EXPECT_THROW(make_sphere(0.01, 9), Error);
}

}  // namespace
}  // namespace palpa::sim3d
