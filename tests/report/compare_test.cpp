// SPDX-License-Identifier: AGPL-3.0-or-later
// Comparing pressure maps: identical maps agree exactly, a scaled map has
// the RMS, correlation and forces it must have, maps on different meshes or
// with a bad field are refused.
#include <gtest/gtest.h>

#include <cmath>

#include <filesystem>

#include "common/test_support.hpp"
#include "palpa/core/error.hpp"
#include "palpa/io/ply.hpp"
#include "palpa/report/compare.hpp"

namespace palpa::report {
namespace {

// A unit square of 2 × 2 cells (9 vertices), pressure p(x, y) = 1000 (1 + x).
PressureMap square() {
  PressureMap m;
  m.mesh.V.resize(9, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) m.mesh.V.row(3 * j + i) << 0.5 * i, 0.5 * j, 0.0;
  m.mesh.F.resize(8, 3);
  int f = 0;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      const int a = 3 * j + i;
      m.mesh.F.row(f++) << a, a + 1, a + 4;
      m.mesh.F.row(f++) << a, a + 4, a + 3;
    }
  }
  m.pressure.resize(9);
  for (int v = 0; v < 9; ++v) m.pressure[v] = 1000.0 * (1.0 + m.mesh.V(v, 0));
  m.source = "square";
  return m;
}

TEST(CompareMaps, IdenticalMapsAgree) {
  const PressureMap a = square();
  const MapComparison c = compare_pressure_maps(a, a);
  EXPECT_EQ(c.vertices, 9);
  EXPECT_DOUBLE_EQ(c.rms_difference, 0.0);
  EXPECT_NEAR(c.correlation, 1.0, 1e-12);
  // The square's area is 1 m²; with lumped vertex areas (a third of each
  // triangle) Σ A_i p_i of this linear field is its integral, 1500 N.
  EXPECT_NEAR(c.a.contact_area, 1.0, 1e-12);
  EXPECT_NEAR(c.a.force, 1500.0, 1e-9);
  EXPECT_DOUBLE_EQ(c.a.peak, 2000.0);
}

TEST(CompareMaps, AUniformMapHasNoCorrelation) {
  // Pearson's correlation needs both maps to vary over the contact: against
  // a uniform map it is undefined (NaN), not 0.
  const PressureMap b = square();
  PressureMap a = b;
  a.pressure.setConstant(1500.0);
  const MapComparison c = compare_pressure_maps(a, b);
  EXPECT_TRUE(std::isnan(c.correlation));
  EXPECT_GT(c.rms_difference, 0.0);
  EXPECT_NEAR(c.a.force, c.b.force, 1e-9 * c.b.force);  // both 1500 N on 1 m²
}

TEST(CompareMaps, AScaledMapHasItsRmsAndFullCorrelation) {
  const PressureMap b = square();
  PressureMap a = b;
  a.pressure *= 1.2;
  const MapComparison c = compare_pressure_maps(a, b);
  // RMS of 0.2 p over the area: 0.2 · sqrt(Σ A p² / Σ A).
  double s = 0.0, w = 0.0, m = 0.0;
  const Eigen::VectorXd A = (Eigen::VectorXd(9) << 1, 2, 1, 2, 4, 2, 1, 2, 1).finished() / 16.0;  // lumped areas
  for (int v = 0; v < 9; ++v) {
    s += A[v] * b.pressure[v] * b.pressure[v];
    w += A[v];
    m += A[v] * b.pressure[v];
  }
  EXPECT_NEAR(c.rms_difference, 0.2 * std::sqrt(s / w), 1e-9);
  EXPECT_NEAR(c.relative_rms, 0.2 * std::sqrt(s / w) / (m / w), 1e-12);
  EXPECT_NEAR(c.correlation, 1.0, 1e-12);
  EXPECT_NEAR(c.a.force, 1.2 * c.b.force, 1e-9);
  EXPECT_NEAR(c.max_difference, 400.0, 1e-9);
}

