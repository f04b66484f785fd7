// SPDX-License-Identifier: AGPL-3.0-or-later
// The ergonomic score, its smoothing and the smoothness term; the adjoint
// gradient of φ against central differences of re-solved equilibria; the
// optimizer on a soft block resting on a bumpy slab.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <random>

#include "palpa/design/baselines.hpp"
#include "palpa/design/checkpoint.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/geometry/surface_operators.hpp"
#include "palpa/geometry/umbrella.hpp"
#include "palpa/material/models.hpp"
#include "palpa/sim3d/shapes.hpp"
#include "palpa/tet/mesh.hpp"
#include "common/test_support.hpp"
#include "design_fixtures.hpp"

namespace palpa::design {
namespace {

using namespace fixture;

// A checkpoint reads back as written, and one of another run (method, γ,
// step lengths, filter, sizes) is refused by field.
TEST(DesignCheckpointFile, ReadsBackWhatWasWrittenAndRefusesAnotherRunsByField) {
  test::ScratchDir dir;
  DesignCheckpoint c;
  c.method = DesignMethod::ConjugateGradient;
  c.gamma = 2.5;
  c.moves = {1e-6, 1e-4};
  c.filter_radius = 0.01;
  c.iteration = 3;
  c.theta = Eigen::VectorXd::LinSpaced(4, -1e-4, 2e-4);
  c.direction = Eigen::VectorXd::Constant(4, 0.5);
  c.gradient = Eigen::VectorXd::Constant(4, -0.25);
  c.steepest = false;
  c.bodies.resize(1);
  c.bodies[0].state.x = Eigen::VectorXd::LinSpaced(6, 0.0, 1e-3);
  c.bodies[0].state.core.omega = Eigen::Vector3d(0.0, 0.01, 0.0);
  c.bodies[0].state.spring_areas = {1e-4, 2e-4};
  c.bodies[0].state.stiffness = 3e4;
  c.bodies[0].state.support = Eigen::VectorXd::Constant(3, 1e-5);
  c.phi = 10.0;
  c.zeta = 9.0;
  c.psi = 1.0;
  c.bodies[0].max_penetration = 2e-4;
  c.bodies[0].refreeze_failed = true;
  c.history = {IterationRecord{1, 11.0, 10.0, 1.0, 1e-4, 3, true, 0.5, 3e4, true}};
  c.evaluations = 7;
  c.newton_iterations = 55;
  c.seconds = 12.5;
  const auto file = dir / "checkpoint.json";
  write_json_file(file, checkpoint_json(c));
  DesignCheckpoint like = c;
  like.theta.setZero();
  like.history.clear();
  const DesignCheckpoint r = read_design_checkpoint(file, like);
  EXPECT_EQ(r.iteration, 3);
  EXPECT_EQ(r.theta, c.theta);
  EXPECT_EQ(r.direction, c.direction);
  EXPECT_EQ(r.gradient, c.gradient);
  EXPECT_FALSE(r.steepest);
  EXPECT_EQ(r.bodies[0].state.x, c.bodies[0].state.x);
  EXPECT_EQ(r.bodies[0].state.core.omega, c.bodies[0].state.core.omega);
  EXPECT_EQ(r.bodies[0].state.spring_areas, c.bodies[0].state.spring_areas);
  EXPECT_EQ(r.bodies[0].state.support, c.bodies[0].state.support);
  EXPECT_EQ(r.bodies[0].state.stiffness, c.bodies[0].state.stiffness);
  EXPECT_EQ(r.bodies[0].max_penetration, 2e-4);
  EXPECT_TRUE(r.bodies[0].refreeze_failed);
  ASSERT_EQ(r.history.size(), 1u);
  EXPECT_EQ(r.history[0].phi, 11.0);
  EXPECT_TRUE(r.history[0].refrozen);
  EXPECT_EQ(r.evaluations, 7);
  EXPECT_EQ(r.newton_iterations, 55);
  EXPECT_EQ(r.seconds, 12.5);

  const auto refused = [&](const std::function<void(DesignCheckpoint&)>& change,
                           const std::vector<std::string>& fragments) {
    DesignCheckpoint other = like;
    change(other);
    return test::throws_error([&] { read_design_checkpoint(file, other); }, ErrorKind::Input, fragments);
  };
  EXPECT_TRUE(refused([](DesignCheckpoint& o) { o.method = DesignMethod::Lbfgs; }, {"'method'", "cg method"}));
  EXPECT_TRUE(refused([](DesignCheckpoint& o) { o.gamma = 2.6; }, {"'gamma'", "differs"}));
  EXPECT_TRUE(refused([](DesignCheckpoint& o) { o.moves = {1e-6}; }, {"'moves'", "step lengths"}));
  EXPECT_TRUE(refused([](DesignCheckpoint& o) { o.filter_radius = 0.02; }, {"'filter_radius'"}));
  EXPECT_TRUE(refused([](DesignCheckpoint& o) { o.theta = Eigen::VectorXd::Zero(5); }, {"'theta'", "another design"}));
  EXPECT_TRUE(refused([](DesignCheckpoint& o) { o.bodies[0].state.x = Eigen::VectorXd::Zero(9); }, {"'state.x'"}));
}

// The design filter on the slab's top (5 mm edges): Sᵀ is S's adjoint, a
// move of one vertex becomes a smooth bump that stays in the region, and a
// uniform move passes unchanged far from the region's rim.
TEST(DesignFilter, IsSmoothAdjointAndKeepsUniformMoves) {
  const SurfaceMesh s = slab();
  const std::vector<int> region = top_inside(s, 0.031);
  const double h = design_edge_length(s, region);
  EXPECT_GT(h, 0.005);  // between the grid's legs and its diagonals
  EXPECT_LT(h, 0.005 * std::sqrt(2.0));
  for (bool normal_only : {true, false}) {
    const DesignSpace raw(s.V, s.F, region, normal_only, 0.0);
    const DesignSpace space(s.V, s.F, region, normal_only, kFilterEdges * h);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd d(space.size());
    for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = u(rng);
    Eigen::MatrixX3d G(s.V.rows(), 3);
    for (Eigen::Index i = 0; i < G.size(); ++i) G.data()[i] = u(rng);
    // ⟨G, B S d⟩ = ⟨Sᵀ Bᵀ G, d⟩: the chain rule back to θ is exact.
    const double forward = G.cwiseProduct(space.moves(d)).sum(), back = space.restrict(G).dot(d);
    EXPECT_NEAR(forward, back, 1e-12 * std::abs(forward)) << (normal_only ? "normal" : "free");

    // One vertex near the centre moved: per vertex, a spike as tall as the
    // move; filtered, a bump whose largest spike is a small part of its height,
    // nothing outside the region moved.
    Eigen::Index centre = 0;
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(region.size()); ++i) {
      if (s.V.row(region[static_cast<std::size_t>(i)]).head<2>().norm() < s.V.row(region[static_cast<std::size_t>(centre)]).head<2>().norm()) centre = i;
    }
    Eigen::VectorXd e = Eigen::VectorXd::Zero(space.size());
    e[normal_only ? centre : 3 * centre + 2] = 1.0;
    const Eigen::MatrixX3d bump = space.moves(e), spike = raw.moves(e);
    EXPECT_NEAR(geometry::largest_spike(spike, s.F, region).distance, spike.rowwise().norm().maxCoeff(), 1e-12);
    const double height = bump.rowwise().norm().maxCoeff();
    // (0.30 at 1.5 edges, 0.14 at 3: the kernel of S is a rounded cone.)
    EXPECT_LT(geometry::largest_spike(bump, s.F, region).distance, 0.35 * height);
    EXPECT_NEAR(bump.row(region[static_cast<std::size_t>(centre)]).norm(), height, 1e-12 * height);  // the peak stays put
    std::vector<char> in(static_cast<std::size_t>(s.V.rows()), 0);
    for (int v : region) in[static_cast<std::size_t>(v)] = 1;
    for (Eigen::Index v = 0; v < s.V.rows(); ++v) {
      if (!in[static_cast<std::size_t>(v)]) EXPECT_EQ(bump.row(v).norm(), 0.0);
    }
    // A uniform move of the region passes at its centre, 6 radii from the rim.
    const DesignSpace narrow(s.V, s.F, region, normal_only, 0.005);
    Eigen::VectorXd one = Eigen::VectorXd::Zero(space.size());
    for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(region.size()); ++i) one[normal_only ? i : 3 * i + 2] = 1.0;
    EXPECT_NEAR(narrow.moves(one).row(region[static_cast<std::size_t>(centre)]).norm(), 1.0, 0.025);
    EXPECT_THROW(DesignSpace(s.V, s.F, region, normal_only, -1e-3), Error);
  }
}

