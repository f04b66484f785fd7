// SPDX-License-Identifier: AGPL-3.0-or-later
// The indentation simulator: punch geometry, derivatives of the system and of
// the force, the curve's start, bad input. Physics: poke_physics_test.cpp.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <random>
#include <vector>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/axisym/poke.hpp"
#include "axisym/poke_fixtures.hpp"
#include "palpa/core/interrupt.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::axisym {
namespace {

using palpa::test::derivatives_match;
using namespace palpa::axisym::test;



// ---------------------------------------------------------------- punch shape

TEST(PunchDistance, SignedDistanceAndItsDerivatives) {
  const PunchShape sharp{kA, 0.0, 1e-3};
  EXPECT_NEAR(punch_distance(sharp, {0.5 * kA, -1.5e-3}).phi, 0.5e-3, 1e-15);    // below the face
  EXPECT_NEAR(punch_distance(sharp, {1.25 * kA, 0.0}).phi, 0.25 * kA, 1e-15);    // beside the wall
  EXPECT_NEAR(punch_distance(sharp, {kA + 3e-4, -1.4e-3}).phi, 5e-4, 1e-15);     // off the corner
  EXPECT_NEAR(punch_distance(sharp, {0.9 * kA, 0.0}).phi, -0.1 * kA, 1e-15);     // inside, wall nearer
  EXPECT_NEAR(punch_distance(sharp, {0.2 * kA, -0.9e-3}).phi, -0.1e-3, 1e-15);   // inside, face nearer
  const PunchShape round{kA, 0.2 * kA, 1e-3};
  // On the arc: centre (a − ρ, −d + ρ).
  const Eigen::Vector2d c(0.8 * kA, -1e-3 + 0.2 * kA);
  const Eigen::Vector2d on_arc = c + 0.2 * kA * Eigen::Vector2d(1.0, -1.0).normalized();
  EXPECT_NEAR(punch_distance(round, on_arc).phi, 0.0, 1e-15);
  // Gradient and Hessian against finite differences, outside and inside the arc.
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(c + Eigen::Vector2d(0.3 * kA, -0.1 * kA)),
                                   Eigen::Vector2d(c + Eigen::Vector2d(0.1 * kA, -0.05 * kA))}) {
    const auto phi = [&](const Eigen::VectorXd& x) { return punch_distance(round, Eigen::Vector2d(x)).phi; };
    const auto grad = [&](const Eigen::VectorXd& x) {
      return Eigen::VectorXd(punch_distance(round, Eigen::Vector2d(x)).normal);
    };
    const PunchDistance d = punch_distance(round, p);
    EXPECT_TRUE(derivatives_match(d.normal, palpa::test::fd_gradient(phi, p, 1e-7), 1e-8));
    EXPECT_TRUE(derivatives_match(d.hessian, palpa::test::fd_jacobian(grad, p, 1e-7), 1e-6));
  }
}

// ---------------------------------------------------------------- system derivatives

TEST(PokeModel, GradientAndHessianMatchFiniteDifferencesWithContactActive) {
  const material::NeoHookean m(kE, 0.45);
  for (PunchContact contact : {PunchContact::Stick, PunchContact::Frictionless}) {
    PokeSetup s = setup_for(3 * kA, 0, contact);
    s.fillet_radius = 0.1 * kA;
    PokeSimulator sim(m, s);
    PokeOptions o;
    o.max_depth = 0.6 * kA;
    o.steps = 6;
    Eigen::VectorXd x_star;
    sim.run(o, [&](const PokeModel&, const Eigen::VectorXd& x, const PokeSample&) { x_star = x; });
    PokeModel& model = sim.model();
    ASSERT_GT(model.diagnostics(x_star).contact_nodes, 0) << "the test needs nodes on the punch";
    // Directional derivatives along seeded random directions.
    auto rng = palpa::test::make_rng(21);
    std::normal_distribution<double> n01;
    Eigen::VectorXd v(model.num_dofs());
    for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = n01(rng);
    v *= 1e-3 * kA / v.norm();
    // Off the equilibrium (where g would vanish), with the contact set unchanged.
    Eigen::VectorXd w(model.num_dofs());
    for (Eigen::Index i = 0; i < w.size(); ++i) w[i] = n01(rng);
    x_star += (0.02 * sim.model().mesh().rim_cell_size / w.cwiseAbs().maxCoeff()) * w;
    ASSERT_GT(model.diagnostics(x_star).contact_nodes, 0);
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
  }
}

