// SPDX-License-Identifier: AGPL-3.0-or-later
// The figures of a pressure map on analytic maps: a uniform disc (force,
// contact area, mean = peak = PPI = p95, centre, the window's share) and a
// Hertz profile p0·√(1 − r²/a²) (force ⅔πa²p0, p95 = p0·√0.95, the peak
// pressure index as the mean over a disc of the window's area), a one-vertex
// spike that moves the peak but not the index, a contact area given per
// vertex, and bad input.

#include "palpa/report/pressure_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/square_grid.hpp"
#include "common/test_support.hpp"
#include "palpa/geometry/surface_operators.hpp"

namespace palpa::report {
namespace {

constexpr double kH = 1e-3;    // grid spacing [m]
constexpr double kA = 0.03;    // contact radius [m]
constexpr double kP0 = 20e3;   // [Pa]
constexpr int kN = 100;        // cells per side

// A flat (kN × kN)-cell grid of side kN·kH centred on (0.01, −0.02, 0.3).
SurfaceMesh grid() { return test::square_grid(kN, kN * kH, Eigen::Vector3d(0.01, -0.02, 0.3)); }

Eigen::VectorXd radial(const SurfaceMesh& m, double (*profile)(double)) {
  Eigen::VectorXd p(m.V.rows());
  for (Eigen::Index v = 0; v < p.size(); ++v) {
    const double r = (m.V.row(v) - Eigen::RowVector3d(0.01, -0.02, 0.3)).norm();
    p[v] = r < kA ? profile(r) : 0.0;
  }
  return p;
}

TEST(PressureMetrics, AUniformDisc) {
  const SurfaceMesh m = grid();
  const Eigen::VectorXd p = radial(m, [](double) { return kP0; });
  const PressureMetrics s = pressure_metrics(m, p);
  const double disc = std::numbers::pi * kA * kA;
  EXPECT_NEAR(s.force, kP0 * disc, 0.01 * kP0 * disc);
  EXPECT_NEAR(s.contact_area, disc, 0.01 * disc);
  EXPECT_NEAR(s.mean, kP0, 1e-9 * kP0);
  EXPECT_EQ(s.peak, kP0);
  EXPECT_NEAR(s.peak_pressure_index, kP0, 1e-9 * kP0);
  EXPECT_EQ(s.p95, kP0);
  EXPECT_LT((s.centre - Eigen::Vector3d(0.01, -0.02, 0.3)).norm(), 1e-9);
  // The window holds 9 cm² of the disc's load.
  EXPECT_NEAR(s.dispersion_index, 9e-4 / s.contact_area, 1e-9);
  EXPECT_EQ(s.contact_vertices, static_cast<int>((p.array() > 0.0).count()));
}

TEST(PressureMetrics, AHertzProfile) {
  const SurfaceMesh m = grid();
  const Eigen::VectorXd p = radial(m, [](double r) { return kP0 * std::sqrt(1.0 - r * r / (kA * kA)); });
  const PressureMetrics s = pressure_metrics(m, p);
  const double force = 2.0 / 3.0 * std::numbers::pi * kA * kA * kP0;
  EXPECT_NEAR(s.force, force, 0.01 * force);
  EXPECT_NEAR(s.mean, 2.0 / 3.0 * kP0, 0.01 * kP0);
  EXPECT_EQ(s.peak, kP0);  // at the centre vertex
  // Area below q: π a² (q/p0)², so the 95th percentile is p0·√0.95.
  EXPECT_NEAR(s.p95, kP0 * std::sqrt(0.95), 0.01 * kP0);
  // The mean over a disc of radius b (the window's area) at the centre:
  // ⅔ p0 (a/b)² (1 − (1 − b²/a²)^{3/2}); its share of the force
  // 1 − (1 − b²/a²)^{3/2}.
  const double b2 = 9e-4 / std::numbers::pi, q = 1.0 - std::pow(1.0 - b2 / (kA * kA), 1.5);
  EXPECT_NEAR(s.peak_pressure_index, 2.0 / 3.0 * kP0 * kA * kA / b2 * q, 0.01 * kP0);
  EXPECT_NEAR(s.dispersion_index, q, 0.02 * q);
  EXPECT_LT(s.peak_pressure_index, s.peak);
}

TEST(PressureMetrics, AOneVertexSpikeMovesThePeakNotTheIndex) {
  const SurfaceMesh m = grid();
  Eigen::VectorXd p = radial(m, [](double r) { return kP0 * std::sqrt(1.0 - r * r / (kA * kA)); });
  const PressureMetrics before = pressure_metrics(m, p);
  p[(kN / 2 + 20) * (kN + 1) + kN / 2] = 10.0 * kP0;  // 20 mm off the centre
  const PressureMetrics after = pressure_metrics(m, p);
  EXPECT_EQ(after.peak, 10.0 * kP0);
  EXPECT_LT(std::abs(after.peak_pressure_index - before.peak_pressure_index), 0.03 * before.peak_pressure_index);
  EXPECT_LT(std::abs(after.p95 - before.p95), 0.01 * before.p95);
}

TEST(PressureMetrics, TheAreaInContactGivenIsTheContactArea) {
  // The uniform disc with its rim vertices half in contact: the patch's area
  // and the mean follow the areas given, the peak and the force do not.
  const SurfaceMesh m = grid();
  const Eigen::VectorXd p = radial(m, [](double) { return kP0; });
  const Eigen::VectorXd area = geometry::vertex_areas(m);
  Eigen::VectorXd in_contact = Eigen::VectorXd::Zero(p.size());
  double rim = 0.0;
  for (Eigen::Index v = 0; v < p.size(); ++v) {
    if (p[v] == 0.0) continue;
    const bool on_rim = (m.V.row(v) - Eigen::RowVector3d(0.01, -0.02, 0.3)).norm() > kA - kH;
    in_contact[v] = on_rim ? 0.5 * area[v] : area[v];
    if (on_rim) rim += 0.5 * area[v];
  }
  const PressureMetrics all = pressure_metrics(m, p);
  const PressureMetrics part = pressure_metrics(m.V, area, p, in_contact);
  EXPECT_GT(rim, 0.0);
  EXPECT_NEAR(part.contact_area, all.contact_area - rim, 1e-12 * all.contact_area);
  EXPECT_NEAR(part.mean, part.force / part.contact_area, 1e-9 * kP0);
  EXPECT_EQ(part.force, all.force);
  EXPECT_EQ(part.peak, all.peak);
  // More area in contact than the vertex has is refused.
  in_contact[(kN / 2) * (kN + 1) + kN / 2] = 2.0 * area[(kN / 2) * (kN + 1) + kN / 2];
  EXPECT_TRUE(test::throws_error([&] { pressure_metrics(m.V, area, p, in_contact); }, ErrorKind::Input,
                                 {"in contact"}));
}

TEST(PressureMetrics, NoContactAndBadInput) {
  const SurfaceMesh m = grid();
  const PressureMetrics none = pressure_metrics(m, Eigen::VectorXd::Zero(m.V.rows()));
  EXPECT_EQ(none.force, 0.0);
  EXPECT_EQ(none.contact_vertices, 0);
  Eigen::VectorXd p = Eigen::VectorXd::Zero(m.V.rows());
  p[7] = -1.0;
  EXPECT_TRUE(test::throws_error([&] { pressure_metrics(m, p); }, ErrorKind::Input, {"vertex 7", "-1"}));
  EXPECT_TRUE(test::throws_error([&] { pressure_metrics(m.V, Eigen::VectorXd::Ones(3), p); }, ErrorKind::Input,
                                 {"3 areas"}));
  PressureMetricsOptions o;
  o.window_area = 0.0;
  EXPECT_TRUE(test::throws_error([&] { pressure_metrics(m, Eigen::VectorXd::Zero(m.V.rows()), o); }, ErrorKind::Input,
                                 {"window"}));
}

}  // namespace
}  // namespace palpa::report
