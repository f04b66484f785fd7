// SPDX-License-Identifier: AGPL-3.0-or-later
// Cheap repairs (merged vertices, degenerate and repeated triangles, winding)
// and the refusal of open, non-manifold and self-intersecting surfaces.
#include <gtest/gtest.h>

#include "common/test_support.hpp"
#include "palpa/mesh/bodies.hpp"
#include "palpa/mesh/surface_check.hpp"

namespace palpa::mesh {
namespace {

using test::throws_error;

// The unit cube as a triangle soup: every triangle with its own 3 vertices.
SurfaceMesh cube_soup() {
  const double c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                          {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  SurfaceMesh m;
  m.V.resize(36, 3);
  m.F.resize(12, 3);
  for (int t = 0; t < 12; ++t) {
    for (int k = 0; k < 3; ++k) {
      m.V.row(3 * t + k) << c[f[t][k]][0], c[f[t][k]][1], c[f[t][k]][2];
      m.F(t, k) = 3 * t + k;
    }
  }
  return m;
}

TEST(SurfaceRepair, MergesSoupVerticesAndDropsDegenerateAndRepeatedTriangles) {
  SurfaceMesh soup = cube_soup();
  // A triangle with a repeated corner and a repeated triangle.
  soup.F.conservativeResize(14, 3);
  soup.F.row(12) << 0, 0, 1;
  soup.F.row(13) = soup.F.row(2);
  RepairReport report;
  const SurfaceMesh cube = repair_surface(soup, &report);
  EXPECT_EQ(cube.V.rows(), 8);
  EXPECT_EQ(cube.F.rows(), 12);
  EXPECT_EQ(report.merged_vertices, 28);
  EXPECT_EQ(report.degenerate_faces, 1);
  EXPECT_EQ(report.duplicate_faces, 1);
  EXPECT_FALSE(report.flipped);
  EXPECT_NEAR(enclosed_volume(cube), 1.0, 1e-15);
  EXPECT_NO_THROW(check_closed_surface(cube, "cube.obj"));
}

TEST(SurfaceRepair, ReversesAnInwardWinding) {
  SurfaceMesh soup = cube_soup();
  soup.F.col(1).swap(soup.F.col(2));
  RepairReport report;
  const SurfaceMesh cube = repair_surface(soup, &report);
  EXPECT_TRUE(report.flipped);
  EXPECT_NEAR(enclosed_volume(cube), 1.0, 1e-15);
}

// A remeshing far beyond what palpa makes (a metre cube at 0.1 mm edges,
// 3e8 triangles) is refused before it starts.
TEST(SurfaceCheck, RefusesARemeshingIntoTooManyTriangles) {
  const SurfaceMesh cube = repair_surface(cube_soup());
  EXPECT_NEAR(surface_area(cube), 6.0, 1e-12);
  EXPECT_NEAR(remeshed_triangles(6.0, 1e-4), 6.0 / (std::sqrt(3.0) / 4.0 * 1e-8), 1.0);
  EXPECT_TRUE(test::throws_error([&] { (void)remesh_surface(cube, 1e-4); }, ErrorKind::Input,
                                 {"remeshing a surface of 6 m²", "would make about 1.39e+09 triangles",
                                  "a longer edge length"}));
}

TEST(SurfaceCheck, RefusesAnOpenSurfaceNamingTheFileAndAnEdge) {
  SurfaceMesh cube = repair_surface(cube_soup());
  cube.F.conservativeResize(11, 3);
  EXPECT_TRUE(throws_error([&] { check_closed_surface(cube, "scan.obj"); }, ErrorKind::Input,
                           {"scan.obj", "open", "3 edges", "watertight"}));
}

TEST(SurfaceCheck, RefusesInconsistentWinding) {
  SurfaceMesh cube = repair_surface(cube_soup());
  cube.F.row(0) = Eigen::RowVector3i(cube.F(0, 0), cube.F(0, 2), cube.F(0, 1));
  EXPECT_TRUE(throws_error([&] { check_closed_surface(cube, "scan.obj"); }, ErrorKind::Input,
                           {"scan.obj", "same direction"}));
}

TEST(SurfaceCheck, RefusesANonManifoldVertex) {
  // The cube and its point reflection through the corner (1, 1, 1): two cubes
  // touching at that one vertex.
  const SurfaceMesh a = repair_surface(cube_soup());
  int shared = -1;
  for (int i = 0; i < 8; ++i) {
    if (a.V.row(i).isApprox(Eigen::RowVector3d(1, 1, 1))) shared = i;
  }
  ASSERT_GE(shared, 0);
  SurfaceMesh two;
  two.V.resize(15, 3);
  two.V.topRows(8) = a.V;
  std::vector<int> map(8);
  int next = 8;
  for (int i = 0; i < 8; ++i) {
    map[i] = i == shared ? shared : next++;
    if (i != shared) two.V.row(map[i]) = Eigen::RowVector3d(2, 2, 2) - a.V.row(i);
  }
  two.F.resize(24, 3);
  two.F.topRows(12) = a.F;
  for (int f = 0; f < 12; ++f) {
    // A point reflection reverses orientation: swap two corners.
    two.F.row(12 + f) << map[a.F(f, 0)], map[a.F(f, 2)], map[a.F(f, 1)];
  }
  EXPECT_TRUE(throws_error([&] { check_closed_surface(two, "two.obj"); }, ErrorKind::Input,
                           {"two.obj", "non-manifold vertex"}));
}

TEST(SurfaceCheck, RefusesATriangleWithoutArea) {
  // The closed cube with its edge 0–1 split at m = (0.5, 0, 0) on one side and
  // closed by the flat triangle (0, 1, m) on the other: still a closed,
  // consistently wound surface, but with a triangle of zero area.
  const double c[9][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1},
                          {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.5, 0, 0}};
  const int f[14][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 8, 5}, {8, 1, 5}, {0, 5, 4},
                        {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}, {0, 1, 8}};
  SurfaceMesh m;
  m.V.resize(9, 3);
  m.F.resize(14, 3);
  for (int v = 0; v < 9; ++v) m.V.row(v) << c[v][0], c[v][1], c[v][2];
  for (int t = 0; t < 14; ++t) m.F.row(t) << f[t][0], f[t][1], f[t][2];
  EXPECT_TRUE(throws_error([&] { check_closed_surface(m, "flat.obj"); }, ErrorKind::Input,
                           {"flat.obj", "triangle 13 near (500 mm, 0 m, 0 m) has no area"}));
}

TEST(SurfaceCheck, RefusesASelfIntersectingSurface) {
  // Two overlapping spheres in one mesh.
  BodyOptions o;
  o.shape = BodyShape::Sphere;
  o.size = Eigen::Vector3d::Constant(0.04);
  o.edge_length = 5e-3;
  const SurfaceMesh s = make_body(o);
  SurfaceMesh two;
  two.V.resize(2 * s.V.rows(), 3);
  two.V.topRows(s.V.rows()) = s.V;
  two.V.bottomRows(s.V.rows()) = s.V.rowwise() + Eigen::RowVector3d(0.02, 0, 0);
  two.F.resize(2 * s.F.rows(), 3);
  two.F.topRows(s.F.rows()) = s.F;
  two.F.bottomRows(s.F.rows()) = s.F.array() + int(s.V.rows());
  EXPECT_TRUE(throws_error([&] { check_closed_surface(two, "two.obj"); }, ErrorKind::Input,
                           {"two.obj", "intersects itself"}));
  EXPECT_TRUE(self_intersects(two));
  EXPECT_FALSE(self_intersects(s));
  // Apart, the two spheres do not cross.
  two.V.bottomRows(s.V.rows()).col(0).array() += 0.03;
  EXPECT_FALSE(self_intersects(two));
}

}  // namespace
}  // namespace palpa::mesh
