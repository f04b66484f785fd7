// SPDX-License-Identifier: AGPL-3.0-or-later
// A body resting on a deformable support (thesis §7.4.3): the coupled
// system's gradient and Hessian against differences; a soft block on a foam
// slab with ν = 0 (uniaxial compression: the slab's top sinks by p·h/E and
// its base carries the weight); a stiff slab gives the rigid slab's answer;
// states round-trip; bad setups refused.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "common/test_support.hpp"
#include "palpa/material/models.hpp"
#include "palpa/rest/coupled.hpp"
#include "palpa/rest/rest.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "palpa/tet/mesh.hpp"
#include "rest/block_constants.hpp"
#include "rest/rest_fixtures.hpp"

namespace palpa::rest {
namespace {

using namespace test;

RestOptions on_foam(double E, double nu, double edge) {
  RestOptions o;
  o.core.locked = {true, true, false, true, true, true};
  o.core.mass = 0.2;
  o.deformable_support = DeformableSupport{std::make_shared<material::NeoHookean>(E, nu), edge, 1e-4};
  return o;
}

TEST(DeformableSupport, CoupledGradientAndHessianMatchDifferences) {
  RestOptions o = on_foam(30e3, 0.3, 8e-3);
  o.core.locked = {true, true, false, false, false, true};  // the core tilts too
  o.core.torque = Eigen::Vector3d(1e-3, -2e-3, 0.0);
  RestSimulation sim(hanging_block(4, 0.3, 3e-4), square_slab(0.06, 0.012, 8), o);
  sim.solve();
  ASSERT_TRUE(sim.deformable_support());
  ASSERT_GT(sim.contact_term().potential().size(), 8u);
  CoupledSystem& system = *sim.coupled_system();
  Eigen::VectorXd y(system.num_dofs());
  y << sim.dofs(), sim.support_dofs();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd d(y.size());
  for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = u(rng);
  // Away from the equilibrium (so the gradient is not ~0), its contacts
  // committed there.
  Eigen::VectorXd y0 = y + 2e-6 * d;
  system.prepare(y0);
  Eigen::VectorXd g;
  system.gradient(y0, g);
  Eigen::SparseMatrix<double> H;
  system.hessian(y0, H);
  const double h = 1e-8;
  const double fd_e = (system.energy(y0 + h * d) - system.energy(y0 - h * d)) / (2 * h);
  EXPECT_NEAR(g.dot(d), fd_e, 1e-5 * std::abs(fd_e));
  Eigen::VectorXd gp, gm;
  system.gradient(y0 + h * d, gp);
  system.gradient(y0 - h * d, gm);
  const Eigen::VectorXd fd_g = (gp - gm) / (2 * h);
  const Eigen::SparseMatrix<double> full = H.selfadjointView<Eigen::Lower>();
  const Eigen::VectorXd Hd = full * d;
  EXPECT_LT((Hd - fd_g).norm(), 1e-5 * fd_g.norm());
  // The coupling blocks are really there: without them the product is off.
  const Eigen::Index nb = system.num_body_dofs();
  Eigen::VectorXd d_body = d, d_support = d;
  d_body.tail(y.size() - nb).setZero();
  d_support.head(nb).setZero();
  const Eigen::VectorXd cross = (full * d_body).tail(y.size() - nb);
  EXPECT_GT(cross.norm(), 1e-3 * (full * d_support).tail(y.size() - nb).norm());
}

TEST(DeformableSupport, FoamSlabUnderABlockCompressesByPressureTimesThicknessOverE) {
  // ν = 0 in both: uniaxial compression, p·h/E under the block's middle.
  const double E = 50e3, hs = 0.008;
  RestSimulation sim(hanging_block(8, 0.0, 3e-4), square_slab(0.048, hs, 12), on_foam(E, 0.0, 4e-3));
  const RestResult r = sim.solve();
  const double weight = (kRho * kW * kW * kH + 0.2) * kG;
  EXPECT_NEAR(r.contact_force.z(), weight, 0.005 * weight);
  // The ground carries it all through the slab's base.
  EXPECT_NEAR(r.support_base_force.z(), weight, 0.005 * weight);
  // The slab is in equilibrium: its base carries what the body presses on it
  // (sideways too, where the locked core holds the body).
  EXPECT_LT((r.support_base_force - r.contact_force).norm(), 1e-3 * weight);
  const double p = weight / (kW * kW);
  const double expected = p * hs / E;
  const Eigen::MatrixX3d& X = sim.support_rest_vertices();
  int middle = 0;
  double mean = 0.0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    if (X(v, 2) > -1e-9 && std::abs(X(v, 0)) < 0.22 * kW && std::abs(X(v, 1)) < 0.22 * kW) {
      const double sink = X(v, 2) - sim.support().world_vertex(static_cast<int>(v)).z();
      // The tets are TetGen's, two across the thickness: each vertex is
      // within 20%, their mean within 5%.
      EXPECT_NEAR(sink, expected, 0.2 * expected) << v;
      mean += sink;
      ++middle;
    }
  }
  ASSERT_GE(middle, 4);
  mean /= middle;
  EXPECT_NEAR(mean, expected, 0.05 * expected);
  // Under a flat rigid block the slab sinks alike everywhere beneath it.
  EXPECT_NEAR(r.support_max_displacement, expected, 0.2 * expected);
  EXPECT_GT(r.support_min_det_f, 0.9);
  // The contact pressure under the middle is still about the mean pressure.
  EXPECT_GT(r.max_penetration, 0.85 * 3e-4);
  EXPECT_LT(r.max_penetration, 1.15 * 3e-4);
}

TEST(DeformableSupport, AStiffSlabGivesTheRigidSlabsAnswer) {
  const SurfaceMesh s = square_slab(0.06, 0.01, 12);
  RestOptions rigid = on_foam(1.0, 0.3, 0.0);
  rigid.deformable_support.reset();
  RestSimulation a(hanging_block(6, 0.3, 3e-4), s, rigid);
  const RestResult ra = a.solve();
  RestSimulation b(hanging_block(6, 0.3, 3e-4), s, on_foam(2e6, 0.3, 5e-3));  // 100 × the body
  const RestResult rb = b.solve();
  const double sink = std::abs(ra.core_translation.z());
  EXPECT_LT(rb.support_max_displacement, 0.02 * sink);
  EXPECT_NEAR(rb.core_translation.z(), ra.core_translation.z(), 0.02 * sink);
  // The pressure under the block's middle (at its rim the deformable slab's
  // own vertices press back on the body too: two passes, not one).
  const TetMesh& mesh = a.model().mesh();
  // Where the slab's vertices fall between the body's, they take a share of
  // its vertices' load: each within 20%, the mean within 3%.
  int middle = 0;
  double mean_a = 0.0, mean_b = 0.0;
  for (int v : a.surface_vertices()) {
    if (mesh.V(v, 2) < 4e-4 && std::abs(mesh.V(v, 0)) < 0.3 * kW && std::abs(mesh.V(v, 1)) < 0.3 * kW) {
      EXPECT_NEAR(rb.body_pressure[v], ra.body_pressure[v], 0.2 * ra.body_pressure[v]) << v;
      mean_a += ra.body_pressure[v];
      mean_b += rb.body_pressure[v];
      ++middle;
    }
  }
  EXPECT_GE(middle, 4);
  EXPECT_NEAR(mean_b, mean_a, 0.03 * mean_a);
  // A soft slab lets the core sink deeper: p·h/E is 0.7 mm, less where the
  // slab around the block holds it (ν = 0.3); 0.39 mm measured.
  RestSimulation c(hanging_block(6, 0.3, 3e-4), s, on_foam(20e3, 0.3, 5e-3));
  const RestResult rc = c.solve();
  EXPECT_LT(rc.core_translation.z(), ra.core_translation.z() - 2.5e-4);
  EXPECT_GT(rc.support_max_displacement, 5e-4);
}

TEST(DeformableSupport, StateRoundTripsAndTheRestShapeMoves) {
  RestSimulation sim(hanging_block(4, 0.3, 3e-4), square_slab(0.06, 0.01, 8), on_foam(30e3, 0.3, 6e-3));
  const RestResult r1 = sim.solve();
  const RestState s = sim.state();
  EXPECT_EQ(s.support.size(), sim.support_dofs().size());
  EXPECT_GT(s.support.norm(), 0.0);
  // Lowering the top's middle by 1 mm moves the rest shape, not the state.
  const Eigen::MatrixX3d X0 = sim.support_rest_vertices();
  Eigen::MatrixX3d X = X0;
  for (Eigen::Index v = 0; v < X.rows(); ++v) {
    if (X(v, 2) > -1e-9 && std::abs(X(v, 0)) < 0.01 && std::abs(X(v, 1)) < 0.01) X(v, 2) -= 1e-3;
  }
  sim.set_support_vertices(X);
  EXPECT_TRUE(sim.support_rest_vertices().isApprox(X));
  sim.solve();
  sim.restore(s);
  sim.set_support_vertices(X0);
  const RestResult r2 = sim.solve();
  EXPECT_NEAR(r2.core_translation.z(), r1.core_translation.z(), 1e-9);
  // A move that turns a top tet inside out is refused as a failed solve,
  // leaving the shape as it was.
  Eigen::MatrixX3d bad = sim.support_rest_vertices();
  Eigen::Index top = 0;
  bad.col(2).maxCoeff(&top);
  bad(top, 2) -= 0.03;  // through the 10 mm slab
  const Eigen::MatrixX3d before = sim.support_rest_vertices();
  EXPECT_TRUE(palpa::test::throws_error([&] { sim.set_support_vertices(bad); }, ErrorKind::Solver, {"tetrahedron"}));
  EXPECT_TRUE(sim.support_rest_vertices().isApprox(before));
}

TEST(DeformableSupport, RefusesBadSetups) {
  RestOptions o = on_foam(30e3, 0.3, 6e-3);
  o.deformable_support->material.reset();
  EXPECT_TRUE(palpa::test::throws_error(
      [&] { RestSimulation s(hanging_block(4, 0.3, 3e-4), square_slab(0.06, 0.01, 8), o); }, ErrorKind::Input,
      {"deformable support", "no material"}));
  o = on_foam(30e3, 0.3, -1.0);
  EXPECT_TRUE(palpa::test::throws_error(
      [&] { RestSimulation s(hanging_block(4, 0.3, 3e-4), square_slab(0.06, 0.01, 8), o); }, ErrorKind::Input, {"tet edge"}));
  // A ball has no flat base to stand on.
  o = on_foam(30e3, 0.3, 0.0);
  o.deformable_support->base_tolerance = 0.0;
  SurfaceMesh ball = sim3d::make_sphere(0.03, 2);
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.1, Eigen::Vector3d(1, 0.3, 0).normalized()).toRotationMatrix();
  ball.V = (ball.V * tilt.transpose()).eval();  // one lowest vertex
  ball.V.col(2).array() -= 0.0305;
  EXPECT_TRUE(palpa::test::throws_error([&] { RestSimulation s(hanging_block(4, 0.3, 3e-4), ball, o); }, ErrorKind::Input,
                                        {"on its base", "flat base"}));
}

}  // namespace
}  // namespace palpa::rest