TEST(DesignScore, PressureSmoothingKeepsConstantsAndSpreadsASpike) {
  // A flat 5 × 5 grid: smoothing keeps a constant, halves a spike and
  // spreads the other half evenly over its ring.
  SurfaceMesh grid = sim3d::make_box_surface(Eigen::Vector3d(1, 1, 1), 4);
  const Eigen::SparseMatrix<double> W = geometry::umbrella_matrix(grid.F, grid.V.rows());
  Eigen::SparseMatrix<double> I(W.rows(), W.cols());
  I.setIdentity();
  const Eigen::SparseMatrix<double> S = 0.5 * I + 0.5 * W;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(grid.V.rows());
  EXPECT_LT((S * ones - ones).cwiseAbs().maxCoeff(), 1e-14);
  int centre = -1;
  for (Eigen::Index i = 0; i < grid.V.rows(); ++i) {
    if ((grid.V.row(i) - Eigen::RowVector3d(0, 0, 1)).norm() < 1e-12) centre = static_cast<int>(i);
  }
  ASSERT_GE(centre, 0);
  Eigen::VectorXd spike = Eigen::VectorXd::Zero(grid.V.rows());
  spike[centre] = 1.0;
  const Eigen::VectorXd smoothed = S * spike;
  EXPECT_DOUBLE_EQ(smoothed[centre], 0.5);
  int ring = 0;
  for (Eigen::Index i = 0; i < smoothed.size(); ++i) {
    if (i != centre && smoothed[i] > 0.0) {
      ++ring;
      EXPECT_NEAR(smoothed[i], 0.5 / 6.0, 1e-14);  // six neighbours each, as the centre has six
    }
  }
  EXPECT_EQ(ring, 6);
}

