// SPDX-License-Identifier: AGPL-3.0-or-later
// Compression of a whole cylindrical sample between two plates in the
// axisymmetric poke engine: mesh, derivatives of the system and of the force
// with the side wall folded onto the platens, sensitivities, bad input.
// Physics (analytic limits, convergence, deep compression):
// compression_physics_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "axisym/poke_fixtures.hpp"
#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/axisym/poke.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::axisym {
namespace {

using palpa::test::derivatives_match;
using namespace palpa::axisym::test;

constexpr double kR = 5e-3;  // sample radius [m]
constexpr double kHeight = 5e-3;  // sample height [m]

// ---------------------------------------------------------------- mesh

TEST(CylinderMesh, CoversTheSampleAndGradesTowardTheFreeCorners) {
  for (const auto& [radius, height] : {std::pair{kR, kHeight}, std::pair{kR, 4 * kHeight}, std::pair{4 * kR, kHeight}}) {
    const AxisymMesh m0 = make_cylinder_mesh(LayerGeometry{radius, height, 0.0}, 0);
    EXPECT_EQ(m0.geometry.punch_radius, radius);
    EXPECT_EQ(m0.geometry.outer_radius, radius);
    EXPECT_EQ(m0.geometry.thickness, height);
    EXPECT_EQ(m0.nodes.col(0).minCoeff(), 0.0);
    EXPECT_EQ(m0.nodes.col(0).maxCoeff(), radius);
    EXPECT_EQ(m0.nodes.col(1).maxCoeff(), 0.0);
    EXPECT_NEAR(m0.nodes.col(1).minCoeff(), -height, 1e-15);
    // At least kCylinderCells cells across the shorter side.
    EXPECT_GE(std::min(m0.columns, m0.rows) - 1, kCylinderCells);
    // Columns shrink toward the side wall; rows toward both platens, symmetric.
    const auto width = [&](int i) { return m0.nodes(m0.node(i + 1, 0), 0) - m0.nodes(m0.node(i, 0), 0); };
    const auto tall = [&](int j) { return m0.nodes(m0.node(0, j + 1), 1) - m0.nodes(m0.node(0, j), 1); };
    for (int i = 0; i + 2 < m0.columns; ++i) EXPECT_GT(width(i), width(i + 1));
    EXPECT_NEAR(width(0) / width(m0.columns - 2), kCylinderGrading, 1e-9);
    const int cells = m0.rows - 1;
    for (int j = 0; j < cells / 2 - 1; ++j) {
      EXPECT_LT(tall(j), tall(j + 1));
      EXPECT_NEAR(tall(j), tall(cells - 1 - j), 1e-12 * height);
    }
    EXPECT_NEAR(m0.rim_cell_size, std::min(width(m0.columns - 2), tall(0)), 1e-15);
    // Levels nest: level 2 keeps every level-0 node and quarters the corner cell.
    const AxisymMesh m2 = make_cylinder_mesh(LayerGeometry{radius, height, 0.0}, 2);
    EXPECT_EQ(m2.columns - 1, 4 * (m0.columns - 1));
    EXPECT_EQ(m2.rows - 1, 4 * (m0.rows - 1));
    EXPECT_DOUBLE_EQ(m2.rim_cell_size, m0.rim_cell_size / 4);
    EXPECT_EQ(m2.nodes(m2.node(4, 4), 0), m0.nodes(m0.node(1, 1), 0));
    EXPECT_EQ(side_wall_nodes(m2).size(), static_cast<std::size_t>(m2.rows - 2));
  }
  // The sample radius may be given as the outer radius instead.
  EXPECT_EQ(make_cylinder_mesh(LayerGeometry{0.0, kHeight, kR}, 0).geometry.punch_radius, kR);
}

// ---------------------------------------------------------------- system derivatives

// A bonded sample compressed until its bulging side wall folds onto both
// platens; returns the equilibrium.
Eigen::VectorXd folded_state(PokeSimulator& sim) {
  PokeOptions o;
  o.max_depth = 0.6 * kHeight;
  o.steps = 12;
  Eigen::VectorXd x_star;
  sim.run(o, [&](const PokeModel&, const Eigen::VectorXd& x, const PokeSample&) { x_star = x; });
  return x_star;
}

TEST(CompressionModel, GradientAndHessianMatchFiniteDifferencesWithTheWallOnThePlatens) {
  const material::NeoHookean m(kE, 0.45);
  PokeSimulator sim(m, compression_setup(kR, kHeight, 0, PunchContact::Stick));
  Eigen::VectorXd x_star = folded_state(sim);
  PokeModel& model = sim.model();
  const int touching = model.diagnostics(x_star).contact_nodes;
  ASSERT_GE(touching, 2) << "the test needs wall nodes on both platens";
  // Steps stay well inside the current contact set: below a tenth of the
  // smallest distance of a wall node to either platen plane.
  const AxisymMesh& mesh = model.mesh();
  const auto closest = [&](const Eigen::VectorXd& x) {
    const Eigen::MatrixX2d u = model.displacements(x);
    double out = std::numeric_limits<double>::infinity();
    for (int n : side_wall_nodes(mesh)) {
      const double z = mesh.nodes(n, 1) + u(n, 1);
      out = std::min({out, std::abs(z + model.depth()), std::abs(z + kHeight)});
    }
    return out;
  };
  auto rng = palpa::test::make_rng(31);
  std::normal_distribution<double> n01;
  // Off the equilibrium (where g would vanish), with the contact set unchanged.
  Eigen::VectorXd w(model.num_dofs());
  for (Eigen::Index i = 0; i < w.size(); ++i) w[i] = n01(rng);
  x_star += (0.1 * closest(x_star) / w.cwiseAbs().maxCoeff()) * w;
  ASSERT_EQ(model.diagnostics(x_star).contact_nodes, touching);
  Eigen::VectorXd v(model.num_dofs());
  for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = n01(rng);
  v *= 0.1 * closest(x_star) / v.cwiseAbs().maxCoeff();
  RecordProperty("closest_to_a_platen_m", std::to_string(closest(x_star)));
  const auto e_of = [&](const Eigen::VectorXd& t) { return model.energy(x_star + t[0] * v); };
  const auto g_of = [&](const Eigen::VectorXd& t) {
    Eigen::VectorXd g;
    model.gradient(x_star + t[0] * v, g);
    return g;
  };
  Eigen::VectorXd g;
  model.gradient(x_star, g);
  Eigen::SparseMatrix<double> h;
  model.set_true_hessian(true);
  model.hessian(x_star, h);
  const Eigen::SparseMatrix<double> full = h.selfadjointView<Eigen::Lower>();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1);
  EXPECT_TRUE(derivatives_match(Eigen::VectorXd::Constant(1, g.dot(v)),
                                palpa::test::fd_gradient(e_of, zero, 1.0), 1e-6));
  EXPECT_TRUE(derivatives_match(full * v, palpa::test::fd_jacobian(g_of, zero, 1.0), 1e-5));
  // ∂F/∂x, including the penalty forces of the wall nodes on the top platen.
  Eigen::VectorXd dfdx;
  Eigen::VectorXd dfdtheta;
  model.punch_force_derivatives(x_star, dfdx, dfdtheta);
  const auto f_of = [&](const Eigen::VectorXd& t) { return model.punch_force(x_star + t[0] * v); };
  EXPECT_TRUE(derivatives_match(Eigen::VectorXd::Constant(1, dfdx.dot(v)),
                                palpa::test::fd_gradient(f_of, zero, 1.0), 1e-6));
}

