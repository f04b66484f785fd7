// SPDX-License-Identifier: AGPL-3.0-or-later
// One support for several bodies: the cohort's objectives (mean, quantile,
// smooth max) and their weights, the cohort's adjoint gradient against
// central differences of re-solved equilibria, each body solved beside the
// others as it is alone, and the checkpoint of a cohort.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "palpa/design/average_impression.hpp"
#include "palpa/design/checkpoint.hpp"
#include "palpa/design/cohort.hpp"
#include "palpa/design/optimizer.hpp"
#include "palpa/material/models.hpp"
#include "common/test_support.hpp"
#include "design_fixtures.hpp"

namespace palpa::design {
namespace {

using namespace fixture;

double value(CohortAggregate a, const Eigen::VectorXd& r, Eigen::VectorXd* w = nullptr, double q = 0.9,
             double tau = 0.05) {
  return cohort_value(CohortObjective{a, q, tau}, r, w);
}

TEST(CohortObjective, MeanQuantileAndSmoothMaxWithTheirWeights) {
  const Eigen::Vector3d r(0.8, 1.3, 1.0);
  Eigen::VectorXd w;
  EXPECT_DOUBLE_EQ(value(CohortAggregate::Mean, r, &w), 3.1 / 3.0);
  EXPECT_EQ(w, Eigen::VectorXd::Constant(3, 1.0 / 3.0));
  // The worst half of three bodies: the worst whole, the next by half.
  EXPECT_DOUBLE_EQ(value(CohortAggregate::Quantile, r, &w, 0.5), (1.3 + 0.5 * 1.0) / 1.5);
  EXPECT_DOUBLE_EQ(w[0], 0.0);
  EXPECT_DOUBLE_EQ(w[1], 1.0 / 1.5);
  EXPECT_DOUBLE_EQ(w[2], 0.5 / 1.5);
  // Fewer than one body's worth above the quantile: the worst body.
  EXPECT_DOUBLE_EQ(value(CohortAggregate::Quantile, r, &w, 0.9), 1.3);
  EXPECT_EQ(w, Eigen::Vector3d(0.0, 1.0, 0.0));
  // The smooth max lies within τ log n below the largest.
  const double tau = 0.05;
  const double m = value(CohortAggregate::SmoothMax, r, &w, 0.9, tau);
  EXPECT_LT(m, 1.3);
  EXPECT_GT(m, 1.3 - tau * std::log(3.0));
  EXPECT_NEAR(w.sum(), 1.0, 1e-15);
  EXPECT_GT(w[1], 0.99);
  // Every one starts at 1 on the initial support.
  for (CohortAggregate a : {CohortAggregate::Mean, CohortAggregate::Quantile, CohortAggregate::SmoothMax}) {
    EXPECT_NEAR(value(a, Eigen::VectorXd::Ones(5)), 1.0, 1e-15) << to_string(a);
  }
}

TEST(CohortObjective, WeightsAreTheDerivatives) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  Eigen::VectorXd r(6);
  for (Eigen::Index i = 0; i < r.size(); ++i) r[i] = u(rng);
  for (CohortAggregate a : {CohortAggregate::Mean, CohortAggregate::Quantile, CohortAggregate::SmoothMax}) {
    for (double tau : {0.05, 0.3}) {
      Eigen::VectorXd w;
      value(a, r, &w, 0.6, tau);
      const double h = 1e-6;
      for (Eigen::Index i = 0; i < r.size(); ++i) {
        Eigen::VectorXd p = r, m = r;
        p[i] += h;
        m[i] -= h;
        const double fd = (value(a, p, nullptr, 0.6, tau) - value(a, m, nullptr, 0.6, tau)) / (2 * h);
        EXPECT_NEAR(w[i], fd, 1e-8) << to_string(a) << " τ " << tau << " body " << i;
      }
    }
  }
}

TEST(CohortObjective, RefusesWhatHasNoMeaning) {
  const Eigen::Vector2d r(1.0, 2.0);
  EXPECT_TRUE(test::throws_error([&] { value(CohortAggregate::Quantile, r, nullptr, 1.0); }, ErrorKind::Input,
                                 {"quantile", "[0, 1)"}));
  EXPECT_TRUE(test::throws_error([&] { value(CohortAggregate::SmoothMax, r, nullptr, 0.9, 0.0); }, ErrorKind::Input,
                                 {"sharpness", "> 0"}));
  EXPECT_TRUE(test::throws_error([&] { value(CohortAggregate::Mean, Eigen::VectorXd()); }, ErrorKind::Input,
                                 {"at least one body"}));
  EXPECT_TRUE(test::throws_error([&] { parse_cohort_aggregate("median", "scene.json: 'cohort.objective'"); },
                                 ErrorKind::Input, {"'cohort.objective'", "median", "\"quantile\""}));
  EXPECT_EQ(parse_cohort_aggregate("max", "x"), CohortAggregate::SmoothMax);
}

// Two bodies unlike each other: the block, and a stiffer, heavier one off
// centre, each with its own rest settings.
std::vector<DesignBody> two_bodies() {
  rest::RestBody other = block();
  other.mesh.V.col(0).array() += 12e-3;
  other.mesh.V.col(1).array() -= 3e-3;
  other.materials = {{std::make_shared<material::NeoHookean>(35e3, 0.3), kRho}};
  rest::RestOptions heavy = options();
  heavy.core.mass = 0.8;
  return {DesignBody{"block", on_linear_tets(block()), options()}, DesignBody{"stiff", on_linear_tets(other), heavy}};
}

// A cohort's design on one thread.
DesignOptions cohort_options(CohortAggregate aggregate = CohortAggregate::Mean) {
  DesignOptions o;
  o.threads = 1;
  o.cohort = CohortObjective{aggregate, 0.9, 0.05};
  return o;
}

// φ of the cohort along a random direction by central differences, against
// the sum of the bodies' adjoints; on a bumpy slab.
void check_cohort_adjoint(CohortAggregate aggregate) {
  const SurfaceMesh s = slab();
  DesignOptions o = cohort_options(aggregate);
  o.normal_only = true;
  ShapeOptimizer opt(two_bodies(), s, top_inside(s), o);
  ASSERT_EQ(opt.num_bodies(), 2u);
  EXPECT_DOUBLE_EQ(opt.initial().zeta, 1.0);  // every body at its own initial value
  const DesignSpace& space = opt.space();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd bump(space.size()), dir(space.size());
  // A rise under the off-centre body alone, with noise on it.
  for (Eigen::Index i = 0; i < bump.size(); ++i) {
    const Eigen::RowVector3d x = space.initial().row(space.vertices()[static_cast<std::size_t>(i)]);
    const double r2 = (x.head<2>() - Eigen::RowVector2d(0.026, -0.005)).squaredNorm();
    bump[i] = 1.5e-3 * std::exp(-r2 / (0.008 * 0.008)) + 2e-5 * u(rng);
  }
  for (Eigen::Index i = 0; i < dir.size(); ++i) dir[i] = u(rng);
  dir /= space.max_move(dir);
  const Evaluation at = opt.evaluate(space.shape(bump), opt.initial().states(), true);
  ASSERT_TRUE(at.ok) << at.failure;
  ASSERT_EQ(at.bodies.size(), 2u);
  for (const BodyEvaluation& b : at.bodies) ASSERT_GT(b.score.body_contacts, 10);
  // The rise moves the bodies' scores apart: the smooth max weighs them
  // unequally.
  EXPECT_GT(std::abs(at.bodies[0].zeta / opt.initial_zeta()[0] - at.bodies[1].zeta / opt.initial_zeta()[1]), 0.01)
      << at.bodies[0].zeta / opt.initial_zeta()[0] << " " << at.bodies[1].zeta / opt.initial_zeta()[1];
  const double analytic = space.restrict(at.gradient).dot(dir);
  const double h = 2e-7;  // largest vertex move [m]
  const Evaluation plus = opt.evaluate(space.shape(bump + h * dir), at.states(), false);
  const Evaluation minus = opt.evaluate(space.shape(bump - h * dir), at.states(), false);
  ASSERT_TRUE(plus.ok && minus.ok);
  const double fd = (plus.phi - minus.phi) / (2 * h);
  EXPECT_NEAR(analytic, fd, 2e-3 * std::abs(fd)) << to_string(aggregate) << ": φ = " << at.phi;
  // Each body's part of it is a gradient of its own: the cohort's is not
  // carried by one body alone.
  for (const BodyEvaluation& b : at.bodies) EXPECT_GT(std::abs(space.restrict(b.gradient).dot(dir)), 0.0);
}

TEST(CohortAdjoint, MeanGradientMatchesFiniteDifferences) { check_cohort_adjoint(CohortAggregate::Mean); }
TEST(CohortAdjoint, SmoothMaxGradientMatchesFiniteDifferences) { check_cohort_adjoint(CohortAggregate::SmoothMax); }

// Each body solved beside the others (at once, on other threads) gives what
// it gives alone, to the last bit: the cohort's result does not depend on
// how its bodies are shared out.
TEST(CohortAdjoint, EachBodyBesideTheOthersIsAsAlone) {
  const SurfaceMesh s = slab();
  const DesignOptions o = cohort_options();
  std::vector<DesignBody> bodies = two_bodies();
  ShapeOptimizer both(bodies, s, top_inside(s), o);
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    ShapeOptimizer alone(std::vector<DesignBody>{bodies[i]}, s, top_inside(s), o);
    EXPECT_EQ(alone.initial().body().zeta, both.initial().body(i).zeta) << bodies[i].name;
    EXPECT_EQ(alone.initial().body().gradient, both.initial().body(i).gradient) << bodies[i].name;
    EXPECT_EQ(alone.initial().body().state.x, both.initial().body(i).state.x) << bodies[i].name;
  }
}