TEST(DesignScore, SmoothnessIsZeroOnAPlaneGridAndItsGradientMatchesDifferences) {
  // Three rounds reach six rings: the design vertices sit farther than that
  // from the slab's rim, where smoothing rounds the edges.
  SurfaceMesh s = slab(20);
  const std::vector<int> design = top_inside(s, 0.012);
  Smoothness psi(s.F, s.V.rows(), design, 3);
  EXPECT_LT(psi.evaluate(s.V), 1e-30);
  EXPECT_GT(Smoothness(s.F, s.V.rows(), top_inside(s, 0.034), 3).evaluate(s.V), 1e-8);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  Eigen::MatrixX3d X = s.V;
  for (int v : design) X(v, 2) += u(rng);
  Eigen::MatrixX3d G;
  const double value = psi.evaluate(X, &G);
  EXPECT_GT(value, 1e-9);
  Eigen::MatrixX3d D(X.rows(), 3);
  for (Eigen::Index i = 0; i < D.size(); ++i) D.data()[i] = u(rng);
  const double h = 1e-3;
  const double fd = (psi.evaluate(X + h * D) - psi.evaluate(X - h * D)) / (2 * h);  // exact: ψ is quadratic
  EXPECT_NEAR(fd, (G.array() * D.array()).sum(), 1e-9 * std::abs(fd) + 1e-18);
}