TEST(CompressionModel, PlatenForcesBalanceAndIncludeTheFoldedWall) {
  const material::NeoHookean m(kE, 0.45);
  PokeSimulator sim(m, compression_setup(kR, kHeight, 0, PunchContact::Stick));
  const Eigen::VectorXd x = folded_state(sim);
  const PokeModel& model = sim.model();
  const AxisymMesh& mesh = model.mesh();
  // Forces from the contact pressures times the nodes' rest areas: rings on
  // the top and base, 2π R ℓ on the wall.
  const Eigen::VectorXd p = model.contact_pressure(x);
  const Eigen::MatrixX2d u = model.displacements(x);
  double top = 0.0;
  double base = 0.0;
  for (std::size_t k = 0; k < mesh.top_nodes.size(); ++k) {
    const double r = mesh.nodes(mesh.top_nodes[k], 0);
    const double lo = k == 0 ? r : 0.5 * (r + mesh.nodes(mesh.top_nodes[k - 1], 0));
    const double hi = k + 1 == mesh.top_nodes.size() ? r : 0.5 * (r + mesh.nodes(mesh.top_nodes[k + 1], 0));
    const double area = std::numbers::pi * (hi * hi - lo * lo);
    top += p[mesh.top_nodes[k]] * area;
    base += p[mesh.base_nodes[k]] * area;
  }
  double wall_on_top = 0.0;
  double wall_on_base = 0.0;
  for (int n : side_wall_nodes(mesh)) {
    const double area = 2 * std::numbers::pi * kR * 0.5 * (mesh.nodes(n + mesh.columns, 1) - mesh.nodes(n - mesh.columns, 1));
    (mesh.nodes(n, 1) + u(n, 1) > -0.5 * kHeight - 0.5 * model.depth() ? wall_on_top : wall_on_base) += p[n] * area;
  }
  EXPECT_GT(wall_on_top, 0.0) << "a wall node should press on the top platen";
  EXPECT_GT(wall_on_base, 0.0) << "a wall node should press on the base";
  const double force = model.punch_force(x);
  EXPECT_NEAR(top + wall_on_top, force, 1e-12 * force);
  // The sample is in equilibrium: the base pushes up as hard as the top presses down.
  EXPECT_NEAR(base + wall_on_base, force, 1e-6 * force);
}