// The adjoint product (∂g/∂θ)ᵀλ against the assembled ∂g/∂θ, and the PSD
// stand-in: positive semi-definite at every depth, and H itself in the limit
// of a vanishing strain.
TEST(PokeModel, AdjointProductAndProjectedHessian) {
  const material::NeoHookean nh(kE, 0.45);
  const material::SplineMaterial spline = material::SplineMaterial::from_model(nh);
  PokeSetup s = setup_for(3 * kA, 0, PunchContact::Stick);
  s.fillet_radius = 0.1 * kA;
  PokeSimulator sim(spline, s);
  PokeOptions o;
  o.max_depth = 0.6 * kA;
  o.steps = 6;
  auto rng = palpa::test::make_rng(5);
  std::normal_distribution<double> n01;
  int checked = 0;
  // At each depth's equilibrium (the model is at that depth only in the callback).
  sim.run(o, [&](const PokeModel& model, const Eigen::VectorXd& x, const PokeSample& sample) {
    const bool deep = sample.depth > 0.55 * kA;
    ++checked;
    if (deep) {
      ASSERT_GT(sample.contact_nodes, 0) << "the test needs the rim in contact";
      Eigen::VectorXd lambda(model.num_dofs());
      for (Eigen::Index i = 0; i < lambda.size(); ++i) lambda[i] = n01(rng);
      Eigen::SparseMatrix<double> J;
      model.gradient_param_jacobian(x, J);
      const Eigen::VectorXd dense = J.transpose() * lambda;
      const Eigen::VectorXd adjoint = model.gradient_param_adjoint(x, lambda);
      ASSERT_EQ(adjoint.size(), model.num_params());
      EXPECT_LE((adjoint - dense).lpNorm<Eigen::Infinity>(), 1e-12 * dense.lpNorm<Eigen::Infinity>());
    }
    Eigen::SparseMatrix<double> H, P;
    model.hessian(x, H);  // the true Hessian (run() switches it on)
    P = H;
    ASSERT_TRUE(model.projected_hessian(x, P));
    const Eigen::MatrixXd Pd = Eigen::MatrixXd(P).selfadjointView<Eigen::Lower>();
    const Eigen::MatrixXd Hd = Eigen::MatrixXd(H).selfadjointView<Eigen::Lower>();
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Pd).eigenvalues();
    EXPECT_GE(ev.minCoeff(), -1e-10 * ev.maxCoeff()) << "depth " << sample.depth;
    const double diff = (Pd - Hd).cwiseAbs().maxCoeff() / Hd.cwiseAbs().maxCoeff();
    // Only the geometric stiffness of the element Hessians (∝ stress, so ∝
    // depth) is clipped: P → H as the strain vanishes.
    EXPECT_LE(diff, 1e-3 * sample.depth / kA) << "depth " << sample.depth;
  });
  EXPECT_EQ(checked, 6);
}

TEST(PokeCurve, ZeroDepthHasZeroForceAndTheCurveStartsThere) {
  const material::NeoHookean m(kE, 0.45);
  PokeSimulator sim(m, setup_for(3 * kA, 0, PunchContact::Stick));
  PokeOptions o;
  o.max_depth = 0.05 * kA;
  o.steps = 3;
  const PokeCurve c = sim.run(o);
  ASSERT_EQ(c.samples.size(), 4u);
  EXPECT_EQ(c.samples[0].depth, 0.0);
  EXPECT_EQ(c.samples[0].force, 0.0);
  for (std::size_t i = 1; i < c.samples.size(); ++i) {
    EXPECT_NEAR(c.samples[i].depth, i * 0.05 * kA / 3, 1e-15);
    EXPECT_GT(c.samples[i].force, c.samples[i - 1].force);
  }
}

// ---------------------------------------------------------------- predictor

