// SPDX-License-Identifier: AGPL-3.0-or-later
// The conformance suite: every material model through the same checks.
//  - stress-free rest state and Ψ(1,1,1) = 0;
//  - small-strain Lamé parameters;
//  - permutation symmetry;
//  - ∂Ψ/∂λ, ∂²Ψ/∂λ², ∂²Ψ/∂λ∂θ against finite differences at random stretches,
//    at repeated stretches (λ1 = λ2, all equal), near inversion and inverted;
//  - P, dP/dF (3D and axisymmetric) and dP/dθ against finite differences,
//    including repeated and inverted singular values;
//  - projected tangents are positive semi-definite;
//  - frame indifference and isotropy.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "model_fixtures.hpp"
#include "palpa/material/kinematics.hpp"

namespace palpa::material {
namespace {

using test::param_scale;

using palpa::test::derivatives_match;
using palpa::test::fd_gradient;
using palpa::test::fd_jacobian;
using test::ModelCase;

class Conformance : public ::testing::TestWithParam<ModelCase> {
 protected:
  void SetUp() override { m_ = GetParam().make(); }
  double scale() const { return GetParam().expected.mu; }
  std::unique_ptr<Material> m_;
};

// Stretch triples where every derivative is checked.
std::vector<Vec3> probe_stretches(bool inversion_safe) {
  auto rng = palpa::test::make_rng(7);
  std::uniform_real_distribution<double> u(0.6, 1.6);
  std::vector<Vec3> pts;
  for (int i = 0; i < 6; ++i) {
    const double a = u(rng), b = u(rng), c = u(rng);  // drawn in order on every compiler
    pts.emplace_back(a, b, c);
  }
  pts.emplace_back(1.3, 1.3, 0.8);     // λ1 = λ2
  pts.emplace_back(0.9, 1.2, 0.9);     // λ1 = λ3
  pts.emplace_back(1.15, 1.15, 1.15);  // all equal
  pts.emplace_back(1.0, 1.0, 1.0);     // rest
  pts.emplace_back(1.02, 0.99, 1.005); // small strain
  if (inversion_safe) {
    pts.emplace_back(0.9, 0.8, 0.25);   // strong compression, J = 0.18
    pts.emplace_back(0.7, 0.6, 0.15);   // J = 0.063, below the continuation threshold
    pts.emplace_back(1.1, 0.9, -0.2);   // inverted element (signed stretch)
  }
  return pts;
}

std::string describe(const Vec3& l) { return ::testing::PrintToString(l.transpose()); }

TEST_P(Conformance, RestStateIsStressFreeWithZeroEnergy) {
  StretchEnergy e;
  m_->evaluate(Vec3::Ones(), EvalOrder::Hessian, e);
  EXPECT_LE(e.grad.cwiseAbs().maxCoeff(), 1e-10 * scale());
  EXPECT_LE(std::abs(e.psi), 1e-10 * scale());
}

TEST_P(Conformance, SmallStrainLinearizationMatchesLameParameters) {
  const ElasticConstants got = small_strain_constants(*m_);
  const ElasticConstants& want = GetParam().expected;
  const double tol = GetParam().lame_tolerance;
  EXPECT_NEAR(got.mu, want.mu, tol * want.mu);
  EXPECT_NEAR(got.lambda, want.lambda, tol * std::abs(want.lambda) + tol * want.mu);
  // And the Hessian at rest has the isotropic-linear-elastic structure.
  const Mat3 h = m_->d2psi_dlambda2(Vec3::Ones());
  EXPECT_NEAR(h(0, 0), h(1, 1), 1e-9 * h(0, 0));
  EXPECT_NEAR(h(0, 1), h(1, 2), 1e-9 * h(0, 0));
}

TEST_P(Conformance, EnergyIsSymmetricUnderPermutations) {
  const Vec3 l(1.3, 0.8, 1.1);
  const StretchEnergy e = [&] {
    StretchEnergy x;
    m_->evaluate(l, EvalOrder::Hessian, x);
    return x;
  }();
  const Vec3 p(l[2], l[0], l[1]);  // cyclic
  StretchEnergy ep;
  m_->evaluate(p, EvalOrder::Hessian, ep);
  EXPECT_NEAR(ep.psi, e.psi, 1e-12 * scale());
  EXPECT_NEAR(ep.grad[0], e.grad[2], 1e-10 * scale());
  EXPECT_NEAR(ep.grad[1], e.grad[0], 1e-10 * scale());
  EXPECT_NEAR(ep.hess(0, 1), e.hess(2, 0), 1e-10 * scale());
}

TEST_P(Conformance, StretchGradientMatchesFiniteDifferences) {
  for (const Vec3& l : probe_stretches(GetParam().inversion_safe)) {
    const auto f = [&](const Eigen::VectorXd& x) { return m_->psi(Vec3(x)); };
    const Vec3 g = m_->dpsi_dlambda(l);
    EXPECT_TRUE(derivatives_match(g, fd_gradient(f, l, 1e-4), 1e-7,
                                  l == Vec3::Ones() ? palpa::test::ZeroPolicy::MayBeZero
                                                    : palpa::test::ZeroPolicy::MustBeNonZero,
                                  scale()))
        << describe(l);
  }
}

TEST_P(Conformance, StretchHessianMatchesFiniteDifferences) {
  for (const Vec3& l : probe_stretches(GetParam().inversion_safe)) {
    const auto g = [&](const Eigen::VectorXd& x) {
      return Eigen::VectorXd(m_->dpsi_dlambda(Vec3(x)));
    };
    EXPECT_TRUE(derivatives_match(m_->d2psi_dlambda2(l), fd_jacobian(g, l, 1e-4), 1e-6))
        << describe(l);
  }
}

// Finite differences in θ with a step relative to each parameter's size.
Eigen::MatrixXd fd_dgrad_dparam(const Material& m, const Vec3& l, double ref) {
  const Eigen::VectorXd theta0 = m.params();
  const Eigen::VectorXd scale = param_scale(m, ref);
  auto work = m.clone();
  const auto g = [&](const Eigen::VectorXd& x) {
    work->set_params(theta0 + scale.cwiseProduct(x));
    return Eigen::VectorXd(work->dpsi_dlambda(l));
  };
  Eigen::MatrixXd jac = fd_jacobian(g, Eigen::VectorXd::Zero(theta0.size()), 1e-4);
  return jac * scale.cwiseInverse().asDiagonal();
}

TEST_P(Conformance, ParameterDerivativeMatchesFiniteDifferences) {
  for (const Vec3& l : probe_stretches(GetParam().inversion_safe)) {
    if (l == Vec3::Ones()) continue;  // ∂²Ψ/∂λ∂θ vanishes at rest by design
    Eigen::MatrixXd analytic(3, m_->num_params());
    m_->d2psi_dlambda_dparam(l, analytic);
    const Eigen::MatrixXd numeric = fd_dgrad_dparam(*m_, l, scale());
    // Per relative change of each parameter, every column is a stress.
    const Eigen::VectorXd ps = param_scale(*m_, scale());
    for (Eigen::Index k = 0; k < m_->num_params(); ++k) {
      EXPECT_TRUE(derivatives_match(analytic.col(k) * ps[k], numeric.col(k) * ps[k], 1e-6,
                                    palpa::test::ZeroPolicy::MayBeZero, scale()))
          << describe(l) << " parameter " << m_->param_info(k).name;
    }
    EXPECT_GT(analytic.norm(), 0.0) << describe(l);
  }
}

TEST_P(Conformance, ParameterDerivativeIsZeroAtRest) {
  Eigen::MatrixXd d(3, m_->num_params());
  m_->d2psi_dlambda_dparam(Vec3::Ones(), d);
  EXPECT_LE(d.cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, d.cwiseAbs().maxCoeff()));
}

// Deformation gradients: random, repeated and inverted singular values.
std::vector<Mat3> probe_gradients(bool inversion_safe) {
  auto rng = palpa::test::make_rng(11);
  std::uniform_real_distribution<double> u(0.7, 1.4);
  std::uniform_real_distribution<double> a(-3.0, 3.0);
  const auto rot = [&] {
    const double angle = a(rng), x = a(rng), y = a(rng), z = a(rng);  // drawn in order on every compiler
    return Eigen::AngleAxisd(angle, Vec3(x, y, z).normalized()).toRotationMatrix();
  };
  std::vector<Mat3> fs;
  for (int i = 0; i < 4; ++i) {
    Mat3 F;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) F(r, c) = (r == c ? 1.0 : 0.0) + 0.3 * (u(rng) - 1.05);
    fs.push_back(F);
  }
  fs.push_back(rot() * Vec3(1.2, 1.2, 0.9).asDiagonal() * rot());   // σ1 = σ2
  fs.push_back(rot() * Vec3(1.1, 1.1, 1.1).asDiagonal() * rot());   // all equal
  fs.push_back(rot() * Vec3(1.3, 0.9, 0.9 + 1e-9).asDiagonal() * rot());  // nearly repeated
  if (inversion_safe) fs.push_back(rot() * Vec3(1.1, 0.9, -0.3).asDiagonal() * rot());  // inverted
  return fs;
}