// A body whose equilibrium cannot be solved is named, and nothing runs.
TEST(CohortAdjoint, ABodyThatFailsIsNamed) {
  const SurfaceMesh s = slab();
  DesignOptions o = cohort_options();
  std::vector<DesignBody> bodies = two_bodies();
  bodies[1].rest.max_iterations = 1;
  EXPECT_TRUE(test::throws_error([&] { ShapeOptimizer(bodies, s, top_inside(s), o); }, ErrorKind::Solver,
                                 {"the body 'stiff'"}));
  // Several bodies need a cohort objective.
  o.cohort.reset();
  EXPECT_TRUE(test::throws_error([&] { ShapeOptimizer(two_bodies(), s, top_inside(s), o); }, ErrorKind::Input,
                                 {"2 bodies", "cohort objective"}));
}

// A surface's lower envelope, seen from below: the lowest crossing of the
// line through each point, +∞ where it misses.
TEST(AverageImpression, TheLowerEnvelopeIsTheLowestCrossing) {
  const SurfaceMesh cube = slab(4);  // 70 × 70 × 10 mm, top at 0
  const std::vector<Eigen::Vector3d> points{{0.0, 0.0, -1.0}, {0.01, -0.02, 5.0}, {0.2, 0.0, 0.0}};
  const std::vector<double> h = lower_envelope(cube.V, cube.F, points, Eigen::Vector3d(0.0, 0.0, -9.81));
  EXPECT_NEAR(h[0], -0.01, 1e-15);
  EXPECT_NEAR(h[1], -0.01, 1e-15);
  EXPECT_TRUE(std::isinf(h[2]) && h[2] > 0.0);
}

