// SPDX-License-Identifier: AGPL-3.0-or-later
// The Jacobian of the training residuals (exact sensitivities through the
// simulators and the cubic interpolation, in scaled free parameters) against
// central finite differences of the residuals.
//
// Step and tolerance: the simulations converge to ‖g‖∞ ≤ 1e-9 of the force
// scale, so a residual carries ~1e-9 relative noise; the Richardson-
// extrapolated central difference with step h (in scaled parameters, ~1)
// amplifies it to ~3e-9/h and has truncation error O(h⁴). With h = 1e-2 both
// stay below ~1e-6 of a Jacobian column; each column must match to 2e-5
// relative to its own largest entry (measured 1e-12 to 3e-7). The spline uses
// h = 3e-3: there the difference error falls only linearly with h (2.9e-5 at
// h = 1e-2, 7.7e-6 at 3e-3: rim nodes entering the penalty contact make the
// force C¹, not C², in θ). Homogeneous curves: closed form, h = 1e-3, 1e-7.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "common/finite_difference.hpp"
#include "fit/fit_fixtures.hpp"
#include "palpa/fit/fit.hpp"
#include "palpa/fit/optimize.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::fit {
namespace {

using palpa::test::derivatives_match;
using palpa::test::ZeroPolicy;

constexpr double kStep = 1e-2;
constexpr double kTolerance = 2e-5;

SimulationOptions coarse() {
  SimulationOptions so;
  so.mesh_level = 0;
  so.steps = 8;
  return so;
}

// Measured values only shift the residuals, not the Jacobian: any curve will do.
test::Curve ramp(double max_x, int points, double slope) {
  test::Curve c;
  for (int k = 1; k <= points; ++k) {
    c.x.push_back(max_x * k / points);
    c.y.push_back(slope * c.x.back());
  }
  return c;
}

Dataset indentation(axisym::PunchContact contact) {
  Dataset d;
  d.test = TestKind::Indentation;
  d.layer_depths = {6e-3};
  d.contact = contact;
  d.curves.push_back(test::measured("a2", CurveRole::Train, 2e-3, ramp(1.2e-3, 7, 100.0)));
  d.curves.push_back(test::measured("a3", CurveRole::Train, 3e-3, ramp(1.0e-3, 5, 150.0)));
  d.curves.push_back(test::measured("a1", CurveRole::Validate, 1e-3, ramp(1.0e-3, 5, 50.0)));
  return d;
}

// Checks the columns `cols` of the Jacobian at the problem's start.
void check_jacobian(TrainingProblem& p, std::vector<Eigen::Index> cols, double h, double tol, const std::string& what) {
  const Eigen::VectorXd x0 = p.start();
  Evaluation e;
  ASSERT_TRUE(p.evaluate(x0, e)) << what << ": " << e.reason;
  ASSERT_EQ(e.jacobian.rows(), p.num_residuals());
  ASSERT_EQ(e.jacobian.cols(), p.num_free());
  if (cols.empty()) {
    cols.resize(static_cast<std::size_t>(p.num_free()));
    std::iota(cols.begin(), cols.end(), Eigen::Index{0});
  }
  for (const Eigen::Index q : cols) {
    const palpa::test::VectorFunction residual_along = [&](const Eigen::VectorXd& t) {
      Eigen::VectorXd x = x0;
      x[q] = t[0];
      Evaluation ev;
      EXPECT_TRUE(p.evaluate(x, ev)) << ev.reason;
      return Eigen::VectorXd(ev.residuals);
    };
    const Eigen::MatrixXd fd = palpa::test::fd_jacobian(residual_along, Eigen::VectorXd::Constant(1, x0[q]), h);
    const auto match = derivatives_match(e.jacobian.col(q), fd, tol);
    EXPECT_TRUE(match) << what << ", parameter " << q;
    ::testing::Test::RecordProperty(what + "_param" + std::to_string(q), match.message());
  }
}

TEST(TrainingSensitivities, NeoHookeanIndentationStickAndFrictionless) {
  for (const auto contact : {axisym::PunchContact::Stick, axisym::PunchContact::Frictionless}) {
    const Dataset d = indentation(contact);
    const material::NeoHookean start(20e3, 0.45);
    TrainingProblem p(d, d.layer_depths[0], coarse(), start, {}, material::small_strain_constants(start).mu);
    EXPECT_EQ(p.num_free(), 2);
    EXPECT_EQ(p.num_residuals(), 12);  // the training curves only
    check_jacobian(p, {}, kStep, kTolerance, std::string("neo-hookean_") + std::string(axisym::to_string(contact)));
  }
}

TEST(TrainingSensitivities, OgdenIndentation) {
  const Dataset d = indentation(axisym::PunchContact::Stick);
  const material::Ogden start({5e3, 0.4e3}, {1.5, 6.0}, 0.45);
  TrainingProblem p(d, d.layer_depths[0], coarse(), start, {}, material::small_strain_constants(start).mu);
  EXPECT_EQ(p.num_free(), 5);
  check_jacobian(p, {}, kStep, kTolerance, "ogden");
}

TEST(TrainingSensitivities, FixedParametersAreLeftOut) {
  const Dataset d = indentation(axisym::PunchContact::Frictionless);
  const material::Ogden start({5e3, 0.4e3}, {1.5, 6.0}, 0.45);
  TrainingProblem p(d, d.layer_depths[0], coarse(), start, {"nu", "alpha[1]"},
                    material::small_strain_constants(start).mu);
  ASSERT_EQ(p.num_free(), 3);
  const Eigen::VectorXd t = p.theta(p.start());
  EXPECT_TRUE(t.isApprox(start.params(), 1e-15)) << t.transpose();  // the start reproduces the material
  check_jacobian(p, {}, kStep, kTolerance, "ogden_fixed");
  EXPECT_THROW(TrainingProblem(d, d.layer_depths[0], coarse(), start, {"E"}, 1e3), Error);
}

TEST(TrainingSensitivities, SplineIndentation) {
  const Dataset d = indentation(axisym::PunchContact::Stick);
  const auto start = material::SplineMaterial::from_model(material::NeoHookean(20e3, 0.45));
  TrainingProblem p(d, d.layer_depths[0], coarse(), start, {}, material::small_strain_constants(start).mu);
  ASSERT_EQ(p.num_free(), start.num_params());
  // The eight parameters the curves depend on most (knots near the rest state).
  Evaluation e;
  ASSERT_TRUE(p.evaluate(p.start(), e)) << e.reason;
  std::vector<Eigen::Index> order(static_cast<std::size_t>(p.num_free()));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::sort(order.begin(), order.end(),
            [&](Eigen::Index a, Eigen::Index b) { return e.jacobian.col(a).norm() > e.jacobian.col(b).norm(); });
  order.resize(8);
  check_jacobian(p, order, 3e-3, kTolerance, "spline");
}

TEST(TrainingSensitivities, BondedCompression) {
  Dataset d;
  d.test = TestKind::Compression;
  d.layer_depths = {10e-3};
  d.sample_radius = 8e-3;
  d.contact = axisym::PunchContact::Stick;
  d.curves.push_back(test::measured("c1", CurveRole::Train, 8e-3, ramp(2.5e-3, 6, 2000.0)));
  const material::NeoHookean start(20e3, 0.45);
  TrainingProblem p(d, d.layer_depths[0], coarse(), start, {}, material::small_strain_constants(start).mu);
  check_jacobian(p, {}, kStep, kTolerance, "compression");
}

TEST(TrainingSensitivities, HomogeneousCurves) {
  Dataset d;
  d.test = TestKind::Homogeneous;
  d.curves.push_back(test::measured("u", CurveRole::Train, 0.0, {{0.7, 0.9, 1.3, 1.8, 2.2}, {0, 0, 0, 0, 0}},
                                    material::LoadCase::Uniaxial));
  d.curves.push_back(test::measured("b", CurveRole::Train, 0.0, {{1.1, 1.3, 1.5}, {0, 0, 0}},
                                    material::LoadCase::Equibiaxial));
  d.curves.push_back(test::measured("s", CurveRole::Train, 0.0, {{0.1, 0.4, 0.8}, {0, 0, 0}},
                                    material::LoadCase::SimpleShear));
  const auto start = material::IsochoricInvariant::yeoh(12e3, 0.6e3, 0.15e3, 5e-6);
  TrainingProblem p(d, 0.0, coarse(), start, {}, material::small_strain_constants(start).mu);
  EXPECT_EQ(p.num_residuals(), 11);
  check_jacobian(p, {}, 1e-3, 1e-7, "homogeneous_yeoh");
  const auto spline = material::SplineMaterial::from_model(start);
  TrainingProblem ps(d, 0.0, coarse(), spline, {}, material::small_strain_constants(spline).mu);
  check_jacobian(ps, {}, 1e-3, 1e-7, "homogeneous_spline");

  // With the curvature regularization: one extra residual per interior knot
  // of f, g and h (3 × 6 with the default 8 knots), linear in θ, zero at the
  // start; its Jacobian rows against finite differences too, and
  // regularization(x) is the squared norm of those rows away from the start.
  ps.set_curvature_regularization(0.1 / material::small_strain_constants(spline).mu);
  EXPECT_EQ(ps.num_residuals(), 11 + 18);
  check_jacobian(ps, {}, 1e-3, 1e-7, "homogeneous_spline_regularized");
  Eigen::VectorXd x = ps.start();
  x[3] += 0.002;
  x[12] -= 0.001;
  Evaluation e;
  ASSERT_TRUE(ps.evaluate(x, e)) << e.reason;
  EXPECT_GT(ps.regularization(x), 0.0);
  EXPECT_NEAR(ps.regularization(x), e.residuals.tail(18).squaredNorm(), 1e-12 * ps.regularization(x));
  EXPECT_LT(ps.regularization(ps.start()), 1e-20 * ps.regularization(x));  // rounding of θ = scale·x
}

}  // namespace
}  // namespace palpa::fit