Eigen::VectorXd vec(const Mat3& m) { return Eigen::Map<const Eigen::VectorXd>(m.data(), 9); }
Mat3 unvec(const Eigen::VectorXd& v) { return Eigen::Map<const Mat3>(v.data()); }

TEST_P(Conformance, FirstPiolaAndTangentMatchFiniteDifferences) {
  for (const Mat3& F : probe_gradients(GetParam().inversion_safe)) {
    Stress3 s;
    stress(*m_, F, EvalOrder::Hessian, PsdProjection::None, s);
    const auto psi = [&](const Eigen::VectorXd& x) {
      Stress3 t;
      stress(*m_, unvec(x), EvalOrder::Energy, PsdProjection::None, t);
      return t.psi;
    };
    const auto p = [&](const Eigen::VectorXd& x) {
      Stress3 t;
      stress(*m_, unvec(x), EvalOrder::Gradient, PsdProjection::None, t);
      return vec(t.P);
    };
    EXPECT_TRUE(derivatives_match(vec(s.P), fd_gradient(psi, vec(F), 1e-4), 1e-7))
        << "F =\n" << F;
    EXPECT_TRUE(derivatives_match(s.dPdF, fd_jacobian(p, vec(F), 1e-4), 1e-6)) << "F =\n" << F;
  }
}

