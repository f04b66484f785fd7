// SPDX-License-Identifier: AGPL-3.0-or-later
// Obstacle meshes: validation messages, the inside test on cube, sphere and
// torus (on faces, edges and vertices too), closest points against brute force,
// palpa's tree against CGAL's AABB tree (the reference), poses and refits.

#include "palpa/contact/obstacle.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <utility>

#include "common/cgal_triangle_tree.hpp"
#include "common/test_support.hpp"
#include "contact/shapes.hpp"
#include "palpa/contact/primitives.hpp"
#include "palpa/geometry/closest_point_on_triangle.hpp"
#include "palpa/geometry/surface_operators.hpp"

namespace palpa::contact {
namespace {

using test::throws_error;

Eigen::Vector3d random_point(std::mt19937_64& rng, double half) {
  std::uniform_real_distribution<double> u(-half, half);
  return {u(rng), u(rng), u(rng)};
}

Pose some_pose() {
  Pose pose;
  pose.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  pose.t = Eigen::Vector3d(0.3, -0.1, 0.25);
  return pose;
}

// ---- validation -------------------------------------------------------------

TEST(ObstacleValidation, RefusesAnOpenMesh) {
  SurfaceMesh m = test::cube_mesh(0.01);
  m.F.conservativeResize(m.F.rows() - 1, 3);  // drop one triangle: three boundary edges
  EXPECT_TRUE(
      throws_error([&] { Obstacle(m, "box.obj"); }, ErrorKind::Input,
                   {"box.obj: ", "not closed", "3 boundary edge(s)", "used by triangle", "only"}));
}

TEST(ObstacleValidation, RefusesANonManifoldEdge) {
  EXPECT_TRUE(throws_error(
      [&] { Obstacle(test::bowtie_mesh(), "bowtie.off"); }, ErrorKind::Input,
      {"bowtie.off: ", "not manifold", "1 edge(s)", "vertices 0 and 1", "shared by 4 triangles"}));
}

TEST(ObstacleValidation, RefusesInconsistentOrientation) {
  SurfaceMesh m = test::cube_mesh(0.01);
  m.F.row(4) = Eigen::Vector3i(m.F(4, 0), m.F(4, 2), m.F(4, 1));
  EXPECT_TRUE(throws_error([&] { Obstacle(m, "box.obj"); }, ErrorKind::Input,
                           {"inconsistent orientation", "3 edge(s)", "both run from vertex"}));
}

TEST(ObstacleValidation, FlipsOrRefusesAnInwardMesh) {
  SurfaceMesh m = test::cube_mesh(0.01);
  m.F.col(1).swap(m.F.col(2));
  ObstacleOptions refuse;
  refuse.flip_inward = false;
  EXPECT_TRUE(throws_error([&] { Obstacle(m, "box.obj", refuse); }, ErrorKind::Input,
                           {"box.obj: ", "oriented inwards", "-8e-06 m³"}));
  const Obstacle flipped(m, "box.obj");
  EXPECT_TRUE(flipped.flipped());
  EXPECT_NEAR(flipped.volume(), 8e-6, 1e-18);
  EXPECT_TRUE(flipped.inside(Eigen::Vector3d(0.009, -0.009, 0.0)));
  EXPECT_FALSE(flipped.inside(Eigen::Vector3d(0.011, 0.0, 0.0)));
}

TEST(ObstacleValidation, RefusesDegenerateTriangles) {
  SurfaceMesh m = test::cube_mesh(0.01);
  m.F(3, 1) = m.F(3, 0);
  EXPECT_TRUE(throws_error([&] { Obstacle(m, "box.obj"); }, ErrorKind::Input,
                           {"1 degenerate triangle(s)", "triangle 3", "three distinct vertices"}));
  // Three distinct but collinear vertices: a sliver of zero area.
  SurfaceMesh s = test::cube_mesh(0.01);
  s.V.conservativeResize(9, 3);
  s.V.row(8) = 0.5 * (s.V.row(0) + s.V.row(1));
  s.F.conservativeResize(13, 3);
  s.F.row(12) = Eigen::Vector3i(0, 8, 1);
  EXPECT_TRUE(
      throws_error([&] { Obstacle(s, "box.obj"); }, ErrorKind::Input,
                   {"degenerate triangle(s)", "triangle 12 (vertices 0, 8, 1) has area 0"}));
}

TEST(ObstacleValidation, RefusesNonFiniteCoordinatesAndBadIndices) {
  SurfaceMesh m = test::cube_mesh(0.01);
  m.V(5, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { Obstacle(m, "box.stl"); }, ErrorKind::Input,
                           {"box.stl: ", "vertex 5 has a non-finite coordinate"}));
  SurfaceMesh b = test::cube_mesh(0.01);
  b.F(2, 2) = 8;
  EXPECT_TRUE(throws_error([&] { Obstacle(b, "box.stl"); }, ErrorKind::Input,
                           {"triangle 2 refers to vertex 8, but there are 8 vertices"}));
}

TEST(ObstacleValidation, RefusesASelfIntersectingSurfaceUnlessAsked) {
  // Two closed, outward cubes overlapping: every test but this one passes.
  const SurfaceMesh a = test::cube_mesh(0.01);
  SurfaceMesh both;
  both.V.resize(16, 3);
  both.V << a.V, (a.V.rowwise() + Eigen::RowVector3d(0.005, 0.004, 0.003));
  both.F.resize(24, 3);
  both.F << a.F, (a.F.array() + 8).matrix();
  EXPECT_TRUE(throws_error([&] { Obstacle(both, "two_boxes.stl"); }, ErrorKind::Input,
                           {"two_boxes.stl: ", "the surface intersects itself",
                            "pair(s) of triangles cross", "does not cross itself"}));
  ObstacleOptions lenient;
  lenient.check_self_intersections = false;
  const Obstacle accepted(both, "two_boxes.stl", lenient);
  EXPECT_TRUE(accepted.inside(Eigen::Vector3d(-0.009, -0.009, -0.009)));  // first box only
  // Just below the second box's bottom face, deep inside the first box: the
  // nearest sheet (that face, seen from outside) decides, so "outside". This is
  // why such surfaces are refused by default.
  EXPECT_FALSE(accepted.inside(Eigen::Vector3d(0.0, 0.0, -0.0071)));
  EXPECT_TRUE(accepted.inside(Eigen::Vector3d(0.0, 0.0, -0.0069)));
}

TEST(ObstacleValidation, RefusesABadPoseAndBadNewVertices) {
  Obstacle box(test::cube_mesh(0.01), "box.obj");
  Pose scaled;
  scaled.R *= 1.01;
  EXPECT_TRUE(throws_error([&] { box.set_pose(scaled); }, ErrorKind::Input,
                           {"box.obj: ", "not a rotation"}));
  Pose mirrored;
  mirrored.R(2, 2) = -1.0;
  EXPECT_TRUE(throws_error([&] { box.set_pose(mirrored); }, ErrorKind::Input, {"not a rotation"}));
  EXPECT_TRUE(throws_error([&] { box.set_vertices(Eigen::MatrixX3d::Zero(7, 3)); },
                           ErrorKind::Input, {"7 new vertex positions for a mesh of 8 vertices"}));
}

// ---- inside test ------------------------------------------------------------

TEST(ObstacleInside, CubeOnAndNearFacesEdgesAndVertices) {
  const double h = 0.01;
  const double e = 1e-9;
  const Obstacle box(test::cube_mesh(h), "box");
  EXPECT_TRUE(box.inside(Eigen::Vector3d::Zero()));
  // Exactly on a face, an edge, a vertex: on the surface, so not inside.
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0, 0, h), Eigen::Vector3d(h, h, 0), Eigen::Vector3d(h, h, h),
        Eigen::Vector3d(0.3 * h, -h, 0.2 * h), Eigen::Vector3d(-h, 0, -h)}) {
    EXPECT_FALSE(box.inside(p)) << p.transpose();
    EXPECT_LT(box.closest_point(p).distance, 1e-18);
  }
  // Just inside and just outside of each kind of feature; the diagonals and the
  // lines through edges and vertices are where ray parity tests break.
  for (const Eigen::Vector3d& dir :
       {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(1, 1, 1),
        Eigen::Vector3d(-1, 0, -1), Eigen::Vector3d(1, -1, 1)}) {
    EXPECT_TRUE(box.inside((h - e) * dir)) << dir.transpose();
    EXPECT_FALSE(box.inside((h + e) * dir)) << dir.transpose();
  }
  // Closest features.
  const ClosestPoint face = box.closest_point(Eigen::Vector3d(0.2 * h, 0.1 * h, 0.9 * h));
  EXPECT_EQ(face.feature, Feature::Face);
  EXPECT_TRUE(face.inside);
  EXPECT_NEAR(face.distance, 0.1 * h, 1e-15);
  const ClosestPoint edge = box.closest_point(Eigen::Vector3d(1.1 * h, 0.2 * h, 1.2 * h));
  EXPECT_EQ(edge.feature, Feature::Edge);
  EXPECT_FALSE(edge.inside);
  EXPECT_NEAR(edge.distance, std::hypot(0.1 * h, 0.2 * h), 1e-15);
  EXPECT_LT(edge.vertices[0], edge.vertices[1]);
  const ClosestPoint corner = box.closest_point(Eigen::Vector3d(1.1 * h, -1.2 * h, 1.3 * h));
  EXPECT_EQ(corner.feature, Feature::Vertex);
  EXPECT_EQ(corner.vertices[0], 5);  // (+h, −h, +h)
  EXPECT_NEAR(corner.distance, std::sqrt(0.01 + 0.04 + 0.09) * h, 1e-15);
}