// Two flat-bottomed blocks pressed 2 mm into the slab: the average body's
// hollow is 2 mm deep where both press, 1 mm where one does, 0 elsewhere.
TEST(AverageImpression, IsTheMeanOfTheBodiesDents) {
  const SurfaceMesh s = slab();
  rest::RestBody a = block(), b = block();
  b.mesh.V.col(0).array() += 12e-3;
  const std::vector<int> region = top_inside(s);
  AverageImpressionOptions o;
  o.press = 2e-3;
  o.smoothing_rounds = 0;
  const SurfaceMesh hollow = average_impression({&a, &b}, s, region, Eigen::Vector3d(0.0, 0.0, -1.0), o);
  const auto depth_at = [&](double x, double y) {
    for (int v : region) {
      if (std::abs(s.V(v, 0) - x) < 1e-9 && std::abs(s.V(v, 1) - y) < 1e-9) return s.V(v, 2) - hollow.V(v, 2);
    }
    ADD_FAILURE() << "no design vertex at " << x << ", " << y;
    return 0.0;
  };
  EXPECT_NEAR(depth_at(0.0, 0.0), 2e-3, 1e-12);     // under both
  EXPECT_NEAR(depth_at(-0.015, 0.0), 1e-3, 1e-12);  // under the first only
  EXPECT_NEAR(depth_at(0.025, 0.0), 1e-3, 1e-12);   // under the second only
  EXPECT_NEAR(depth_at(-0.025, 0.0), 0.0, 1e-15);   // under neither
  // Off the design region nothing moves.
  double moved_off = 0.0;
  std::vector<bool> in(static_cast<std::size_t>(s.V.rows()), false);
  for (int v : region) in[static_cast<std::size_t>(v)] = true;
  for (Eigen::Index v = 0; v < s.V.rows(); ++v) {
    if (!in[static_cast<std::size_t>(v)]) moved_off = std::max(moved_off, (hollow.V.row(v) - s.V.row(v)).norm());
  }
  EXPECT_EQ(moved_off, 0.0);
  o.press = 0.0;
  EXPECT_TRUE(test::throws_error([&] { average_impression({&a}, s, region, Eigen::Vector3d(0, 0, -1), o); },
                                 ErrorKind::Input, {"press"}));
  o.press = 2e-3;
  rest::RestBody away = block();
  away.mesh.V.col(0).array() += 0.2;
  EXPECT_TRUE(test::throws_error([&] { average_impression({&away}, s, region, Eigen::Vector3d(0, 0, -1), o); },
                                 ErrorKind::Input, {"reaches none"}));
}