// ---------------------------------------------------------------- sensitivities

TEST(CompressionSensitivities, MatchFiniteDifferencesOfWholeCurves) {
  const material::NeoHookean nh(kE, 0.45);
  const material::SplineMaterial spline = material::SplineMaterial::from_model(nh);
  for (PunchContact platens : {PunchContact::Stick, PunchContact::Frictionless}) {
    for (const material::Material* m : {static_cast<const material::Material*>(&nh),
                                        static_cast<const material::Material*>(&spline)}) {
      PokeOptions o;
      // Bonded: deep enough for the wall to fold onto the platens.
      o.max_depth = 0.6 * kHeight;
      o.steps = 6;
      o.sensitivities = true;
      PokeSimulator sim(*m, compression_setup(kR, kHeight, 0, platens));
      const PokeCurve c = sim.run(o);
      if (platens == PunchContact::Stick) {
        ASSERT_GT(c.samples.back().contact_nodes, 0);
      }
      test::expect_curve_sensitivities(sim, c, o, kE, std::string(platen_contact_name(platens)));
    }
  }
}

// ---------------------------------------------------------------- bad input

TEST(CompressionInput, RefusesImpossibleSetups) {
  const material::NeoHookean m(kE, 0.45);
  using palpa::test::throws_error;
  EXPECT_TRUE(throws_error([&] { PokeSimulator(m, compression_setup(kR, -1.0, 0, PunchContact::Stick)); },
                           ErrorKind::Input, {"sample height", "not a positive length"}));
  EXPECT_TRUE(throws_error([&] { PokeSimulator(m, compression_setup(0.0, kHeight, 0, PunchContact::Stick)); },
                           ErrorKind::Input, {"sample radius", "not a positive length"}));
  PokeSetup s = compression_setup(kR, kHeight, 0, PunchContact::Stick);
  s.fillet_radius = 0.1 * kR;
  EXPECT_TRUE(throws_error([&] { PokeSimulator sim(m, s); }, ErrorKind::Input, {"fillet", "compression"}));
  s.fillet_radius = 0.0;
  s.geometry.outer_radius = 2 * kR;
  EXPECT_TRUE(throws_error([&] { PokeSimulator sim(m, s); }, ErrorKind::Input,
                           {"outer radius", "differs from the sample radius"}));
  s.geometry.outer_radius = kR;  // the same radius twice is fine
  PokeSimulator sim(m, s);
  PokeOptions o;
  o.max_depth = 0.95 * kHeight;
  EXPECT_TRUE(throws_error([&] { sim.run(o); }, ErrorKind::Input, {"below 90% of the sample height"}));
  EXPECT_EQ(parse_poke_test("compression"), PokeTest::Compression);
  EXPECT_EQ(parse_platen_contact("bonded"), PunchContact::Stick);
  EXPECT_EQ(platen_contact_name(PunchContact::Frictionless), "frictionless");
  EXPECT_TRUE(throws_error([] { parse_poke_test("shear"); }, ErrorKind::Input, {"unknown test 'shear'"}));
  EXPECT_TRUE(throws_error([] { parse_platen_contact("stick"); }, ErrorKind::Input,
                           {"unknown platen contact 'stick'"}));
}

}  // namespace
}  // namespace palpa::axisym