// The inside test against the generalized winding number, on random points
// that are not within 1e-7 of the surface.
// `concave`: the mesh has inside points whose closest feature is a vertex or an
// edge (a convex mesh has none).
void expect_inside_matches_winding_number(const SurfaceMesh& mesh, double half, int n,
                                          std::uint64_t salt, bool concave) {
  const Obstacle obstacle(mesh, "mesh");
  auto rng = test::make_rng(salt);
  int inside = 0;
  int non_face_inside = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = random_point(rng, half);
    const ClosestPoint c = obstacle.closest_point(p);
    if (c.distance < 1e-7) continue;
    const double w = test::winding_number(mesh, p);
    ASSERT_EQ(c.inside, w > 0.5) << "point " << p.transpose() << " winding number " << w;
    inside += c.inside ? 1 : 0;
    non_face_inside += (c.inside && c.feature != Feature::Face) ? 1 : 0;
  }
  EXPECT_GT(inside, n / 20);
  if (concave) {
    EXPECT_GT(non_face_inside, 0) << "no inside point had a vertex or edge as closest feature";
  }
}

TEST(ObstacleInside, SphereAgreesWithWindingNumber) {
  expect_inside_matches_winding_number(test::sphere_mesh(0.05, 2), 0.06, 3000, 1, false);
}