TEST(CompareMaps, RefusesDifferentMeshesAndBadFields) {
  const PressureMap b = square();
  PressureMap a = b;
  a.mesh.V(4, 2) += 0.01;
  EXPECT_THROW(compare_pressure_maps(a, b), Error);
  PressureMap none = b;
  none.pressure.setZero();
  EXPECT_THROW(compare_pressure_maps(none, none), Error);
  test::ScratchDir dir;
  PlyWriteOptions o;
  o.vertex_scalars = {{"pressure_Pa", -b.pressure}};
  write_ply(dir / "negative.ply", b.mesh, o);
  EXPECT_THROW(read_pressure_map(dir / "negative.ply"), Error);
  EXPECT_THROW(read_pressure_map(dir / "negative.ply", "stress"), Error);
  // Pressures whose sums and squares overflow are refused by name, not left to
  // make infinities downstream.
  o.vertex_scalars = {{"pressure_Pa", Eigen::VectorXd::Constant(b.pressure.size(), 1e308)}};
  write_ply(dir / "huge.ply", b.mesh, o);
  try {
    (void)read_pressure_map(dir / "huge.ply");
    ADD_FAILURE() << "1e308 Pa was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Input);
    EXPECT_NE(std::string(e.what()).find("huge.ply"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("from 0 to 1e+09 Pa"), std::string::npos) << e.what();
  }
  o.vertex_scalars = {{"pressure_Pa", b.pressure}};
  write_ply(dir / "good.ply", b.mesh, o);
  const PressureMap read = read_pressure_map(dir / "good.ply");
  EXPECT_EQ(read.pressure, b.pressure);
}

}  // namespace
}  // namespace palpa::report

namespace palpa::report {
namespace {

// A finer square over the same unit square (4 × 4 cells), lifted by `lift`.
SurfaceMesh fine_square(double lift) {
  SurfaceMesh m;
  m.V.resize(25, 3);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) m.V.row(5 * j + i) << 0.25 * i, 0.25 * j, lift;
  m.F.resize(32, 3);
  int f = 0;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      const int a = 5 * j + i;
      m.F.row(f++) << a, a + 1, a + 6;
      m.F.row(f++) << a, a + 6, a + 5;
    }
  }
  return m;
}

TEST(CompareMaps, ATransferOntoAnotherMeshKeepsALinearFieldAndSaysHowFar) {
  // p = 1000 (1 + x) is linear, so the closest point's interpolation
  // reproduces it exactly on the finer mesh 2 mm above.
  const PressureMap coarse = square();
  MapTransfer t;
  const PressureMap moved = transfer_pressure_map(coarse, fine_square(0.002), &t);
  ASSERT_EQ(moved.pressure.size(), 25);
  for (Eigen::Index v = 0; v < 25; ++v) {
    EXPECT_NEAR(moved.pressure[v], 1000.0 * (1.0 + moved.mesh.V(v, 0)), 1e-9) << v;
  }
  EXPECT_NEAR(t.max_distance, 0.002, 1e-12);
  EXPECT_NEAR(t.mean_distance, 0.002, 1e-12);
  // Compared across the meshes: the same field agrees; each side's own
  // figures on its own mesh (both carry 1500 N).
  PressureMap fine{fine_square(0.0), Eigen::VectorXd(25), "fine"};
  for (Eigen::Index v = 0; v < 25; ++v) fine.pressure[v] = 1000.0 * (1.0 + fine.mesh.V(v, 0));
  const MapComparison c = compare_across_meshes(fine, coarse);
  EXPECT_NEAR(c.rms_difference, 0.0, 1e-9);
  EXPECT_NEAR(c.correlation, 1.0, 1e-12);
  EXPECT_NEAR(c.a.force, 1500.0, 1e-9);
  EXPECT_NEAR(c.b.force, 1500.0, 1e-9);
  // Without the transfer the meshes are refused, naming it.
  try {
    compare_pressure_maps(fine, coarse);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("--transfer"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace palpa::report