TEST(CohortCheckpoint, KeepsEachBodyAndRefusesAnotherCohort) {
  test::ScratchDir dir;
  DesignCheckpoint c;
  c.theta = Eigen::VectorXd::Zero(2);
  c.direction = c.gradient = c.theta;
  for (const char* name : {"tiny-a", "tiny-b"}) {
    BodyCheckpoint b;
    b.name = name;
    b.state.x = Eigen::VectorXd::LinSpaced(4, 0.0, 1e-3);
    b.state.spring_areas = {1e-4};
    b.state.stiffness = name[5] == 'a' ? 2e4 : 3e4;
    b.max_penetration = name[5] == 'a' ? 1e-4 : 2e-4;
    b.refreeze_failed = name[5] == 'b';
    c.bodies.push_back(b);
  }
  const auto file = dir / "checkpoint.json";
  write_json_file(file, checkpoint_json(c));
  const DesignCheckpoint r = read_design_checkpoint(file, c);
  ASSERT_EQ(r.bodies.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(r.bodies[i].name, c.bodies[i].name);
    EXPECT_EQ(r.bodies[i].state.x, c.bodies[i].state.x);
    EXPECT_EQ(r.bodies[i].state.stiffness, c.bodies[i].state.stiffness);
    EXPECT_EQ(r.bodies[i].max_penetration, c.bodies[i].max_penetration);
    EXPECT_EQ(r.bodies[i].refreeze_failed, c.bodies[i].refreeze_failed);
  }
  DesignCheckpoint other = c;
  other.bodies[1].name = "tiny-c";
  EXPECT_TRUE(test::throws_error([&] { read_design_checkpoint(file, other); }, ErrorKind::Input,
                                 {"'bodies[1].name'", "tiny-b", "another cohort"}));
  other.bodies.pop_back();
  EXPECT_TRUE(test::throws_error([&] { read_design_checkpoint(file, other); }, ErrorKind::Input,
                                 {"'bodies'", "2 bodies", "another cohort"}));
}

}  // namespace
}  // namespace palpa::design