TEST(ObstacleInside, TorusAgreesWithWindingNumber) {
  // Coarse, so that inside points near saddle vertices and concave edges occur.
  expect_inside_matches_winding_number(test::torus_mesh(0.04, 0.015, 12, 6), 0.06, 3000, 2, true);
}

TEST(ObstacleInside, TorusOnItsVerticesAndEdgesAndThroughItsHole) {
  const double R = 0.04;
  const SurfaceMesh mesh = test::torus_mesh(R, 0.015, 24, 12);
  const Obstacle torus(mesh, "torus");
  // On a vertex or an edge (within rounding), and 1 µm to either side along
  // the smooth torus's normal (saddle and convex vertices and edges alike).
  const double offset = 1e-6;
  for (Eigen::Index f = 0; f < mesh.F.rows(); f += 5) {
    const Eigen::Vector3d vertex = mesh.V.row(mesh.F(f, 0));
    const Eigen::Vector3d mid = 0.5 * (mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)));
    for (const Eigen::Vector3d& p : {vertex, mid}) {
      EXPECT_LT(torus.closest_point(p).distance, 1e-17);
      const Eigen::Vector3d core = R * Eigen::Vector3d(p.x(), p.y(), 0.0).normalized();
      const Eigen::Vector3d normal = (p - core).normalized();
      EXPECT_TRUE(torus.inside(p - offset * normal)) << p.transpose();
      EXPECT_FALSE(torus.inside(p + offset * normal)) << p.transpose();
      EXPECT_GT(test::winding_number(mesh, p - offset * normal), 0.5);
    }
  }
  EXPECT_FALSE(torus.inside(Eigen::Vector3d::Zero()));  // the hole
  EXPECT_TRUE(torus.inside(Eigen::Vector3d(R, 0.0, 0.0)));
  EXPECT_TRUE(torus.inside(Eigen::Vector3d(0.0, -R, 0.01)));
}

