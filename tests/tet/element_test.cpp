// SPDX-License-Identifier: AGPL-3.0-or-later
// The linear tet: gradient, Hessian and parameter derivatives against finite
// differences, rigid-motion invariance, PSD projection, Cauchy stress.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/material/kinematics.hpp"
#include "palpa/material/models.hpp"
#include "palpa/material/spline_material.hpp"
#include "palpa/tet/element.hpp"

namespace palpa::tet {
namespace {

using palpa::test::derivatives_match;
using palpa::test::fd_gradient;
using palpa::test::fd_jacobian;

constexpr double kH = 2e-3;  // edge length [m]

Mat34 rest_tet() {
  Mat34 X;
  X << 0.0, kH, 0.1 * kH, 0.2 * kH,  //
      0.0, 0.1 * kH, 0.9 * kH, 0.15 * kH,  //
      0.0, -0.05 * kH, 0.1 * kH, 1.1 * kH;
  return X;
}

Mat34 unflatten(const Eigen::VectorXd& v) { return Eigen::Map<const Mat34>(v.data()); }

TEST(TetElement, GeometryOfTheReferenceTet) {
  Mat34 X = Mat34::Zero();
  X(0, 1) = 1.0;
  X(1, 2) = 1.0;
  X(2, 3) = 1.0;
  const TetGeometry g = tet_geometry(X);
  EXPECT_NEAR(g.volume, 1.0 / 6.0, 1e-15);
  Mat43 expected;
  expected << -1, -1, -1, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  EXPECT_LE((g.grad_n - expected).cwiseAbs().maxCoeff(), 1e-15);
  // Gradients of the shape functions sum to zero (partition of unity).
  EXPECT_LE(tet_geometry(rest_tet()).grad_n.colwise().sum().cwiseAbs().maxCoeff(), 1e-9 / kH);
}

TEST(TetElement, GradientHessianAndParametersMatchFiniteDifferences) {
  const material::NeoHookean nh(12e3, 0.45);
  const material::SplineMaterial spline = material::SplineMaterial::from_model(nh);
  const TetGeometry g = tet_geometry(rest_tet());
  auto rng = palpa::test::make_rng(11);
  std::uniform_real_distribution<double> du(-0.12 * kH, 0.12 * kH);
  for (const material::Material* m : {static_cast<const material::Material*>(&nh),
                                      static_cast<const material::Material*>(&spline)}) {
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd x = Eigen::Map<const Vec12>(rest_tet().data());
      for (int i = 0; i < 12; ++i) x[i] += du(rng);
      TetResult r;
      ASSERT_TRUE(tet_evaluate(*m, g, unflatten(x), material::EvalOrder::Hessian,
                               material::PsdProjection::None, r));
      const auto energy = [&](const Eigen::VectorXd& v) {
        TetResult e;
        EXPECT_TRUE(tet_evaluate(*m, g, unflatten(v), material::EvalOrder::Energy,
                                 material::PsdProjection::None, e));
        return e.energy;
      };
      const auto grad = [&](const Eigen::VectorXd& v) {
        TetResult e;
        EXPECT_TRUE(tet_evaluate(*m, g, unflatten(v), material::EvalOrder::Gradient,
                                 material::PsdProjection::None, e));
        return Eigen::VectorXd(e.gradient);
      };
      EXPECT_TRUE(derivatives_match(r.gradient, fd_gradient(energy, x, 1e-3 * kH), 1e-7));
      EXPECT_TRUE(derivatives_match(r.hessian, fd_jacobian(grad, x, 1e-3 * kH), 1e-6));
      EXPECT_LE((r.hessian - r.hessian.transpose()).cwiseAbs().maxCoeff(),
                1e-10 * r.hessian.cwiseAbs().maxCoeff());

      // ∂g/∂θ against central differences of the gradient in each parameter.
      const Eigen::Index p = m->num_params();
      Eigen::MatrixXd w3(3, p), w9(9, p), analytic(12, p);
      tet_dgradient_dparam(*m, g, unflatten(x), w3, w9, analytic);
      auto work = m->clone();
      const auto grad_of_theta = [&](const Eigen::VectorXd& theta) {
        work->set_params(theta);
        TetResult e;
        EXPECT_TRUE(tet_evaluate(*work, g, unflatten(x), material::EvalOrder::Gradient,
                                 material::PsdProjection::None, e));
        return Eigen::VectorXd(e.gradient);
      };
      // Steps relative to each parameter (moduli ~1e4 Pa, ratios ~1).
      const Eigen::VectorXd theta0 = m->params();
      Eigen::MatrixXd numeric(12, p);
      for (Eigen::Index k = 0; k < p; ++k) {
        const double h = 1e-4 * std::max(std::abs(theta0[k]), 1e-2);
        const auto along = [&](const Eigen::VectorXd& t) {
          Eigen::VectorXd theta = theta0;
          theta[k] = t[0];
          return grad_of_theta(theta);
        };
        numeric.col(k) = fd_jacobian(along, Eigen::VectorXd::Constant(1, theta0[k]), h);
      }
      EXPECT_TRUE(derivatives_match(analytic, numeric, 1e-5));
    }
  }
}

TEST(TetElement, RigidMotionHasNoEnergyAndNoForce) {
  const material::NeoHookean nh(12e3, 0.45);
  const TetGeometry g = tet_geometry(rest_tet());
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.3, -0.1, 0.05);
  const Mat34 x = (R * rest_tet()).colwise() + t;
  TetResult r;
  ASSERT_TRUE(tet_evaluate(nh, g, x, material::EvalOrder::Gradient, material::PsdProjection::None, r));
  // Against the scale of a 1% strain: μ·0.01·V and μ·0.01·h².
  const double mu = 12e3 / 2.9;
  EXPECT_LE(std::abs(r.energy), 1e-10 * mu * 1e-2 * g.volume);
  EXPECT_LE(r.gradient.cwiseAbs().maxCoeff(), 1e-8 * mu * 1e-2 * kH * kH);
}

