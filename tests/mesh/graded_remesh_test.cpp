// SPDX-License-Identifier: AGPL-3.0-or-later
// A skin refined toward a contact: the levels' edges and reaches, and a
// sphere above a plane meshed at 3 mm near the plane and 8 mm elsewhere,
// closed and manifold.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "common/test_support.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/graded_remesh.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::mesh {
namespace {

using test::throws_error;

TEST(GradingLevels, EqualRatiosWithinTheGrowthAndBandsOfTwoEdges) {
  const GradingLevels l = grading_levels(7e-3, {3e-3, 18e-3});
  ASSERT_EQ(l.edge.size(), 4u);  // 7 / 3 needs three steps of at most 1.5
  EXPECT_DOUBLE_EQ(l.edge.front(), 7e-3);
  EXPECT_DOUBLE_EQ(l.edge.back(), 3e-3);
  for (std::size_t k = 1; k < l.edge.size(); ++k) {
    EXPECT_NEAR(l.edge[k - 1] / l.edge[k], std::cbrt(7.0 / 3.0), 1e-12);
  }
  EXPECT_DOUBLE_EQ(l.reach.back(), 18e-3);
  for (std::size_t k = 1; k + 1 < l.edge.size(); ++k) EXPECT_NEAR(l.reach[k], l.reach[k + 1] + 2.0 * l.edge[k], 1e-15);
  EXPECT_EQ(grading_levels(3e-3, {3e-3, 1e-2}).edge.size(), 1u);  // nothing finer to make
  EXPECT_TRUE(throws_error([] { grading_levels(7e-3, {0.0, 1e-2}); }, ErrorKind::Input, {"not positive"}));
  EXPECT_TRUE(throws_error([] { grading_levels(7e-3, {3e-3, -1e-3}); }, ErrorKind::Input, {"negative"}));
}

// Mean edge length of the triangles whose centroid is at a height in [lo, hi).
double mean_edge(const SurfaceMesh& m, double lo, double hi) {
  double sum = 0.0;
  int n = 0;
  for (Eigen::Index f = 0; f < m.F.rows(); ++f) {
    const double z = (m.V(m.F(f, 0), 2) + m.V(m.F(f, 1), 2) + m.V(m.F(f, 2), 2)) / 3.0;
    if (z < lo || z >= hi) continue;
    for (int c = 0; c < 3; ++c) sum += (m.V.row(m.F(f, c)) - m.V.row(m.F(f, (c + 1) % 3))).norm();
    n += 3;
  }
  return sum / std::max(n, 1);
}

TEST(RemeshGraded, FineNearTheContactCoarseAwayClosed) {
  // A 100 mm sphere whose lowest point touches the plane z = −50 mm.
  BodyOptions o;
  o.shape = BodyShape::Sphere;
  o.size = Eigen::Vector3d::Constant(0.1);
  o.edge_length = 8e-3;
  const SurfaceMesh coarse = remesh_surface(make_body(o), 8e-3);
  const ContactDistance to_plane = [](const Eigen::MatrixX3d& p) { return (p.col(2).array() + 0.05).matrix().eval(); };
  const SurfaceMesh graded = remesh_graded(coarse, 8e-3, {3e-3, 10e-3}, to_plane);
  check_closed_surface(graded, "graded sphere");
  const double near = mean_edge(graded, -0.05, -0.04);  // within 10 mm of the plane
  const double far = mean_edge(graded, 0.0, 0.05);      // the upper half
  EXPECT_NEAR(near, 3e-3, 0.25 * 3e-3);
  EXPECT_NEAR(far, 8e-3, 0.25 * 8e-3);
  EXPECT_NEAR(mean_edge(coarse, 0.0, 0.05), far, 0.05 * far);  // the far part keeps its triangles' size
  // Far fewer triangles than the whole surface at 3 mm.
  EXPECT_LT(graded.F.rows(), remeshed_triangles(surface_area(coarse), 3e-3) / 2.0);
  // A grading no finer than the surface leaves it as it is.
  EXPECT_EQ(remesh_graded(coarse, 8e-3, {8e-3, 10e-3}, to_plane).F.rows(), coarse.F.rows());
}

}  // namespace
}  // namespace palpa::mesh