// The predictor's tangent dx/dd = −K⁻¹ ∂g/∂d against the central difference of
// converged equilibria one depth step either side (no contact change there).
TEST(PokePredictor, TheTangentIsTheDerivativeOfTheEquilibriumPath) {
  const material::NeoHookean m(kE, 0.45);
  PokeSimulator sim(m, setup_for(3 * kA, 0, PunchContact::Stick));
  PokeOptions o;
  o.max_depth = 0.3 * kA;
  o.steps = 60;
  std::vector<Eigen::VectorXd> xs;
  std::vector<std::vector<char>> contacts;
  sim.run(o, [&](const PokeModel& model, const Eigen::VectorXd& x, const PokeSample&) {
    xs.push_back(x);
    contacts.push_back(model.contact_set(x));
  });
  ASSERT_EQ(xs.size(), 60u);
  const std::size_t k = 49;  // depth 50 δ
  const double delta = o.max_depth / o.steps;
  ASSERT_EQ(contacts[k - 1], contacts[k]);
  ASSERT_EQ(contacts[k + 1], contacts[k]);
  PokeModel& model = sim.model();
  model.set_depth(static_cast<double>(k + 1) * delta);
  model.set_true_hessian(true);
  Eigen::SparseMatrix<double> h;
  model.hessian(xs[k], h);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt(h);
  ASSERT_EQ(ldlt.info(), Eigen::Success);
  Eigen::VectorXd dg_dd;
  ASSERT_TRUE(model.gradient_depth_derivative(xs[k], 1e-4 * delta, dg_dd));
  const Eigen::VectorXd tangent = -ldlt.solve(dg_dd);
  const Eigen::VectorXd path = (xs[k + 1] - xs[k - 1]) / (2.0 * delta);
  ASSERT_GT(path.norm(), 0.1);  // a displacement per unit depth of order 1
  EXPECT_LT((tangent - path).norm(), 1e-3 * path.norm());
  // The depth derivative of the gradient is what moving the punch does: the
  // gradient one step deeper at the same free DOFs, to first order.
  Eigen::VectorXd g0;
  Eigen::VectorXd g1;
  model.gradient(xs[k], g0);
  model.set_depth(static_cast<double>(k + 1) * delta + 1e-3 * delta);
  model.gradient(xs[k], g1);
  model.set_depth(static_cast<double>(k + 1) * delta);
  EXPECT_TRUE(derivatives_match(dg_dd, (g1 - g0) / (1e-3 * delta), 1e-3));
  // Where x at depth ± eps inverts a cell there is no derivative (here every
  // free node moved past the axis).
  const Eigen::VectorXd folded = Eigen::VectorXd::Constant(xs[k].size(), -2.0 * kA);
  EXPECT_FALSE(std::isfinite(model.energy(folded)));
  EXPECT_FALSE(model.gradient_depth_derivative(folded, 1e-4 * delta, dg_dd));
}

// Nodes a predicted step pushes into the punch start on its surface; nodes
// already in contact keep their penetration.
TEST(PokePredictor, NewContactsStartJustInsideThePunch) {
  const material::NeoHookean m(kE, 0.45);
  PokeSetup s = setup_for(3 * kA, 2, PunchContact::Frictionless);
  s.fillet_radius = 0.4 * kA;
  PokeModel model(m, s);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(model.num_dofs());
  const std::vector<char> at_rest = model.contact_set(x);
  for (char c : at_rest) ASSERT_EQ(c, 0);
  // The undeformed surface under the fillet is inside the lowered punch.
  model.set_depth(0.01 * kA);
  ASSERT_GT(model.diagnostics(x).contact_nodes, 1);
  ASSERT_TRUE(std::isfinite(model.energy(x)));
  // Marked as already in contact: left where they are.
  Eigen::VectorXd kept = x;
  EXPECT_EQ(model.separate_new_contacts(kept, model.contact_set(x)), 0);
  EXPECT_EQ(kept, x);
  // New contacts: moved back to 1/penalty_factor of their penetration, still
  // inside (so that the first Hessian holds their penalty).
  const auto before = model.diagnostics(x);
  EXPECT_EQ(model.separate_new_contacts(x, at_rest), before.contact_nodes);
  const auto after = model.diagnostics(x);
  EXPECT_EQ(after.contact_nodes, before.contact_nodes);
  EXPECT_NEAR(after.max_penetration, before.max_penetration / s.penalty_factor, 1e-9 * before.max_penetration);
  EXPECT_TRUE(std::isfinite(model.energy(x)));
}

