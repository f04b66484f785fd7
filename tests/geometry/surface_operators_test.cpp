// SPDX-License-Identifier: AGPL-3.0-or-later
// Areas, normals, cotangent Laplacian and mass matrix against analytic values
// on a sphere and exact identities on a plane; the umbrella operator and
// sub-meshes.
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/test_surfaces.hpp"
#include "palpa/geometry/submesh.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/geometry/umbrella.hpp"

namespace palpa::geometry {
namespace {

using palpa::test::icosphere;
using palpa::test::square_grid;

constexpr double kRadius = 0.05;  // m

TEST(Icosphere, CountsAndUnitRadius) {
  for (int level : {0, 1, 3}) {
    const SurfaceMesh m = icosphere(level, 1.0);
    EXPECT_EQ(m.V.rows(), 10 * (1 << (2 * level)) + 2);
    EXPECT_EQ(m.F.rows(), 20 * (1 << (2 * level)));
    EXPECT_LT((m.V.rowwise().norm().array() - 1.0).abs().maxCoeff(), 1e-15);
    // Outward winding: every face normal points away from the centre.
    const Eigen::MatrixX3d n = face_normals(m);
    for (Eigen::Index f = 0; f < m.F.rows(); ++f) EXPECT_GT(n.row(f).dot(m.V.row(m.F(f, 0))), 0.0);
  }
}

TEST(SurfaceOperators, AreasSumToTheSphereArea) {
  const SurfaceMesh sphere = icosphere(4, kRadius);
  const double exact = 4.0 * std::numbers::pi * kRadius * kRadius;
  // A level-4 icosphere (5120 triangles) is inscribed: its area is below the
  // sphere's by O(h²), under 0.5 %.
  EXPECT_NEAR(face_areas(sphere).sum(), exact, 5e-3 * exact);
  EXPECT_LT(face_areas(sphere).sum(), exact);
  EXPECT_NEAR(vertex_areas(sphere).sum(), face_areas(sphere).sum(), 1e-14 * exact);
  EXPECT_GT(vertex_areas(sphere).minCoeff(), 0.0);
  const Eigen::SparseMatrix<double> M = mass_matrix(sphere);
  EXPECT_NEAR(Eigen::VectorXd(M.diagonal()).sum(), vertex_areas(sphere).sum(), 1e-14 * exact);
  EXPECT_EQ(M.nonZeros(), sphere.V.rows());
}

TEST(SurfaceOperators, NormalsOfASpherePointOutwardRadially) {
  const SurfaceMesh sphere = icosphere(3, kRadius);
  const Eigen::MatrixX3d n = vertex_normals(sphere);
  for (Eigen::Index i = 0; i < n.rows(); ++i) {
    EXPECT_NEAR(n.row(i).norm(), 1.0, 1e-14);
    // Nearly symmetric one-rings: the angle-weighted normal is radial to 0.01 rad.
    EXPECT_GT(n.row(i).dot(sphere.V.row(i).normalized()), std::cos(1e-2)) << "vertex " << i;
  }
  const Eigen::MatrixX3d fn = face_normals(sphere);
  for (Eigen::Index f = 0; f < fn.rows(); ++f) {
    const Eigen::RowVector3d centre =
        (sphere.V.row(sphere.F(f, 0)) + sphere.V.row(sphere.F(f, 1)) + sphere.V.row(sphere.F(f, 2))) /
        3.0;
    EXPECT_GT(fn.row(f).dot(centre.normalized()), 0.99);
  }
}

TEST(SurfaceOperators, AngleWeightedNormalIgnoresTheTriangulationOfAFlatFan) {
  SurfaceMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  // One face: the normal is the face normal.
  EXPECT_TRUE(vertex_normals(m).row(0).isApprox(Eigen::RowVector3d(0, 0, 1), 1e-15));
  // A symmetric pyramid fan: the apex normal is the axis.
  SurfaceMesh fan;
  fan.V.resize(5, 3);
  fan.V << 0, 0, 0.2, 1, 1, 0, -1, 1, 0, -1, -1, 0, 1, -1, 0;
  fan.F.resize(4, 3);
  fan.F << 0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1;
  EXPECT_TRUE(vertex_normals(fan).row(0).isApprox(Eigen::RowVector3d(0, 0, 1), 1e-14));
}

TEST(SurfaceOperators, PressureForceIsTheNetForceOfTheMap) {
  // A uniform pressure on a closed surface has no net force; on the upper
  // half of a sphere (z > 0) it is p·πr² along +z while ∫ p dA is twice that;
  // a pressure linear in z over the whole sphere, p = z, gives (4/3)πr³ ẑ
  // (the divergence theorem), and every one is exact for P1 fields up to the
  // inscribed polyhedron's O(h²).
  const SurfaceMesh sphere = icosphere(4, kRadius);
  const double p0 = 2000.0;  // Pa
  const Eigen::VectorXd uniform = Eigen::VectorXd::Constant(sphere.V.rows(), p0);
  EXPECT_LT(pressure_force(sphere.V, sphere.F, uniform).norm(), 1e-12 * p0 * kRadius * kRadius);
  Eigen::VectorXd cap = Eigen::VectorXd::Zero(sphere.V.rows());
  for (Eigen::Index i = 0; i < cap.size(); ++i) cap[i] = sphere.V(i, 2) > 1e-12 ? p0 : 0.0;
  const Eigen::Vector3d f_cap = pressure_force(sphere.V, sphere.F, cap);
  const double disc = std::numbers::pi * kRadius * kRadius * p0;
  // The cap's edge triangles carry a third to two thirds of p0: O(h) there.
  EXPECT_NEAR(f_cap.z(), disc, 0.03 * disc);
  EXPECT_LT(f_cap.head<2>().norm(), 1e-9 * disc);
  const Eigen::VectorXd z = sphere.V.col(2);
  const Eigen::Vector3d f_z = pressure_force(sphere.V, sphere.F, z);
  const double volume = 4.0 / 3.0 * std::numbers::pi * std::pow(kRadius, 3);
  EXPECT_NEAR(f_z.z(), volume, 5e-3 * volume);
  EXPECT_LT(f_z.head<2>().norm(), 1e-12 * volume);
}

TEST(SurfaceOperators, LaplacianIsSymmetricWithZeroRowSumsAndKillsLinearFunctionsOnAPlane) {
  const SurfaceMesh grid = square_grid(8, 0.1);
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(grid);
  EXPECT_NEAR((Eigen::MatrixXd(L) - Eigen::MatrixXd(L.transpose())).norm(), 0.0, 1e-14);
  const Eigen::VectorXd row_sums = L * Eigen::VectorXd::Ones(L.cols());
  EXPECT_LT(row_sums.cwiseAbs().maxCoeff(), 1e-13);
  // A linear function is harmonic: L u = 0 at interior vertices.
  const Eigen::VectorXd u = 2.0 * grid.V.col(0) - 3.0 * grid.V.col(1);
  const Eigen::VectorXd Lu = L * u;
  for (Eigen::Index i = 0; i < grid.V.rows(); ++i) {
    const bool interior = std::abs(grid.V(i, 0)) < 0.049 && std::abs(grid.V(i, 1)) < 0.049;
    if (interior) {
      EXPECT_NEAR(Lu(i), 0.0, 1e-14) << "vertex " << i;
    }
  }
  // Dirichlet energy of u = a·x over the square: ½|a|² × area.
  EXPECT_NEAR(0.5 * u.dot(L * u), 0.5 * 13.0 * 0.01, 1e-14);
}

TEST(SurfaceOperators, LaplacianOfPositionIsTwiceTheMeanCurvatureNormal) {
  // −Δx = 2H n with H = 1/r on a sphere: (M⁻¹ L x)_i ≈ (2/r) n_i.
  const SurfaceMesh sphere = icosphere(4, kRadius);
  const Eigen::SparseMatrix<double> L = cotangent_laplacian(sphere);
  const Eigen::VectorXd areas = vertex_areas(sphere);
  const Eigen::MatrixXd LX = L * Eigen::MatrixXd(sphere.V);
  double worst = 0.0;
  double mean = 0.0;
  for (Eigen::Index i = 0; i < sphere.V.rows(); ++i) {
    const Eigen::RowVector3d hn = LX.row(i) / areas(i);
    const Eigen::RowVector3d radial = sphere.V.row(i).normalized();
    // The direction is radial (the cotangent formula is exact in direction on
    // these symmetric rings up to 0.01 rad) ...
    EXPECT_GT(hn.normalized().dot(radial), std::cos(1e-2)) << "vertex " << i;
    worst = std::max(worst, std::abs(hn.norm() * kRadius / 2.0 - 1.0));
    mean += hn.norm() * kRadius / 2.0 / double(sphere.V.rows());
  }
  // ... and the magnitude 2/r within 20 % pointwise (barycentric areas are not
  // the Voronoi areas the pointwise limit needs) and 1 % on average.
  EXPECT_LT(worst, 0.2);
  EXPECT_NEAR(mean, 1.0, 0.01);
}

TEST(SurfaceOperators, DegenerateTrianglesContributeNothing) {
  SurfaceMesh m = square_grid(2, 1.0);
  const Eigen::SparseMatrix<double> L0 = cotangent_laplacian(m);
  // Append a zero-area triangle on existing vertices 0, 1, 2 (collinear).
  m.F.conservativeResize(m.F.rows() + 1, 3);
  m.F.row(m.F.rows() - 1) << 0, 1, 2;
  const Eigen::SparseMatrix<double> L1 = cotangent_laplacian(m);
  EXPECT_TRUE(Eigen::MatrixXd(L1).allFinite());
  EXPECT_NEAR((Eigen::MatrixXd(L1) - Eigen::MatrixXd(L0)).norm(), 0.0, 1e-15);
  EXPECT_TRUE(face_normals(m).row(m.F.rows() - 1).isZero());
}

TEST(SurfaceOperators, ArrayOverloadsGiveTheMeshResultsExactly) {
  const SurfaceMesh sphere = icosphere(2, kRadius);
  EXPECT_EQ(face_areas(sphere.V, sphere.F), face_areas(sphere));
  EXPECT_EQ(vertex_areas(sphere.V, sphere.F), vertex_areas(sphere));
}

TEST(SurfaceOperators, NormalWeightingsWeighTheFacesAsDocumented) {
  // Around vertex 0: a long thin triangle in z = 0 (normal +z, area 5, corner
  // angle atan(1/10)) and a small right triangle in x = 0 (normal +x, area ½,
  // corner angle π/2).
  SurfaceMesh m;
  m.V.resize(5, 3);
  m.V << 0, 0, 0, 10, 0, 0, 10, 1, 0, 0, 1, 0, 0, 0, 1;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 0, 3, 4;
  const Eigen::RowVector3d z(0, 0, 1), x(1, 0, 0);
  EXPECT_TRUE(vertex_normals(m, NormalWeighting::Uniform)
                  .row(0)
                  .isApprox((z + x).normalized(), 1e-14));
  EXPECT_TRUE(
      vertex_normals(m, NormalWeighting::Area).row(0).isApprox((10 * z + x).normalized(), 1e-14));
  EXPECT_TRUE(vertex_normals(m, NormalWeighting::Angle)
                  .row(0)
                  .isApprox((std::atan(0.1) * z + std::numbers::pi / 2 * x).normalized(), 1e-14));
  EXPECT_EQ(vertex_normals(m), vertex_normals(m, NormalWeighting::Angle));
}

TEST(Umbrella, NeighboursAreSymmetricAndRowsAreMeans) {
  // Two triangles of an open strip and an unused vertex 4.
  Eigen::MatrixX3i F(2, 3);
  F << 0, 1, 2, 1, 3, 2;
  const auto nb = vertex_neighbours(F, 5);
  EXPECT_EQ(nb[0], (std::vector<int>{1, 2}));
  EXPECT_EQ(nb[1], (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(nb[3], (std::vector<int>{1, 2}));
  EXPECT_TRUE(nb[4].empty());
  const Eigen::MatrixXd W(umbrella_matrix(F, 5));
  EXPECT_DOUBLE_EQ(W(1, 3), 1.0 / 3.0);
  EXPECT_EQ(W(1, 1), 0.0);
  EXPECT_EQ(W(4, 4), 1.0);
  for (Eigen::Index i = 0; i < 5; ++i) EXPECT_NEAR(W.row(i).sum(), 1.0, 1e-15);
}

TEST(Umbrella, TheLargestSpikeIsTheLoneVertexThatMoved) {
  // A 6 × 6-cell grid of 60 mm; its interior vertices.
  const SurfaceMesh grid = square_grid(6, 0.06);
  std::vector<int> inside;
  for (Eigen::Index v = 0; v < grid.V.rows(); ++v) {
    if (grid.V.row(v).head<2>().cwiseAbs().maxCoeff() < 0.029) inside.push_back(static_cast<int>(v));
  }
  ASSERT_EQ(inside.size(), 25u);
  // A tilt and a lift are no spike.
  Eigen::MatrixX3d D = Eigen::MatrixX3d::Zero(grid.V.rows(), 3);
  D.col(2) = 0.1 * grid.V.col(0) + 0.05 * grid.V.col(1) + Eigen::VectorXd::Constant(grid.V.rows(), 2e-3);
  EXPECT_LT(largest_spike(D, grid.F, inside).distance, 1e-15);
  // One vertex raised 1 mm among still neighbours.
  const int centre = inside[12];
  ASSERT_LT(grid.V.row(centre).norm(), 1e-12);
  D.setZero();
  D(centre, 2) = 1e-3;
  const Spike s = largest_spike(D, grid.F, inside);
  EXPECT_EQ(s.vertex, centre);
  EXPECT_NEAR(s.distance, 1e-3, 1e-15);
  EXPECT_EQ(largest_spike(D, grid.F, {}).vertex, -1);
  // Along the normals (here +z) the lone vertex is the same spike.
  Eigen::MatrixX3d up = Eigen::MatrixX3d::Zero(grid.V.rows(), 3);
  up.col(2).setOnes();
  EXPECT_NEAR(largest_spike(D, grid.F, inside, &up).distance, 1e-3, 1e-15);
}

TEST(Umbrella, VerticesSlidingAlongTheSurfaceMakeNoSpikeOutOfIt) {
  const SurfaceMesh grid = square_grid(6, 0.06);
  std::vector<int> inside;
  for (Eigen::Index v = 0; v < grid.V.rows(); ++v) {
    if (grid.V.row(v).head<2>().cwiseAbs().maxCoeff() < 0.029) inside.push_back(static_cast<int>(v));
  }
  Eigen::MatrixX3d up = Eigen::MatrixX3d::Zero(grid.V.rows(), 3);
  up.col(2).setOnes();
  // Every vertex slides 0.5 mm along the plane, each in its own direction,
  // and the whole grid rises 2 mm: the plane stays a plane.
  Eigen::MatrixX3d D = Eigen::MatrixX3d::Zero(grid.V.rows(), 3);
  for (Eigen::Index v = 0; v < grid.V.rows(); ++v) {
    const double a = 2.399963 * static_cast<double>(v);  // the golden angle: no two alike
    D.row(v) << 0.5e-3 * std::cos(a), 0.5e-3 * std::sin(a), 2e-3;
  }
  EXPECT_GT(largest_spike(D, grid.F, inside).distance, 0.4e-3);
  EXPECT_LT(largest_spike(D, grid.F, inside, &up).distance, 1e-15);
  // A vertex raised 1 mm out of it among them is seen in full.
  const int centre = inside[12];
  D(centre, 2) += 1e-3;
  const Spike s = largest_spike(D, grid.F, inside, &up);
  EXPECT_EQ(s.vertex, centre);
  EXPECT_NEAR(s.distance, 1e-3, 1e-15);
}

TEST(Submesh, NumbersVerticesInOrderOfFirstUse) {
  Eigen::MatrixX3d V(6, 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) V.row(i) << double(i), 0.0, 0.0;
  Eigen::MatrixX3i F(2, 3);
  F << 4, 1, 5, 1, 2, 5;
  const Submesh s = submesh(V, F);
  EXPECT_EQ(s.to_old, (std::vector<int>{4, 1, 5, 2}));
  EXPECT_EQ(s.to_new, (std::vector<int>{-1, 1, 3, -1, 0, 2}));
  Eigen::MatrixX3i expected(2, 3);
  expected << 0, 1, 2, 1, 3, 2;
  EXPECT_EQ(s.mesh.F, expected);
  for (std::size_t i = 0; i < s.to_old.size(); ++i) {
    EXPECT_EQ(s.mesh.V.row(Eigen::Index(i)), V.row(s.to_old[i]));
  }
}

}  // namespace
}  // namespace palpa::geometry