TEST(ObstacleInside, PoseMovesTheObstacle) {
  Obstacle torus(test::torus_mesh(0.04, 0.015, 24, 12), "torus");
  Obstacle moved(test::torus_mesh(0.04, 0.015, 24, 12), "torus");
  const Pose pose = some_pose();
  moved.set_pose(pose);
  auto rng = test::make_rng(3);
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d xb = random_point(rng, 0.06);
    const ClosestPoint body = torus.closest_point(xb);
    const ClosestPoint world = moved.closest_point(pose.R * xb + pose.t);
    EXPECT_EQ(world.inside, body.inside);
    EXPECT_NEAR(world.distance, body.distance, 1e-15);
    EXPECT_LT((world.point - (pose.R * body.point + pose.t)).norm(), 1e-15);
    EXPECT_EQ(world.vertices, body.vertices);
  }
  EXPECT_LT(
      (moved.world_vertex(3) - (pose.R * torus.vertices().row(3).transpose() + pose.t)).norm(),
      1e-16);
}

// ---- closest points ---------------------------------------------------------

// Closest point against brute force, and its optimality: (p − c)·(v − c) ≤ 0
// for every corner v of the triangle holding c; the weights reproduce c.
void expect_closest_points_correct(const Obstacle& obstacle, const SurfaceMesh& mesh, double half,
                                   int n, std::uint64_t salt) {
  auto rng = test::make_rng(salt);
  int kinds[3] = {0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d p = random_point(rng, half);
    const ClosestPoint c = obstacle.closest_point(p);
    ASSERT_NEAR(c.distance, test::brute_distance(mesh, p), 1e-14) << p.transpose();
    Eigen::Vector3d from_weights = Eigen::Vector3d::Zero();
    for (int k = 0; k < feature_size(c.feature); ++k) {
      from_weights +=
          c.weights[k] * mesh.V.row(c.vertices[static_cast<std::size_t>(k)]).transpose();
      EXPECT_GT(c.weights[k], 0.0);
    }
    EXPECT_LT((from_weights - c.point).norm(), 1e-15);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d v = mesh.V.row(mesh.F(c.triangle, k));
      EXPECT_LE((p - c.point).dot(v - c.point), 1e-15 * half * half);
    }
    ++kinds[static_cast<int>(c.feature)];
  }
  EXPECT_GT(kinds[0], 0);
  EXPECT_GT(kinds[1], 0);
  EXPECT_GT(kinds[2], 0);
}