// A fit runs the same simulator again and again with other parameters: each
// run starts from rest, whatever depth and contact the last one ended at, and
// takes the same path as a fresh simulator.
TEST(PokePredictor, ARunAfterAnotherIsTheSameAsAFreshOne) {
  const material::NeoHookean first(kE, 0.45);
  const material::NeoHookean second(1.01 * kE, 0.45);
  PokeSetup s = setup_for(3 * kA, 1, PunchContact::Frictionless);
  s.fillet_radius = 0.1 * kA;
  PokeOptions o;
  o.max_depth = 0.5 * kA;
  o.steps = 5;
  PokeSimulator again(first, s);
  const PokeCurve before = again.run(o);
  ASSERT_GT(before.samples.back().contact_nodes, 0) << "the test needs the rim in contact at the end";
  again.set_material_params(second.params());
  const PokeCurve repeated = again.run(o);
  // (Built from the first material: the contact penalty and the F-bar
  // stabilization are fixed by the material a model is built with.)
  PokeSimulator fresh(first, s);
  fresh.set_material_params(second.params());
  const PokeCurve cold = fresh.run(o);
  ASSERT_EQ(repeated.samples.size(), cold.samples.size());
  for (std::size_t k = 1; k < cold.samples.size(); ++k) {
    EXPECT_EQ(repeated.samples[k].newton_iterations, cold.samples[k].newton_iterations) << "step " << k;
    EXPECT_NEAR(repeated.samples[k].force, cold.samples[k].force, 1e-12 * cold.samples[k].force) << "step " << k;
  }
}

// Warm start: a run for a slightly different material, started at each depth
// from the last run's equilibrium, reaches the same curve as a cold run with
// fewer Newton iterations.
TEST(PokePredictor, AWarmStartReachesTheColdCurveWithFewerIterations) {
  const material::NeoHookean first(kE, 0.45);
  const material::NeoHookean second(1.002 * kE, 0.45);
  const PokeSetup s = setup_for(3 * kA, 0, PunchContact::Frictionless);
  PokeOptions o;
  o.max_depth = 0.4 * kA;
  o.steps = 5;
  PokeSimulator cold_sim(first, s);
  cold_sim.set_material_params(second.params());
  const PokeCurve cold = cold_sim.run(o);

  o.warm_start = true;
  PokeSimulator warm_sim(first, s);
  warm_sim.run(o);
  warm_sim.set_material_params(second.params());
  const PokeCurve warm = warm_sim.run(o);
  ASSERT_EQ(warm.samples.size(), cold.samples.size());
  for (std::size_t k = 1; k < cold.samples.size(); ++k) {
    EXPECT_NEAR(warm.samples[k].force, cold.samples[k].force, 1e-7 * cold.samples[k].force) << "step " << k;
  }
  EXPECT_LT(warm.newton_iterations, cold.newton_iterations);

  // Another schedule: the stored equilibria do not apply and it runs cold.
  o.steps = 4;
  PokeSimulator fresh(first, s);
  fresh.set_material_params(second.params());
  o.warm_start = false;
  const PokeCurve four_cold = fresh.run(o);
  o.warm_start = true;
  const PokeCurve four = warm_sim.run(o);
  EXPECT_EQ(four.newton_iterations, four_cold.newton_iterations);
}