TEST_P(Conformance, ParameterDerivativeOfStressMatchesFiniteDifferences) {
  const Mat3 F = probe_gradients(false)[0];
  Eigen::MatrixXd work(3, m_->num_params());
  Eigen::MatrixXd analytic(9, m_->num_params());
  dP_dparam(*m_, F, work, analytic);
  // Through the stretch derivative: dP/dθ = U diag(∂²Ψ/∂λ∂θ) Vᵀ.
  const Svd3 svd = signed_svd(F);
  const Eigen::MatrixXd numeric_stretch = fd_dgrad_dparam(*m_, svd.sigma, scale());
  const Eigen::VectorXd ps = param_scale(*m_, scale());
  for (Eigen::Index k = 0; k < m_->num_params(); ++k) {
    const Mat3 pk = svd.U * numeric_stretch.col(k).asDiagonal() * svd.V.transpose();
    EXPECT_TRUE(derivatives_match(analytic.col(k) * ps[k], vec(pk) * ps[k], 1e-6,
                                  palpa::test::ZeroPolicy::MayBeZero, scale()))
        << m_->param_info(k).name;
  }
  EXPECT_GT(analytic.norm(), 0.0);
}

TEST_P(Conformance, ProjectedTangentIsPositiveSemiDefinite) {
  for (PsdProjection proj : {PsdProjection::Clamp, PsdProjection::Abs}) {
    for (const Mat3& F : probe_gradients(GetParam().inversion_safe)) {
      Stress3 s;
      stress(*m_, F, EvalOrder::Hessian, proj, s);
      const Eigen::SelfAdjointEigenSolver<Mat9> eig(s.dPdF);
      EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * eig.eigenvalues().cwiseAbs().maxCoeff())
          << "F =\n" << F;
    }
  }
  // Where the true tangent is already PSD (at rest), projection changes nothing.
  Stress3 a;
  Stress3 b;
  stress(*m_, Mat3::Identity(), EvalOrder::Hessian, PsdProjection::None, a);
  stress(*m_, Mat3::Identity(), EvalOrder::Hessian, PsdProjection::Clamp, b);
  EXPECT_LE((a.dPdF - b.dPdF).cwiseAbs().maxCoeff(), 1e-9 * a.dPdF.cwiseAbs().maxCoeff());
}

TEST_P(Conformance, FrameIndifferentAndIsotropic) {
  const Mat3 F = probe_gradients(false)[1];
  const Mat3 q = Eigen::AngleAxisd(0.7, Vec3(1.0, -2.0, 0.5).normalized()).toRotationMatrix();
  Stress3 s;
  Stress3 sq;
  Stress3 sr;
  stress(*m_, F, EvalOrder::Gradient, PsdProjection::None, s);
  stress(*m_, q * F, EvalOrder::Gradient, PsdProjection::None, sq);
  stress(*m_, F * q, EvalOrder::Gradient, PsdProjection::None, sr);
  const double ps = s.P.cwiseAbs().maxCoeff();
  EXPECT_NEAR(sq.psi, s.psi, 1e-12 * scale());
  EXPECT_LE((sq.P - q * s.P).cwiseAbs().maxCoeff(), 1e-10 * ps);  // P(QF) = Q P(F)
  EXPECT_NEAR(sr.psi, s.psi, 1e-12 * scale());
  EXPECT_LE((sr.P - s.P * q).cwiseAbs().maxCoeff(), 1e-10 * ps);  // isotropy
}