TEST(TetElement, ProjectedHessianIsPositiveSemiDefinite) {
  const material::NeoHookean nh(12e3, 0.45);
  const TetGeometry g = tet_geometry(rest_tet());
  // Strong compression with shear: the true Hessian is indefinite there.
  Mat34 x = rest_tet();
  x.row(2) *= 0.45;
  x.row(0) += 0.4 * x.row(2);
  TetResult t, p;
  ASSERT_TRUE(tet_evaluate(nh, g, x, material::EvalOrder::Hessian, material::PsdProjection::None, t));
  ASSERT_TRUE(tet_evaluate(nh, g, x, material::EvalOrder::Hessian, material::PsdProjection::Clamp, p));
  const Eigen::VectorXd et = Eigen::SelfAdjointEigenSolver<Mat12>(t.hessian).eigenvalues();
  const Eigen::VectorXd ep = Eigen::SelfAdjointEigenSolver<Mat12>(p.hessian).eigenvalues();
  EXPECT_LT(et.minCoeff(), -1e-6 * et.maxCoeff());
  EXPECT_GE(ep.minCoeff(), -1e-10 * ep.maxCoeff());
}

TEST(TetElement, InvertedElementHasNoEnergy) {
  const material::NeoHookean nh(12e3, 0.45);
  const TetGeometry g = tet_geometry(rest_tet());
  Mat34 x = rest_tet();
  x.col(3) = x.col(0) - 0.1 * (x.col(3) - x.col(0));  // the apex pushed through its base
  TetResult r;
  EXPECT_FALSE(tet_evaluate(nh, g, x, material::EvalOrder::Energy, material::PsdProjection::None, r));
}

TEST(TetElement, CauchyStressOfUniaxialStretchMatchesTheMaterial) {
  const material::NeoHookean nh(12e3, 0.45);
  const TetGeometry g = tet_geometry(rest_tet());
  material::Mat3 F = material::Mat3::Identity();
  F(0, 0) = 1.2;
  F(1, 1) = F(2, 2) = 0.95;
  const Mat34 x = F * rest_tet();
  material::Stress3 s;
  material::stress(nh, F, material::EvalOrder::Gradient, material::PsdProjection::None, s);
  const material::Mat3 expected = s.P * F.transpose() / F.determinant();
  const material::Mat3 sigma = cauchy_stress(nh, g, x);
  EXPECT_LE((sigma - expected).cwiseAbs().maxCoeff(), 1e-9 * expected.cwiseAbs().maxCoeff());
  EXPECT_LE(std::abs(sigma(0, 1)) + std::abs(sigma(0, 2)) + std::abs(sigma(1, 2)), 1e-9 * std::abs(sigma(0, 0)));
}

}  // namespace
}  // namespace palpa::tet