TEST(ObstacleClosest, MatchesBruteForceOnSphereAndTorus) {
  const SurfaceMesh sphere = test::sphere_mesh(0.05, 2);
  expect_closest_points_correct(Obstacle(sphere, "sphere"), sphere, 0.08, 2000, 4);
  const SurfaceMesh torus = test::torus_mesh(0.04, 0.015, 16, 8);
  expect_closest_points_correct(Obstacle(torus, "torus"), torus, 0.08, 2000, 5);
}

// The feature of the mesh (and the vertices spanning it, ordered as
// ClosestPoint::vertices) holding the closest point of triangle f to p.
std::pair<Feature, std::array<int, 3>> feature_of(const SurfaceMesh& mesh, int f,
                                                  const Eigen::Vector3d& p) {
  const Eigen::Vector3i t = mesh.F.row(f);
  const int region =
      geometry::closest_on_triangle(p, mesh.V.row(t[0]), mesh.V.row(t[1]), mesh.V.row(t[2])).region;
  if (region == geometry::kFace) return {Feature::Face, {t[0], t[1], t[2]}};
  if (region < geometry::kEdgeAB) return {Feature::Vertex, {t[region], -1, -1}};
  const int a = t[region - geometry::kEdgeAB];
  const int b = t[(region - geometry::kEdgeAB + 1) % 3];
  return {Feature::Edge, {std::min(a, b), std::max(a, b), -1}};
}

TEST(ObstacleClosest, AgreesWithCgalsTree) {
  const SurfaceMesh torus = test::torus_mesh(0.04, 0.015, 40, 25);  // 2000 triangles
  const Obstacle own(torus, "torus");
  const test::CgalTriangleTree cgal(torus.V, torus.F);
  expect_closest_points_correct(own, torus, 0.07, 300, 6);
  auto rng = test::make_rng(7);
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p = random_point(rng, 0.07);
    const ClosestPoint a = own.closest_point(p);
    const test::CgalTriangleTree::Hit b = cgal.closest(p);
    ASSERT_NEAR(a.distance, std::sqrt(b.distance2), 1e-15) << p.transpose();
    EXPECT_LT((a.point - b.point).norm(), 1e-14);
    const auto [feature, vertices] = feature_of(torus, b.triangle, p);
    EXPECT_EQ(a.feature, feature);
    EXPECT_EQ(a.vertices, vertices);
    // The inside test against the winding number (O(#F), so on every tenth point).
    if (i % 10 == 0) EXPECT_EQ(a.inside, test::winding_number(torus, p) > 0.5) << p.transpose();
  }
}

TEST(ObstacleClosest, RefitRebuildAndCgalAgreeAfterDeformation) {
  const SurfaceMesh sphere = test::sphere_mesh(0.05, 3);
  Obstacle refit(sphere, "body");
  Obstacle rebuilt(sphere, "body");
  // A large, uneven deformation: squash along z, wobble in x.
  SurfaceMesh moved = sphere;
  for (Eigen::Index v = 0; v < moved.V.rows(); ++v) {
    moved.V(v, 2) *= 0.6;
    moved.V(v, 0) += 0.01 * std::sin(60.0 * moved.V(v, 1));
  }
  refit.set_vertices(moved.V, true);
  rebuilt.set_vertices(moved.V, false);
  const test::CgalTriangleTree cgal(moved.V, moved.F);
  expect_closest_points_correct(refit, moved, 0.07, 500, 8);
  auto rng = test::make_rng(9);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d p = random_point(rng, 0.07);
    const ClosestPoint a = refit.closest_point(p);
    EXPECT_NEAR(a.distance, rebuilt.closest_point(p).distance, 1e-15);
    EXPECT_NEAR(a.distance, std::sqrt(cgal.closest(p).distance2), 1e-15);
    EXPECT_EQ(a.inside, test::winding_number(moved, p) > 0.5);
  }
}

