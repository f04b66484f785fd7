// SPDX-License-Identifier: AGPL-3.0-or-later
// Tet mesh checks, boundary extraction and structured box meshes.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numbers>
#include <vector>

#include "common/test_support.hpp"
#include "palpa/core/error.hpp"
#include "palpa/geometry/boundary.hpp"
#include "palpa/tet/element.hpp"
#include "palpa/tet/mesh.hpp"

namespace palpa::tet {
namespace {

Mat34 corners(const TetMesh& m, Eigen::Index t) {
  Mat34 X;
  for (int a = 0; a < 4; ++a) X.col(a) = m.V.row(m.T(t, a)).transpose();
  return X;
}

TEST(BoxMesh, VolumesOrientationAndNamedFaces) {
  const Eigen::Vector3d lo(-0.02, -0.01, -0.005), hi(0.02, 0.03, 0.0);
  const BoxMesh box = make_box_mesh(lo, hi, Eigen::Vector3i(4, 3, 2));
  EXPECT_EQ(box.mesh.V.rows(), 5 * 4 * 3);
  EXPECT_EQ(box.mesh.T.rows(), 6 * 4 * 3 * 2);
  double total = 0.0;
  for (Eigen::Index t = 0; t < box.mesh.T.rows(); ++t) {
    const double v = signed_volume(corners(box.mesh, t));
    EXPECT_GT(v, 0.0);
    total += v;
  }
  EXPECT_NEAR(total, 0.04 * 0.04 * 0.005, 1e-15);
  EXPECT_EQ(box.vertex_sets.at("bottom").size(), 5u * 4u);
  EXPECT_EQ(box.vertex_sets.at("xmax").size(), 4u * 3u);
  for (int v : box.vertex_sets.at("top")) EXPECT_DOUBLE_EQ(box.mesh.V(v, 2), 0.0);
  TetMesh copy = box.mesh;
  const TetMeshCheck check = prepare_tet_mesh(copy, "box");
  EXPECT_EQ(check.flipped, 0);
  EXPECT_NEAR(check.total_volume, 0.04 * 0.04 * 0.005, 1e-15);
}

TEST(BoxMesh, BoundaryIsClosedOutwardAndEnclosesTheVolume) {
  const BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.03, 0.02, 0.01),
                                    Eigen::Vector3i(3, 2, 2));
  const geometry::Boundary b = geometry::boundary_of(box.mesh);
  // Two triangles per boundary square.
  EXPECT_EQ(b.faces.rows(), 2 * 2 * (3 * 2 + 2 * 2 + 3 * 2));
  // Divergence theorem: V = (1/3) Σ_f (centroid · n) A, and Σ n A = 0.
  double volume = 0.0;
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  for (Eigen::Index f = 0; f < b.faces.rows(); ++f) {
    const Eigen::Vector3d p0 = box.mesh.V.row(b.faces(f, 0)), p1 = box.mesh.V.row(b.faces(f, 1)),
                          p2 = box.mesh.V.row(b.faces(f, 2));
    const Eigen::Vector3d an = 0.5 * (p1 - p0).cross(p2 - p0);
    normal_sum += an;
    volume += ((p0 + p1 + p2) / 3.0).dot(an) / 3.0;
  }
  EXPECT_NEAR(volume, 0.03 * 0.02 * 0.01, 1e-15);
  EXPECT_LE(normal_sum.norm(), 1e-18);
  // Only the one interior vertex layer is missing: (4·3·3) − (2·1·1).
  EXPECT_EQ(b.vertices.size(), 4u * 3u * 3u - 2u * 1u * 1u);
}

// The boundary of a cylinder mesh: its area is that of the polygonal solid's
// faces only when every interior face is shared by two tets (the prisms' quad
// faces are split the same way from both sides).
double boundary_area(const TetMesh& m) {
  const geometry::Boundary b = geometry::boundary_of(m);
  double area = 0.0;
  for (Eigen::Index f = 0; f < b.faces.rows(); ++f) {
    const Eigen::Vector3d p0 = m.V.row(b.faces(f, 0)), p1 = m.V.row(b.faces(f, 1)), p2 = m.V.row(b.faces(f, 2));
    area += 0.5 * (p1 - p0).cross(p2 - p0).norm();
  }
  return area;
}