// Extrapolation (PokeSetup::extrapolate): 2 F_L − F_{L−1} from the two
// meshes, each warm-started from its own last run.
TEST(PokeExtrapolation, CombinesTwoLevelsAndWarmStartsBoth) {
  const material::NeoHookean first(kE, 0.45);
  const material::NeoHookean second(1.002 * kE, 0.45);
  PokeSetup s = setup_for(3 * kA, 1, PunchContact::Frictionless);
  PokeOptions o;
  o.max_depth = 0.3 * kA;
  o.steps = 3;
  PokeSimulator sim(first, s);
  ASSERT_TRUE(sim.extrapolates());
  const PokeCurve both = sim.run(o);
  s.extrapolate = false;
  PokeSimulator fine(first, s);
  EXPECT_FALSE(fine.extrapolates());
  const PokeCurve f = fine.run(o);
  s.mesh_level = 0;
  PokeSimulator coarse(first, s);
  const PokeCurve c = coarse.run(o);
  ASSERT_EQ(both.samples.size(), 4u);
  for (std::size_t k = 1; k < both.samples.size(); ++k) {
    const double ff = f.samples[k].force;
    EXPECT_NEAR(both.samples[k].force, 2 * ff - c.samples[k].force, 1e-12 * ff) << "step " << k;
    EXPECT_NEAR(both.samples[k].mesh_correction, ff - c.samples[k].force, 1e-12 * ff) << "step " << k;
    EXPECT_EQ(both.samples[k].newton_iterations, f.samples[k].newton_iterations + c.samples[k].newton_iterations);
    EXPECT_EQ(both.samples[k].min_jacobian, f.samples[k].min_jacobian);
  }
  EXPECT_EQ(both.newton_iterations, f.newton_iterations + c.newton_iterations);
  EXPECT_EQ(f.samples.back().mesh_correction, 0.0);

  // Warm starts: one set of equilibria per mesh, and a warm run reaches the
  // cold curve of a nearby material in fewer iterations.
  o.warm_start = true;
  PokeSimulator warm(first, setup_for(3 * kA, 1, PunchContact::Frictionless));
  warm.run(o);
  ASSERT_EQ(warm.warm_start().solutions.size(), 4u);
  ASSERT_EQ(warm.warm_start().coarse_solutions.size(), 4u);
  EXPECT_EQ(warm.warm_start().coarse_solutions[3].size(), coarse.model().num_dofs());
  warm.set_material_params(second.params());
  const PokeCurve warm_curve = warm.run(o);
  PokeSimulator cold(first, setup_for(3 * kA, 1, PunchContact::Frictionless));
  cold.set_material_params(second.params());
  o.warm_start = false;
  const PokeCurve cold_curve = cold.run(o);
  for (std::size_t k = 1; k < cold_curve.samples.size(); ++k) {
    EXPECT_NEAR(warm_curve.samples[k].force, cold_curve.samples[k].force, 1e-7 * cold_curve.samples[k].force);
  }
  EXPECT_LT(warm_curve.newton_iterations, cold_curve.newton_iterations);
}

TEST(PokeExtrapolation, OnlyWhereTheForceConvergesAtFirstOrder) {
  const material::NeoHookean m(kE, 0.45);
  PokeSetup s = setup_for(3 * kA, 1, PunchContact::Stick);
  EXPECT_TRUE(extrapolates(s));
  s.mesh_level = 0;  // no coarser mesh
  EXPECT_FALSE(extrapolates(s));
  s.mesh_level = 1;
  s.fillet_radius = 0.1 * kA;  // a rounded rim
  EXPECT_FALSE(extrapolates(s));
  EXPECT_FALSE(PokeSimulator(m, s).extrapolates());
  EXPECT_FALSE(extrapolates(compression_setup(5e-3, 5e-3, 1, PunchContact::Stick)));
}

// ---------------------------------------------------------------- sensitivities

TEST(PokeSensitivities, MatchFiniteDifferencesOfWholeCurves) {
  const material::NeoHookean nh(kE, 0.45);
  const material::SplineMaterial spline = material::SplineMaterial::from_model(nh);
  for (const material::Material* m : {static_cast<const material::Material*>(&nh),
                                      static_cast<const material::Material*>(&spline)}) {
    PokeSetup s = setup_for(3 * kA, 0, PunchContact::Stick);
    PokeOptions o;
    o.max_depth = 0.5 * kA;  // deep enough for surface nodes to touch the rim
    o.steps = 5;
    o.sensitivities = true;
    PokeSimulator sim(*m, s);
    const PokeCurve c = sim.run(o);
    test::expect_curve_sensitivities(sim, c, o, kE, std::string(to_string(s.contact)));
  }
}

// ---------------------------------------------------------------- bad input