TEST(ObstacleClosest, TriangleRegionsAreOptimal) {
  // The closest point on one triangle, for points all around it: optimality
  // (p − c)·(v − c) ≤ 0 at every corner, and region ↔ weights.
  const Eigen::Vector3d a(0.0, 0.0, 0.0);
  const Eigen::Vector3d b(0.02, 0.001, 0.0);
  const Eigen::Vector3d c(0.005, 0.015, 0.003);
  auto rng = test::make_rng(10);
  int seen[7] = {};
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d p = random_point(rng, 0.04);
    const auto tp = geometry::closest_on_triangle(p, a, b, c);
    for (const Eigen::Vector3d& v : {a, b, c}) EXPECT_LE((p - tp.point).dot(v - tp.point), 1e-18);
    EXPECT_LT((tp.weights[0] * a + tp.weights[1] * b + tp.weights[2] * c - tp.point).norm(), 1e-17);
    const int zeros = (tp.weights.array() == 0.0).count();
    EXPECT_EQ(zeros, tp.region < 3 ? 2 : (tp.region < 6 ? 1 : 0));
    ++seen[tp.region];
  }
  for (int r = 0; r < 7; ++r) EXPECT_GT(seen[r], 0) << "region " << r;
}

TEST(Primitives, ValidClosedSurfacesWithTheirVolumes) {
  const Obstacle box(box_surface(Eigen::Vector3d(0.01, 0.02, 0.03)), "box");
  EXPECT_FALSE(box.flipped());
  EXPECT_NEAR(box.volume(), 8.0 * 0.01 * 0.02 * 0.03, 1e-18);
  EXPECT_TRUE(box.inside(Eigen::Vector3d(0.0099, -0.0199, 0.0299)));
  EXPECT_FALSE(box.inside(Eigen::Vector3d(0.0, 0.0201, 0.0)));
  const int n = 24;
  const Obstacle cylinder(cylinder_surface(0.005, 0.02, n), "cylinder");
  EXPECT_FALSE(cylinder.flipped());
  EXPECT_EQ(cylinder.triangles().rows(), 4 * n);
  EXPECT_NEAR(cylinder.volume(), 0.5 * n * 25e-6 * std::sin(2.0 * std::numbers::pi / n) * 0.02,
              1e-17);
  EXPECT_TRUE(cylinder.inside(Eigen::Vector3d(0.0048, 0.0, -0.0099)));  // near a vertex of the rim
  EXPECT_FALSE(cylinder.inside(Eigen::Vector3d(0.0, 0.0, -0.0101)));
  EXPECT_FALSE(cylinder.inside(Eigen::Vector3d(0.0036, 0.0036, 0.0)));  // outside the 24-gon
  const Obstacle sphere(sphere_surface(0.05, 2), "sphere");
  EXPECT_FALSE(sphere.flipped());
  EXPECT_EQ(sphere.triangles().rows(), 320);
  EXPECT_LT(sphere.volume(), 4.0 / 3.0 * std::numbers::pi * 1.25e-4);
  EXPECT_GT(sphere.volume(), 0.95 * 4.0 / 3.0 * std::numbers::pi * 1.25e-4);
}

TEST(VertexAreas, ThirdOfIncidentTriangles) {
  const SurfaceMesh box = test::cube_mesh(0.01);
  const Eigen::VectorXd area = geometry::vertex_areas(box.V, box.F);
  EXPECT_NEAR(area.sum(), 6.0 * 4e-4, 1e-18);
  // Every cube corner has either 4 or 5 incident right triangles of area 2e-4.
  for (Eigen::Index v = 0; v < area.size(); ++v) {
    int incident = 0;
    for (Eigen::Index f = 0; f < box.F.rows(); ++f)
      incident += (box.F.row(f).array() == v).any() ? 1 : 0;
    EXPECT_NEAR(area[v], incident * 2e-4 / 3.0, 1e-18);
  }
}

}  // namespace
}  // namespace palpa::contact
