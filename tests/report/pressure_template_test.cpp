// SPDX-License-Identifier: AGPL-3.0-or-later
// A simulated map against a gridded template: reading grids, aligning two
// footprints that differ by a turn, a mirror and a stretch, and the picture.
#include "palpa/report/pressure_template.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/test_support.hpp"
#include "xml_check.hpp"

namespace palpa::report {
namespace {

using palpa::test::ScratchDir;
using palpa::test::throws_error;

// A foot-like pattern in its own frame (u along the length, v across, both
// in [−1, 1]): a heel blob, a forefoot blob off to one side, nothing outside
// an ellipse. Asymmetric both ways, so that a reversal shows.
double pattern(double u, double v) {
  if (u * u + v * v / 0.16 > 1.0) return 0.0;
  const double heel = std::exp(-((u + 0.65) * (u + 0.65) + v * v / 0.2) / 0.04);
  const double ball =
      1.5 * std::exp(-((u - 0.45) * (u - 0.45) + (v - 0.15) * (v - 0.15) / 0.2) / 0.03);
  return 1e3 * (20.0 + 100.0 * heel + 100.0 * ball);
}

// The pattern on a flat triangulated skin in the plane z = 0, its length
// along x over 2·half_length [m].
struct Skin {
  SurfaceMesh mesh;
  Eigen::VectorXd pressure;
};

Skin skin(double half_length, int n) {
  Skin s;
  const int m = n / 2;
  s.mesh.V.resize((n + 1) * (m + 1), 3);
  s.pressure.resize(s.mesh.V.rows());
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= m; ++j) {
      const double u = -1.0 + 2.0 * i / n, v = -0.5 + 1.0 * j / m;
      const int k = i * (m + 1) + j;
      s.mesh.V.row(k) << u * half_length, v * half_length, 0.0;
      s.pressure[k] = pattern(u, v);
    }
  }
  s.mesh.F.resize(2 * n * m, 3);
  int f = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const int a = i * (m + 1) + j, b = a + m + 1;
      s.mesh.F.row(f++) << a, b, b + 1;
      s.mesh.F.row(f++) << a, b + 1, a + 1;
    }
  }
  return s;
}

TEST(PressureTemplate, ReadsAGridInItsUnitAndRefusesBadOnes) {
  ScratchDir dir;
  const PressureGrid g = read_pressure_grid(
      dir.write("g.csv", "\xEF\xBB\xBF# a comment\n0,1,2\n3,4.5,0\n"), 5e-3, 1e3);
  ASSERT_EQ(g.pressure.rows(), 2);
  ASSERT_EQ(g.pressure.cols(), 3);
  EXPECT_EQ(g.pressure(1, 1), 4500.0);
  EXPECT_EQ(g.pixel, 5e-3);
  EXPECT_TRUE(
      throws_error([&] { read_pressure_grid(dir.write("a.csv", "0,1,2\n3,4\n"), 5e-3, 1e3); },
                   ErrorKind::Input, {"a.csv", "2 fields where the first row has 3"}));
  EXPECT_TRUE(throws_error([&] { read_pressure_grid(dir.write("b.csv", "0,1\n3,x\n"), 5e-3, 1e3); },
                           ErrorKind::Input, {"b.csv", "field 2"}));
  EXPECT_TRUE(
      throws_error([&] { read_pressure_grid(dir.write("c.csv", "0,1\n3,-2\n"), 5e-3, 1e3); },
                   ErrorKind::Input, {"c.csv", "negative pressure -2 in row 2, field 2"}));
  EXPECT_TRUE(throws_error([&] { read_pressure_grid(dir.write("d.csv", "0,0\n0,0\n"), 5e-3, 1e3); },
                           ErrorKind::Input, {"d.csv", "no pressure"}));
  EXPECT_TRUE(
      throws_error([&] { read_pressure_grid(dir.write("e.csv", "# only a comment\n"), 5e-3, 1e3); },
                   ErrorKind::Input, {"e.csv", "no rows"}));
  EXPECT_TRUE(throws_error([&] { read_pressure_grid(dir / "missing.csv", 5e-3, 1e3); },
                           ErrorKind::Input, {"missing.csv"}));
  EXPECT_TRUE(throws_error([&] { read_pressure_grid(dir / "g.csv", 0.0, 1e3); }, ErrorKind::Input,
                           {"pixel"}));
}

TEST(PressureTemplate, AlignsATurnedMirroredAndStretchedFootprint) {
  // The template: the pattern with its length along the grid's rows (y),
  // 0.26 m long, the side across mirrored (v → −v), 5 mm pixels.
  PressureGrid t;
  t.pixel = 5e-3;
  t.pressure = Eigen::MatrixXd::Zero(64, 30);
  for (Eigen::Index r = 0; r < t.pressure.rows(); ++r) {
    for (Eigen::Index c = 0; c < t.pressure.cols(); ++c) {
      const double x = (static_cast<double>(c) + 0.5) * t.pixel - 0.075,
                   y = (static_cast<double>(r) + 0.5) * t.pixel - 0.16;
      t.pressure(r, c) = pattern(y / 0.13, -x / 0.13);
    }
  }
  // The simulation: the same pattern along x, 0.2 m long, seen along +z.
  const Skin s = skin(0.1, 80);
  const TemplateComparison c =
      compare_with_template(s.mesh, s.pressure, Eigen::Vector3d::UnitZ(), t);
  EXPECT_GT(c.correlation, 0.97);
  EXPECT_NEAR(c.length_scale, 1.3, 0.03);
  EXPECT_NEAR(c.width_scale, 1.3, 0.05);
  EXPECT_NEAR(c.template_peak, t.pressure.maxCoeff(), 1e-9);
  EXPECT_NEAR(c.simulated_peak / c.template_peak, 1.0, 0.1);
  EXPECT_GT(c.pixels, 500);
  // Reversed along its length, it is found as well as before: the alignment
  // tries each way the axes can point.
  Skin reversed = s;
  for (Eigen::Index v = 0; v < reversed.mesh.V.rows(); ++v)
    reversed.mesh.V(v, 0) = -reversed.mesh.V(v, 0);
  const TemplateComparison r =
      compare_with_template(reversed.mesh, reversed.pressure, Eigen::Vector3d::UnitZ(), t);
  EXPECT_NEAR(r.correlation, c.correlation, 0.01);
  // The picture: two panels of the grid's pixels and the correlation.
  ScratchDir dir;
  write_template_comparison_svg(dir / "t.svg", c, t, "simulated", "template");
  const palpa::test::XmlDocument doc =
      palpa::test::parse_xml(palpa::test::read_text(dir / "t.svg"));
  ASSERT_TRUE(doc.ok()) << doc.error;
  EXPECT_EQ(doc.all("rect", "map").size(), 2u * 64u * 30u);
  bool said = false;
  for (const auto* e : doc.all("text"))
    said = said || e->text.find("correlation r = ") != std::string::npos;
  EXPECT_TRUE(said);
  // No contact: a clear refusal.
  EXPECT_TRUE(throws_error(
      [&] {
        compare_with_template(s.mesh, Eigen::VectorXd::Zero(s.pressure.size()),
                              Eigen::Vector3d::UnitZ(), t);
      },
      ErrorKind::Input, {"no footprint"}));
}

}  // namespace
}  // namespace palpa::report
