// SPDX-License-Identifier: AGPL-3.0-or-later
// The axisymmetric element: gradient, Hessian and parameter derivatives against
// finite differences for both formulations; patch tests (rigid motions,
// homogeneous deformations) with their exact energies.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/axisym/element.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"

namespace palpa::axisym {
namespace {

using palpa::test::derivatives_match;
using palpa::test::fd_gradient;
using palpa::test::fd_jacobian;

constexpr double kH = 1e-3;  // cell size [m]

Eigen::Matrix<double, 2, 4> rest_cell(double r0) {
  Eigen::Matrix<double, 2, 4> x;
  x << r0, r0 + kH, r0 + 1.1 * kH, r0 - 0.1 * kH, -kH, -kH, 0.0, 0.1 * kH;  // a skewed quad
  return x;
}

class ElementDerivatives
    : public ::testing::TestWithParam<std::tuple<ElementFormulation, double>> {};

TEST_P(ElementDerivatives, GradientHessianAndParametersMatchFiniteDifferences) {
  const auto [form_p, r0] = GetParam();
  const auto form = form_p;  // a plain variable: lambdas below capture it
  const material::NeoHookean nh(12e3, 0.45);
  const material::SplineMaterial spline = material::SplineMaterial::from_model(nh);
  const QuadGeometry g = quad_geometry(rest_cell(r0));
  auto rng = palpa::test::make_rng(5);
  // Displacements of a tenth of the cell, and of the radius next to the axis
  // (where F_θθ = 1 + u_r/r).
  const double amp = 0.15 * std::min(kH, r0);
  std::uniform_real_distribution<double> du(-amp, amp);
  for (const material::Material* m : {static_cast<const material::Material*>(&nh),
                                      static_cast<const material::Material*>(&spline)}) {
    for (int trial = 0; trial < 3; ++trial) {
      Vec8 u;
      for (int i = 0; i < 8; ++i) u[i] = du(rng);
      ElementResult r;
      ASSERT_TRUE(element_evaluate(*m, g, u, material::EvalOrder::Hessian,
                                   material::PsdProjection::None, r, ElementOptions{form, 3000.0}));
      const auto energy = [&](const Eigen::VectorXd& v) {
        ElementResult e;
        EXPECT_TRUE(element_evaluate(*m, g, Vec8(v), material::EvalOrder::Energy,
                                     material::PsdProjection::None, e, ElementOptions{form, 3000.0}));
        return e.energy;
      };
      const auto grad = [&](const Eigen::VectorXd& v) {
        ElementResult e;
        EXPECT_TRUE(element_evaluate(*m, g, Vec8(v), material::EvalOrder::Gradient,
                                     material::PsdProjection::None, e, ElementOptions{form, 3000.0}));
        return Eigen::VectorXd(e.gradient);
      };
      EXPECT_TRUE(derivatives_match(r.gradient, fd_gradient(energy, u, 1e-3 * kH), 1e-7));
      EXPECT_TRUE(derivatives_match(r.hessian, fd_jacobian(grad, u, 1e-3 * kH), 1e-6));
      EXPECT_LE((r.hessian - r.hessian.transpose()).cwiseAbs().maxCoeff(),
                1e-10 * r.hessian.cwiseAbs().maxCoeff());

      // ∂g/∂θ against differences of the gradient in each parameter.
      const Eigen::Index p = m->num_params();
      Eigen::MatrixXd w3(3, p), w5(5, p), analytic(8, p);
      element_dgradient_dparam(*m, g, u, w3, w5, analytic, ElementOptions{form, 3000.0});
      const Eigen::VectorXd theta0 = m->params();
      auto work = m->clone();
      for (Eigen::Index k = 0; k < p; ++k) {
        const double h = 1e-5 * std::max(std::abs(theta0[k]), k < 2 && p == 2 ? 1e-3 : 1e3);
        Eigen::VectorXd tp = theta0, tm = theta0;
        tp[k] += h;
        tm[k] -= h;
        ElementResult ep, em;
        work->set_params(tp);
        element_evaluate(*work, g, u, material::EvalOrder::Gradient, material::PsdProjection::None, ep, ElementOptions{form, 3000.0});
        work->set_params(tm);
        element_evaluate(*work, g, u, material::EvalOrder::Gradient, material::PsdProjection::None, em, ElementOptions{form, 3000.0});
        const Vec8 numeric = (ep.gradient - em.gradient) / (2.0 * h);
        EXPECT_TRUE(derivatives_match(analytic.col(k) * std::abs(theta0[k] == 0.0 ? 1e3 : theta0[k]),
                                      numeric * std::abs(theta0[k] == 0.0 ? 1e3 : theta0[k]), 1e-5,
                                      palpa::test::ZeroPolicy::MayBeZero,
                                      1e-3 * r.gradient.cwiseAbs().maxCoeff()))
            << m->model() << " parameter " << k;
      }
      EXPECT_GT(analytic.norm(), 0.0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Formulations, ElementDerivatives,
    ::testing::Combine(::testing::Values(ElementFormulation::Standard, ElementFormulation::FBar),
                       ::testing::Values(0.15 * kH, 5.0 * kH)),  // next to the axis, and away
    [](const auto& param_info) {
      return std::string(std::get<0>(param_info.param) == ElementFormulation::FBar ? "FBar" : "Standard") +
             (std::get<1>(param_info.param) < kH ? "NearAxis" : "Away");
    });

class Patch : public ::testing::TestWithParam<ElementFormulation> {};

TEST_P(Patch, RigidVerticalTranslationCostsNothing) {
  // Axisymmetry allows only one rigid motion: translation along z.
  const material::NeoHookean nh(12e3, 0.45);
  const QuadGeometry g = quad_geometry(rest_cell(2.0 * kH));
  Vec8 u = Vec8::Zero();
  for (int k = 0; k < 4; ++k) u[2 * k + 1] = 0.37 * kH;
  ElementResult r;
  ASSERT_TRUE(element_evaluate(nh, g, u, material::EvalOrder::Hessian, material::PsdProjection::None, r, ElementOptions{GetParam(), 3000.0}));
  EXPECT_NEAR(r.energy, 0.0, 1e-18);
  EXPECT_LE(r.gradient.cwiseAbs().maxCoeff(), 1e-16);
}

TEST_P(Patch, HomogeneousDeformationGivesTheExactEnergy) {
  // u_r = α r, u_z = β z is homogeneous: λ = (1+α, 1+α, 1+β) everywhere
  // (F_θθ = 1 + u_r/r = 1 + α), so E = Ψ(λ) × cell volume exactly, and F-bar
  // changes nothing where J is uniform.
  const material::NeoHookean nh(12e3, 0.45);
  const auto rest = rest_cell(3.0 * kH);
  const QuadGeometry g = quad_geometry(rest);
  const double alpha = 0.08;
  const double beta = -0.12;
  Vec8 u;
  for (int k = 0; k < 4; ++k) {
    u[2 * k] = alpha * rest(0, k);
    u[2 * k + 1] = beta * rest(1, k);
  }
  double volume = 0.0;
  for (double w : g.weight) volume += w;
  ElementResult r;
  ASSERT_TRUE(element_evaluate(nh, g, u, material::EvalOrder::Gradient, material::PsdProjection::None, r, ElementOptions{GetParam(), 3000.0}));
  const double psi = nh.psi(material::Vec3(1 + alpha, 1 + alpha, 1 + beta));
  EXPECT_NEAR(r.energy, psi * volume, 1e-12 * psi * volume);
  // The exact volume of the ring cell (Pappus): 2π r̄ A, with r̄ its centroid.
  const double area = 0.5 * std::abs((rest(0, 0) - rest(0, 2)) * (rest(1, 1) - rest(1, 3)) -
                                     (rest(0, 1) - rest(0, 3)) * (rest(1, 0) - rest(1, 2)));
  EXPECT_GT(area, 0.0);
  EXPECT_GT(volume, 0.0);
}

TEST_P(Patch, InvertedGaussPointIsRejected) {
  const material::NeoHookean nh(12e3, 0.45);
  const auto rest = rest_cell(3.0 * kH);
  const QuadGeometry g = quad_geometry(rest);
  Vec8 u = Vec8::Zero();
  u[5] = -2.5 * kH;  // push a top node through the cell
  ElementResult r;
  EXPECT_FALSE(element_evaluate(nh, g, u, material::EvalOrder::Energy, material::PsdProjection::None, r, ElementOptions{GetParam(), 3000.0}));
  EXPECT_LT(element_min_jacobian(g, u), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Formulations, Patch,
                         ::testing::Values(ElementFormulation::Standard, ElementFormulation::FBar),
                         [](const auto& param_info) {
                           return param_info.param == ElementFormulation::FBar ? "FBar" : "Standard";
                         });

}  // namespace
}  // namespace palpa::axisym
