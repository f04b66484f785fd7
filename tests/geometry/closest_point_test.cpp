// SPDX-License-Identifier: AGPL-3.0-or-later
// Closest points on a triangle (each Voronoi region) and on a surface.
#include <gtest/gtest.h>

#include <random>

#include "common/test_support.hpp"
#include "geometry/test_surfaces.hpp"
#include "palpa/geometry/closest_point.hpp"

namespace palpa::geometry {
namespace {

const Eigen::Vector3d kA(0, 0, 0), kB(2, 0, 0), kC(0, 2, 0);

void expect_weights(const Eigen::Vector3d& p, const Eigen::Vector3d& expected) {
  const Eigen::Vector3d w = closest_point_on_triangle(p, kA, kB, kC);
  EXPECT_TRUE(w.isApprox(expected, 1e-14) || (w - expected).norm() < 1e-14)
      << "p = " << p.transpose() << " got " << w.transpose();
}

TEST(ClosestPoint, EveryRegionOfATriangle) {
  expect_weights({0.5, 0.5, 3.0}, {0.5, 0.25, 0.25});  // face
  expect_weights({-1, -1, 1}, {1, 0, 0});              // vertex a
  expect_weights({3, -1, 0}, {0, 1, 0});               // vertex b
  expect_weights({-1, 3, 0}, {0, 0, 1});               // vertex c
  expect_weights({1, -1, 0}, {0.5, 0.5, 0});           // edge ab
  expect_weights({-1, 1, 0}, {0.5, 0, 0.5});           // edge ac
  expect_weights({2, 2, 0}, {0, 0.5, 0.5});            // edge bc
}

TEST(ClosestPoint, DegenerateTriangleFallsBackToItsEdges) {
  const Eigen::Vector3d w =
      closest_point_on_triangle({1, 1, 0}, {0, 0, 0}, {2, 0, 0}, {1, 0, 0});
  const Eigen::Vector3d q = w(0) * Eigen::Vector3d(0, 0, 0) + w(1) * Eigen::Vector3d(2, 0, 0) +
                            w(2) * Eigen::Vector3d(1, 0, 0);
  EXPECT_NEAR((q - Eigen::Vector3d(1, 0, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(w.sum(), 1.0, 1e-15);
}

TEST(ClosestPoint, RepeatedCornerGivesAFiniteEdgePoint) {
  // a = b: the edge ab is a point, so its parameter d1/(d1 − d3) would be 0/0.
  const Eigen::Vector3d a(0, 0, 0), c(1, 0, 0), p(0.5, 1, 0);
  const TrianglePoint tp = closest_on_triangle(p, a, a, c);
  ASSERT_TRUE(tp.point.allFinite());
  ASSERT_TRUE(tp.weights.allFinite());
  EXPECT_NEAR((tp.point - Eigen::Vector3d(0.5, 0, 0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR(tp.weights.sum(), 1.0, 1e-15);
  EXPECT_GE(tp.weights.minCoeff(), 0.0);
  EXPECT_GE(tp.region, kEdgeAB);
  EXPECT_LT(tp.region, kFace);
}

TEST(ClosestPoint, CollinearTriangleRegionMatchesItsWeights) {
  // A zero-area triangle whose closest point is inside its longest edge ac.
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);
  const TrianglePoint tp = closest_on_triangle(Eigen::Vector3d(1.5, 1, 0), a, b, c);
  EXPECT_NEAR((tp.point - Eigen::Vector3d(1.5, 0, 0)).norm(), 0.0, 1e-15);
  const Eigen::Vector3d q = tp.weights(0) * a + tp.weights(1) * b + tp.weights(2) * c;
  EXPECT_NEAR((q - tp.point).norm(), 0.0, 1e-15);
  EXPECT_NE(tp.region, kFace);
}

TEST(ClosestPoint, OnASphereMatchesExhaustiveSearchAndTheRadialDistance) {
  const double r = 0.05;
  const SurfaceMesh sphere = test::icosphere(3, r);
  auto rng = test::make_rng(11);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Vector3d dir;
    for (int k = 0; k < 3; ++k) dir[k] = normal(rng);  // drawn in order on every compiler
    dir.normalize();
    const double radius = r * (0.7 + 0.6 * (trial % 7) / 6.0);
    const Eigen::Vector3d p = radius * dir;
    const SurfacePoint q = closest_point(sphere, p);
    double best = 1e300;
    for (Eigen::Index f = 0; f < sphere.F.rows(); ++f) {
      const Eigen::Vector3d w = closest_point_on_triangle(
          p, sphere.V.row(sphere.F(f, 0)), sphere.V.row(sphere.F(f, 1)), sphere.V.row(sphere.F(f, 2)));
      const Eigen::Vector3d x = w(0) * sphere.V.row(sphere.F(f, 0)).transpose() +
                                w(1) * sphere.V.row(sphere.F(f, 1)).transpose() +
                                w(2) * sphere.V.row(sphere.F(f, 2)).transpose();
      best = std::min(best, (p - x).norm());
    }
    EXPECT_NEAR(q.distance, best, 1e-15);
    EXPECT_NEAR((q.position - p).norm(), q.distance, 1e-15);
    // The inscribed polyhedron is within its sagitta (< 0.3 mm here) of the sphere.
    EXPECT_NEAR(q.distance, std::abs(radius - r), 3e-4);
    EXPECT_NEAR(q.barycentric.sum(), 1.0, 1e-14);
    EXPECT_GE(q.barycentric.minCoeff(), 0.0);
    // evaluate_at of the coordinates is the position itself.
    const Eigen::RowVectorXd x = evaluate_at(sphere, q, Eigen::MatrixXd(sphere.V));
    EXPECT_NEAR((x.transpose() - q.position).norm(), 0.0, 1e-15);
  }
}

TEST(ClosestPoint, TiesGoToTheLowestFaceIndex) {
  // Above the centre vertex of a flat grid with dyadic coordinates: the
  // distance to every triangle around it is exactly 0.5.
  const SurfaceMesh grid = test::square_grid(4, 1.0);
  const Eigen::Index centre = 2 * 5 + 2;
  Eigen::Index lowest = -1;
  for (Eigen::Index f = grid.F.rows() - 1; f >= 0; --f) {
    if ((grid.F.row(f).array() == centre).any()) lowest = f;
  }
  const SurfacePoint q =
      closest_point(grid, grid.V.row(centre).transpose() + Eigen::Vector3d(0.0, 0.0, 0.5));
  EXPECT_EQ(q.face, lowest);
  EXPECT_EQ(q.distance, 0.5);
  EXPECT_EQ(q.position, Eigen::Vector3d(grid.V.row(centre)));
}

TEST(ClosestPoint, WithATreeBuiltOnceAnswersAsOneQueryAtATime) {
  const SurfaceMesh sphere = test::icosphere(2, 0.05);
  const TriangleTree tree(sphere.V, sphere.F);
  auto rng = test::make_rng(12);
  std::uniform_real_distribution<double> u(-0.08, 0.08);
  for (int trial = 0; trial < 200; ++trial) {
    const double x = u(rng), y = u(rng), z = u(rng);  // drawn in order on every compiler
    const Eigen::Vector3d p(x, y, z);
    const SurfacePoint a = closest_point(sphere, tree, p);
    const SurfacePoint b = closest_point(sphere, p);
    EXPECT_EQ(a.face, b.face);
    EXPECT_EQ(a.barycentric, b.barycentric);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.distance, b.distance);
  }
}

}  // namespace
}  // namespace palpa::geometry