TEST(DesignScore, AreaGradientMatchesDifferences) {
  SurfaceMesh s = sim3d::make_sphere(0.05, 2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd w(s.V.rows());
  for (Eigen::Index i = 0; i < w.size(); ++i) w[i] = u(rng);
  Eigen::MatrixX3d G = Eigen::MatrixX3d::Zero(s.V.rows(), 3);
  geometry::add_vertex_area_gradient(s.V, s.F, w, G);
  Eigen::MatrixX3d D(s.V.rows(), 3);
  for (Eigen::Index i = 0; i < D.size(); ++i) D.data()[i] = u(rng);
  const double h = 1e-6;
  const double fd =
      (w.dot(geometry::vertex_areas(s.V + h * D, s.F)) - w.dot(geometry::vertex_areas(s.V - h * D, s.F))) / (2 * h);
  EXPECT_NEAR(fd, (G.array() * D.array()).sum(), 1e-7 * std::abs(fd));
}

// φ along a random direction of θ by central differences of re-solved
// equilibria, against the adjoint gradient; on a bumpy slab so that every
// term (body side, support side, areas, smoothness) takes part.
void check_adjoint(bool rotate, bool normal_only, int exponent, bool smoothness, bool deformable = false,
                   double pressure_smoothing = 0.5) {
  const SurfaceMesh s = deformable ? foam_slab() : slab();
  DesignOptions o;
  o.score.exponent = exponent;
  o.score.pressure_smoothing = pressure_smoothing;
  o.normal_only = normal_only;
  o.threads = 1;
  if (!smoothness) o.gamma = 0.0;
  ShapeOptimizer opt(block(), s, deformable ? on_foam(options(rotate)) : options(rotate), top_inside(s), o);
  ASSERT_EQ(opt.simulation().deformable_support(), deformable);
  const DesignSpace& space = opt.space();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd bump(space.size()), dir(space.size());
  for (Eigen::Index i = 0; i < bump.size(); ++i) bump[i] = 1e-4 * u(rng);
  for (Eigen::Index i = 0; i < dir.size(); ++i) dir[i] = u(rng);
  if (normal_only) bump = bump.cwiseAbs() * -1.0;  // dents only: the body stays above the slab's rim
  dir /= space.max_move(dir);
  const Evaluation at = opt.evaluate(space.shape(bump), opt.initial().states(), true);
  ASSERT_TRUE(at.ok) << at.failure;
  ASSERT_GT(at.body().score.body_contacts, 10);
  ASSERT_GT(at.body().score.support_contacts, 5);
  const double analytic = space.restrict(at.gradient).dot(dir);
  const double h = 2e-7;  // largest vertex move [m]
  const Evaluation plus = opt.evaluate(space.shape(bump + h * dir), at.states(), false);
  const Evaluation minus = opt.evaluate(space.shape(bump - h * dir), at.states(), false);
  ASSERT_TRUE(plus.ok && minus.ok);
  const double fd = (plus.phi - minus.phi) / (2 * h);
  constexpr double tolerance = 2e-3;  // of |fd|
  EXPECT_NEAR(analytic, fd, tolerance * std::abs(fd)) << "φ = " << at.phi << ", ζ = " << at.zeta;
  if (smoothness) {
    // The smoothness term is not what carries the agreement.
    EXPECT_GT(at.zeta, opt.gamma() * at.psi * 0.1);
  } else {
    // Without the adjoint term (the equilibrium held fixed) the derivative
    // is off by ten times the tolerance or more (4% to 33× on the nodal-pressure
    // block): the test sees the adjoint. (A deformable support's surface
    // is where the equilibrium puts it, so only its held base is explicit.)
    const double explicit_only =
        space.restrict(deformable ? at.body().score.d_support_area : at.body().score.d_support + at.body().score.d_support_area).dot(dir);
    EXPECT_GT(std::abs(explicit_only - fd), 10.0 * tolerance * std::abs(fd));
    std::printf("[design] adjoint share of the derivative: %.1f%%\n", 100.0 * std::abs(explicit_only - fd) / std::abs(fd));
  }
}

TEST(DesignAdjoint, GradientMatchesFiniteDifferences) { check_adjoint(false, false, 3, true); }
TEST(DesignAdjoint, ScoreGradientMatchesFiniteDifferences) { check_adjoint(false, false, 3, false); }
TEST(DesignAdjoint, GradientMatchesFiniteDifferencesWithARotatingCore) { check_adjoint(true, false, 3, false); }
TEST(DesignAdjoint, NormalOnlyGradientMatchesFiniteDifferences) { check_adjoint(false, true, 4, false); }
TEST(DesignAdjoint, SquaredPressureGradientMatchesFiniteDifferences) { check_adjoint(true, true, 2, true); }
// The score of the pressures as they are (no smoothing step), as the shipped
// seat, sole and thigh score them.
TEST(DesignAdjoint, UnsmoothedPressureGradientMatchesFiniteDifferences) {
  check_adjoint(false, true, 3, false, false, 0.0);
}
// A deformable support (7.21–7.23): its DOFs in the equilibrium, its rest
// shape the design.
TEST(DesignAdjoint, DeformableSupportGradientMatchesFiniteDifferences) { check_adjoint(true, false, 3, true, true); }
TEST(DesignAdjoint, DeformableSupportScoreGradientMatchesFiniteDifferences) {
  check_adjoint(false, true, 3, false, true);
}

}  // namespace
}  // namespace palpa::design