// Axisymmetric specialization: F2 on (r, z) plus the hoop stretch.
TEST_P(Conformance, AxisymmetricStressAndTangentMatchFiniteDifferences) {
  struct Probe {
    Mat2 F2;
    double hoop;
  };
  std::vector<Probe> probes = {
      {(Mat2() << 1.1, 0.15, -0.2, 0.85).finished(), 1.05},
      {(Mat2() << 0.9, 0.0, 0.0, 0.9).finished(), 0.9},                // all equal
      {(Mat2() << 1.2, 0.0, 0.0, 1.2).finished(), 0.95},               // σ1 = σ2
      {Eigen::Rotation2Dd(0.4).toRotationMatrix() * (Mat2() << 1.1, 0, 0, 0.8).finished(), 1.1},
  };
  if (GetParam().inversion_safe) {
    probes.push_back({(Mat2() << 0.8, 0.1, 0.05, -0.2).finished(), 1.0});  // inverted in-plane
  }
  const auto pack = [](const Mat2& f, double h) {
    Eigen::VectorXd x(5);
    x << f(0, 0), f(1, 0), f(0, 1), f(1, 1), h;
    return x;
  };
  const auto f2 = [](const Eigen::VectorXd& x) { return (Mat2() << x[0], x[2], x[1], x[3]).finished(); };
  for (const Probe& pr : probes) {
    StressAxisym s;
    stress_axisymmetric(*m_, pr.F2, pr.hoop, EvalOrder::Hessian, PsdProjection::None, s);
    const auto psi = [&](const Eigen::VectorXd& x) {
      StressAxisym t;
      stress_axisymmetric(*m_, f2(x), x[4], EvalOrder::Energy, PsdProjection::None, t);
      return t.psi;
    };
    const auto p = [&](const Eigen::VectorXd& x) {
      StressAxisym t;
      stress_axisymmetric(*m_, f2(x), x[4], EvalOrder::Gradient, PsdProjection::None, t);
      return Eigen::VectorXd(t.P);
    };
    const Eigen::VectorXd x0 = pack(pr.F2, pr.hoop);
    EXPECT_TRUE(derivatives_match(s.P, fd_gradient(psi, x0, 1e-4), 1e-7)) << x0.transpose();
    EXPECT_TRUE(derivatives_match(s.dPdF, fd_jacobian(p, x0, 1e-4), 1e-6)) << x0.transpose();

    // The same state through the 3D path gives the same energy and stress.
    Mat3 F = Mat3::Zero();
    F(0, 0) = pr.F2(0, 0);
    F(0, 2) = pr.F2(0, 1);
    F(2, 0) = pr.F2(1, 0);
    F(2, 2) = pr.F2(1, 1);
    F(1, 1) = pr.hoop;
    Stress3 s3;
    stress(*m_, F, EvalOrder::Gradient, PsdProjection::None, s3);
    EXPECT_NEAR(s3.psi, s.psi, 1e-10 * scale());
    EXPECT_NEAR(s3.P(0, 0), s.P[0], 1e-9 * scale());
    EXPECT_NEAR(s3.P(2, 0), s.P[1], 1e-9 * scale());
    EXPECT_NEAR(s3.P(1, 1), s.P[4], 1e-9 * scale());

    StressAxisym proj;
    stress_axisymmetric(*m_, pr.F2, pr.hoop, EvalOrder::Hessian, PsdProjection::Clamp, proj);
    const Eigen::SelfAdjointEigenSolver<Mat5> eig(proj.dPdF);
    EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-9 * eig.eigenvalues().cwiseAbs().maxCoeff());

    Eigen::MatrixXd work(3, m_->num_params());
    Eigen::MatrixXd dp(5, m_->num_params());
    dP_dparam_axisymmetric(*m_, pr.F2, pr.hoop, work, dp);
    Eigen::MatrixXd dp3(9, m_->num_params());
    dP_dparam(*m_, F, work, dp3);
    EXPECT_LE((dp.row(0) - dp3.row(0)).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, dp.cwiseAbs().maxCoeff()));
    EXPECT_LE((dp.row(4) - dp3.row(4)).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, dp.cwiseAbs().maxCoeff()));
  }
}