TEST(CylinderMesh, ConformingPositiveTetsFillThePolygonalSolid) {
  const std::vector<double> radii{0.0, 0.002, 0.003, 0.005}, depths{0.0, 0.001, 0.004};
  const double big_r = 0.005, h = 0.004;
  for (const int segments : {8, 12}) {
    for (const double angle : {2.0 * std::numbers::pi, 0.5 * std::numbers::pi}) {
      const StructuredMesh c = make_cylinder_mesh(radii, depths, segments, angle);
      const bool closed = angle > 6.0;
      const int sectors = closed ? segments : segments / 4;
      const int around = closed ? segments : sectors + 1;
      EXPECT_EQ(c.mesh.V.rows(), 3 * (1 + 3 * around));
      // Per layer: one prism per sector on the axis, two per sector and ring gap.
      EXPECT_EQ(c.mesh.T.rows(), 2 * 3 * (sectors * (1 + 2 * 2)));
      const double wedge = 0.5 * big_r * big_r * std::sin(2.0 * std::numbers::pi / segments);
      double volume = 0.0;
      for (Eigen::Index t = 0; t < c.mesh.T.rows(); ++t) {
        const double v = signed_volume(corners(c.mesh, t));
        EXPECT_GT(v, 0.0) << t;
        volume += v;
      }
      EXPECT_NEAR(volume, sectors * wedge * h, 1e-12 * volume);
      const double chord = 2.0 * big_r * std::sin(std::numbers::pi / segments);
      const double faces = 2.0 * sectors * wedge + sectors * chord * h + (closed ? 0.0 : 2.0 * big_r * h);
      EXPECT_NEAR(boundary_area(c.mesh), faces, 1e-12 * faces) << segments << " " << angle;
      EXPECT_EQ(c.vertex_sets.at("top").size(), static_cast<std::size_t>(1 + 3 * around));
      for (int v : c.vertex_sets.at("top")) EXPECT_DOUBLE_EQ(c.mesh.V(v, 2), 0.0);
      for (int v : c.vertex_sets.at("bottom")) EXPECT_DOUBLE_EQ(c.mesh.V(v, 2), -h);
      for (int v : c.vertex_sets.at("side")) EXPECT_NEAR(c.mesh.V.row(v).head<2>().norm(), big_r, 1e-15);
      EXPECT_EQ(c.vertex_sets.count("sector_start"), closed ? 0u : 1u);
      if (!closed) {
        EXPECT_EQ(c.vertex_sets.at("sector_start").size(), 3u * 4u);
        for (int v : c.vertex_sets.at("sector_start")) EXPECT_EQ(c.mesh.V(v, 1), 0.0);
        for (int v : c.vertex_sets.at("sector_end")) EXPECT_NEAR(c.mesh.V(v, 0), 0.0, 1e-15);
      }
    }
  }
  EXPECT_TRUE(palpa::test::throws_error([&] { make_cylinder_mesh(radii, depths, 10, 0.5 * std::numbers::pi); },
                                        ErrorKind::Input, {"not a whole number of the 10 segments"}));
  const std::vector<double> bad{0.0, 0.002, 0.002};
  EXPECT_TRUE(palpa::test::throws_error([&] { make_cylinder_mesh(bad, depths, 8); }, ErrorKind::Input,
                                        {"radii and depths must increase from 0"}));
}

TEST(PrepareTetMesh, FlipsAConsistentlyNegativeMeshAndRefusesMixedOrientation) {
  BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones() * 0.01, Eigen::Vector3i(2, 2, 2));
  TetMesh negative = box.mesh;
  for (Eigen::Index t = 0; t < negative.T.rows(); ++t) std::swap(negative.T(t, 0), negative.T(t, 1));
  const TetMeshCheck check = prepare_tet_mesh(negative, "neg.vtu");
  EXPECT_EQ(check.flipped, negative.T.rows());
  for (Eigen::Index t = 0; t < negative.T.rows(); ++t) EXPECT_GT(signed_volume(corners(negative, t)), 0.0);

  TetMesh mixed = box.mesh;
  std::swap(mixed.T(5, 0), mixed.T(5, 1));
  EXPECT_TRUE(palpa::test::throws_error([&] { prepare_tet_mesh(mixed, "mixed.vtu"); }, ErrorKind::Input, {"mixed.vtu: 1 of 48 tetrahedra are inverted (the first is tetrahedron 5"}));
}

TEST(PrepareTetMesh, RefusesBadIndicesDegenerateTetsAndNaN) {
  const BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones() * 0.01, Eigen::Vector3i(1, 1, 1));
  TetMesh m = box.mesh;
  m.T(2, 3) = 99;
  EXPECT_TRUE(palpa::test::throws_error([&] { prepare_tet_mesh(m, "a.ele"); }, ErrorKind::Input, {"a.ele: tetrahedron 2 uses vertex 99, but there are only 8 vertices"}));
  m = box.mesh;
  m.T(1, 2) = m.T(1, 0);
  EXPECT_TRUE(palpa::test::throws_error([&] { prepare_tet_mesh(m, "a.ele"); }, ErrorKind::Input, {"tetrahedron 1 uses vertex"}));
  m = box.mesh;
  m.V(m.T(3, 3), 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(palpa::test::throws_error([&] { prepare_tet_mesh(m, "a.ele"); }, ErrorKind::Input, {"non-finite coordinate"}));
  m = box.mesh;
  // Move a corner of tet 0 into the plane of the other three.
  const Eigen::RowVector3d a = m.V.row(m.T(0, 0)), b = m.V.row(m.T(0, 1)), c = m.V.row(m.T(0, 2));
  m.V.row(m.T(0, 3)) = (a + b + c) / 3.0;
  EXPECT_TRUE(palpa::test::throws_error([&] { prepare_tet_mesh(m, "flat.vtu"); }, ErrorKind::Input, {"is degenerate"}));
}

}  // namespace
}  // namespace palpa::tet