namespace palpa::design {
namespace {

using namespace fixture;

TEST(DesignBaselines, PoseToSeatBalancesTheForceAndActsOnTheLoadLine) {
  // The cushion resting on the flat slab; the estimate without elasticity
  // carries palpa's contact force through the same point.
  rest::RestSimulation sim(cushion(6e-3), slab(15), options());
  const rest::RestResult r = sim.solve();
  const PressureEstimate e = pose_to_seat(sim, r, 2e-3);
  ASSERT_GT(e.contacts, 10);
  double force = 0.0;
  Eigen::Vector2d moment = Eigen::Vector2d::Zero();
  for (int v : sim.surface_vertices()) {
    const double f = e.body_pressure[v] * sim.skin_area()[v];
    force += f;
    moment += f * sim.model().mesh().V.row(v).head<2>().transpose();
  }
  EXPECT_NEAR(force, r.contact_force.z(), 1e-9 * force);
  // Centred body and load: the pressure centre is on the axis (to the mesh's
  // asymmetry).
  EXPECT_LT((moment / force).norm(), 1e-3);
  // It reaches the support's vertices under the contact.
  EXPECT_GT(e.support_pressure.maxCoeff(), 0.0);
  EXPECT_THROW(pose_to_seat(sim, r, 0.0), Error);
}

TEST(DesignOptimizer, LbfgsLowersTheScoreToo) {
  const SurfaceMesh s = slab(15);
  const DesignResult r = cushion_design(s, DesignMethod::Lbfgs, 8, 2);
  ASSERT_GE(r.iterations, 4) << r.stop.detail;
  EXPECT_LT(r.final.zeta, 0.6 * r.initial.zeta);
  EXPECT_LT(r.final.body().rest.balance_error, 0.005);
  // Post-smoothing moved only design vertices, and was re-scored.
  ASSERT_TRUE(r.before_post_smoothing.has_value());
  const Eigen::MatrixX3d smoothed = r.final.support - r.before_post_smoothing->support;
  EXPECT_GT(smoothed.cwiseAbs().maxCoeff(), 1e-7);
  std::vector<char> design(static_cast<std::size_t>(s.V.rows()), 0);
  for (int v : top_inside(s)) design[static_cast<std::size_t>(v)] = 1;
  for (Eigen::Index v = 0; v < s.V.rows(); ++v) {
    if (!design[static_cast<std::size_t>(v)]) {
      EXPECT_EQ(smoothed.row(v).norm(), 0.0) << v;
    }
  }
  EXPECT_NE(r.final.zeta, r.before_post_smoothing->zeta);
}

}  // namespace
}  // namespace palpa::design