TEST_P(Conformance, InvertedElementsGetRestoringForcesNotNaN) {
  if (!GetParam().inversion_safe) {
    // StVK's documented collapse: squashed flat, its resistance vanishes
    // (∂Ψ/∂λ3 = λ3 (λ/2 (I_C − 3) + μ (λ3² − 1)) = 0 at λ3 = 0).
    EXPECT_EQ(m_->dpsi_dlambda(Vec3(1.0, 1.0, 0.0))[2], 0.0);
    EXPECT_LT(m_->dpsi_dlambda(Vec3(1.0, 1.0, 0.5))[2], 0.0);
    return;
  }
  // Squash through J = 0: the energy stays finite and keeps growing, and the
  // force on the compressed direction pushes back (∂Ψ/∂λ3 < 0).
  double last = -1.0;
  for (double l3 : {0.5, 0.2, 0.1, 0.05, 0.0, -0.05, -0.2}) {
    StretchEnergy e;
    m_->evaluate(Vec3(1.0, 1.0, l3), EvalOrder::Hessian, e);
    ASSERT_TRUE(std::isfinite(e.psi) && e.grad.allFinite() && e.hess.allFinite()) << l3;
    EXPECT_GT(e.psi, last) << l3;
    EXPECT_LT(e.grad[2], 0.0) << l3;
    last = e.psi;
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, Conformance, ::testing::ValuesIn(test::all_model_cases()),
                         [](const auto& param_info) { return param_info.param.name; });

TEST(SignedSvd, ThreeByThreeReconstructsWithRotationsAndSignedSmallestValue) {
  const Mat3 F = (Mat3() << 0.9, 0.2, -0.1, 0.05, 1.1, 0.3, 0.1, -0.2, -0.7).finished();
  const Svd3 s = signed_svd(F);
  EXPECT_LE((s.U * s.sigma.asDiagonal() * s.V.transpose() - F).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_NEAR(s.U.determinant(), 1.0, 1e-13);
  EXPECT_NEAR(s.V.determinant(), 1.0, 1e-13);
  EXPECT_LT(s.sigma[2], 0.0);  // det F < 0
  EXPECT_NEAR(s.sigma.prod(), F.determinant(), 1e-13);
}

TEST(SignedSvd, TwoByTwoClosedFormReconstructs) {
  auto rng = palpa::test::make_rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int i = 0; i < 200; ++i) {
    const Mat2 F = (Mat2() << u(rng), u(rng), u(rng), u(rng)).finished();
    const Svd2 s = signed_svd(F);
    ASSERT_LE((s.U * s.sigma.asDiagonal() * s.V.transpose() - F).cwiseAbs().maxCoeff(), 1e-13) << F;
    ASSERT_NEAR(s.U.determinant(), 1.0, 1e-13);
    ASSERT_NEAR(s.V.determinant(), 1.0, 1e-13);
    ASSERT_GE(s.sigma[0], std::abs(s.sigma[1]) - 1e-15);
    ASSERT_NEAR(s.sigma.prod(), F.determinant(), 1e-12);
  }
  // Where one part vanishes or the half-angle root changes branch: a pure
  // rotation by nearly π, a reflection, a zero matrix, a rank-one matrix.
  const double pi = 3.14159265358979323846;
  for (const Mat2& F : {Mat2((Mat2() << std::cos(pi - 1e-9), -std::sin(pi - 1e-9), std::sin(pi - 1e-9),
                              std::cos(pi - 1e-9)).finished()),
                        Mat2((Mat2() << -1.0, 0.0, 0.0, -1.0).finished()), Mat2((Mat2() << 1.0, 0.0, 0.0, -1.0).finished()),
                        Mat2((Mat2() << 0.0, 2.0, 2.0, 0.0).finished()), Mat2(Mat2::Zero()),
                        Mat2((Mat2() << 1.0, 2.0, 0.5, 1.0).finished()), Mat2((Mat2() << -0.3, 1e-12, -1e-12, -0.7).finished())}) {
    const Svd2 s = signed_svd(F);
    EXPECT_LE((s.U * s.sigma.asDiagonal() * s.V.transpose() - F).cwiseAbs().maxCoeff(), 1e-14) << F;
    EXPECT_NEAR(s.U.determinant(), 1.0, 1e-14) << F;
    EXPECT_NEAR(s.V.determinant(), 1.0, 1e-14) << F;
    EXPECT_GE(s.sigma[0], std::abs(s.sigma[1])) << F;
  }
  const Svd2 id = signed_svd(Mat2(Mat2::Identity()));
  EXPECT_NEAR(id.sigma[0], 1.0, 1e-15);
  EXPECT_NEAR(id.sigma[1], 1.0, 1e-15);
}

}  // namespace
}  // namespace palpa::material
