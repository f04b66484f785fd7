// SPDX-License-Identifier: AGPL-3.0-or-later
// Gravity sag of a column against linear elasticity.
#include <gtest/gtest.h>

#include <memory>

#include "palpa/material/models.hpp"
#include "palpa/solve/newton.hpp"
#include "palpa/tet/mesh.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::tet {
namespace {

TEST(GravitySag, ColumnOnRollersMatchesLinearElasticityAtSmallLoad) {
  // A column of height H standing on rollers (u_z = 0 at the bottom, pinned
  // against rigid motion) under its own weight: uniaxial stress
  // σzz = −ρg(H − z) and a top displacement of −ρgH²/(2E) in linear
  // elasticity. With ν = 0 there is no lateral strain, so rollers are exactly
  // that solution's boundary condition (with ν > 0 its base would curve), and
  // linear elements are nodally exact along z. ρgH/E = 1e-3: the nonlinear
  // answer is within a few 0.1% of the linear one.
  const double E = 20e3, nu = 0.0, rho = 1000.0, g = 9.81, H = 0.02;
  const double scale = 1e-3 * E / (rho * g * H);  // gravity multiplier for ρgH/E = 1e-3
  BoxMesh box = make_box_mesh(Eigen::Vector3d(-0.005, -0.005, 0.0), Eigen::Vector3d(0.005, 0.005, H),
                              Eigen::Vector3i(2, 2, 8));
  const ElasticModel model(box.mesh, {BodyMaterial{std::make_shared<material::NeoHookean>(E, nu), rho}});
  std::vector<char> fixed(static_cast<std::size_t>(model.num_dofs()), 0);
  for (int v : box.vertex_sets.at("bottom")) fixed[static_cast<std::size_t>(3 * v + 2)] = 1;
  // Against rigid motion in the plane: the bottom centre fully, a second
  // bottom vertex on the x axis in y.
  int centre = -1, on_axis = -1;
  for (int v : box.vertex_sets.at("bottom")) {
    if (box.mesh.V.row(v).head<2>().norm() < 1e-12) centre = v;
    if (std::abs(box.mesh.V(v, 1)) < 1e-12 && box.mesh.V(v, 0) > 0.004) on_axis = v;
  }
  ASSERT_GE(centre, 0);
  ASSERT_GE(on_axis, 0);
  fixed[static_cast<std::size_t>(3 * centre)] = fixed[static_cast<std::size_t>(3 * centre + 1)] = 1;
  fixed[static_cast<std::size_t>(3 * on_axis + 1)] = 1;
  StaticSystem sys(model, fixed);
  sys.set_gravity(Eigen::Vector3d(0.0, 0.0, -g * scale));
  NewtonOptions opt;
  opt.gradient_rel_tol = 1e-10;
  opt.gradient_accept_tol = 1e-9 * model.total_mass() * g * scale / static_cast<double>(model.num_vertices());
  NewtonSolver newton(opt);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(sys.num_dofs());
  ASSERT_TRUE(newton.solve(sys, x).converged());
  const Eigen::VectorXd u = sys.full_displacement(x);
  const double expected = -rho * g * scale * H * H / (2.0 * E);
  for (int v : box.vertex_sets.at("top")) {
    if (box.mesh.V.row(v).head<2>().norm() < 1e-12) {
      EXPECT_NEAR(u[3 * v + 2], expected, 3e-3 * std::abs(expected));
    }
  }
  // The support carries the weight.
  const Eigen::VectorXd react = sys.reactions(x);
  double fz = 0.0;
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) fz += react[3 * v + 2];
  EXPECT_NEAR(fz, model.total_mass() * g * scale, 1e-8 * model.total_mass() * g * scale);
}

}  // namespace
}  // namespace palpa::tet