TEST(PokeInput, RefusesImpossibleSetups) {
  const material::NeoHookean m(kE, 0.45);
  using palpa::test::throws_error;
  EXPECT_TRUE(throws_error([&] { PokeSimulator(m, setup_for(-1.0, 1, PunchContact::Stick)); },
                           ErrorKind::Input, {"thickness", "not a positive length"}));
  PokeSetup s = setup_for(3 * kA, 1, PunchContact::Stick);
  s.fillet_radius = kA;
  EXPECT_TRUE(throws_error([&] { PokeSimulator sim(m, s); }, ErrorKind::Input, {"fillet"}));
  s.fillet_radius = 0.0;
  s.geometry.outer_radius = kA;
  EXPECT_TRUE(throws_error([&] { PokeSimulator sim(m, s); }, ErrorKind::Input, {"outer radius"}));
  PokeSimulator sim(m, setup_for(3 * kA, 0, PunchContact::Stick));
  PokeOptions o;
  o.max_depth = 3 * kA;
  EXPECT_TRUE(throws_error([&] { sim.run(o); }, ErrorKind::Input, {"below 90% of the layer thickness"}));
  o.max_depth = -1e-3;
  EXPECT_TRUE(throws_error([&] { sim.run(o); }, ErrorKind::Input, {"not positive"}));
  EXPECT_TRUE(throws_error([] { parse_punch_contact("glue"); }, ErrorKind::Input, {"unknown contact 'glue'"}));
}

TEST(PokeInput, AFailedDepthHalvesTheStepOrGivesUpOnCrushedCells) {
  const material::NeoHookean m(kE, 0.45);
  PokeSimulator sim(m, setup_for(3 * kA, 0, PunchContact::Stick));
  PokeOptions o;
  o.max_depth = 0.2 * kA;
  o.steps = 2;
  o.newton.max_iterations = 1;  // no depth can converge
  o.max_step_cuts = 3;
  using palpa::test::throws_error;
  EXPECT_TRUE(throws_error([&] { sim.run(o); }, ErrorKind::Solver, {"after 3 halvings of the step"}));
  // The undeformed mesh's det F is 1: a limit above it gives up at the first
  // failure and says why.
  o.give_up_below_jacobian = 1.5;
  EXPECT_TRUE(throws_error([&] { sim.run(o); }, ErrorKind::Solver,
                           {"halving the step would not help", "keeps 100% of its volume"}));
  // Below it, the step is halved as before.
  o.give_up_below_jacobian = 0.5;
  EXPECT_TRUE(throws_error([&] { sim.run(o); }, ErrorKind::Solver, {"after 3 halvings of the step"}));
  // A material that gives way in compression is named as the likely cause,
  // with the advice that holds for it (a finer mesh does not help).
  const auto yeoh = material::IsochoricInvariant::yeoh(8e3, 2e3, 500.0, 7.5e-5);
  PokeSimulator foam(yeoh, setup_for(3 * kA, 0, PunchContact::Stick));
  EXPECT_TRUE(throws_error([&] { foam.run(o); }, ErrorKind::Solver,
                           {"stops resisting compression below a uniaxial stretch of 0.5",
                            "a finer --mesh-level stops sooner"}));
  EXPECT_FALSE(throws_error([&] { sim.run(o); }, ErrorKind::Solver, {"stops resisting compression"}));
}

TEST(PokeInput, InterruptStopsTheRun) {
  const material::NeoHookean m(kE, 0.45);
  PokeSimulator sim(m, setup_for(3 * kA, 0, PunchContact::Stick));
  PokeOptions o;
  o.max_depth = 0.2 * kA;
  o.steps = 4;
  int depths = 0;
  EXPECT_TRUE(palpa::test::throws_error(
      [&] {
        sim.run(o, [&](const PokeModel&, const Eigen::VectorXd&, const PokeSample&) {
          if (++depths == 2) request_interrupt();
        });
      },
      ErrorKind::Interrupted, {}));
  clear_interrupt();
  EXPECT_EQ(depths, 2);
  EXPECT_NO_THROW(sim.run(o));  // usable afterwards
}

}  // namespace
}  // namespace palpa::axisym
