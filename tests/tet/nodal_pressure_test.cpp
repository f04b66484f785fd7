// SPDX-License-Identifier: AGPL-3.0-or-later
// The tet with nodally averaged volume change (tet/nodal_pressure.hpp): the
// tet volume and dilatation energy against finite differences, the patch test
// (a homogeneous deformation gives the linear tet's energy and forces
// exactly). What it is for is in locking_physics_test.cpp.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <memory>
#include <random>

#include "common/finite_difference.hpp"
#include "common/test_support.hpp"
#include "palpa/material/models.hpp"
#include "palpa/tet/elastic_term.hpp"
#include "palpa/tet/mesh.hpp"
#include "palpa/tet/nodal_pressure.hpp"
#include "palpa/tet/system.hpp"

namespace palpa::tet {
namespace {

using test::derivatives_match;
using test::fd_gradient;
using test::fd_jacobian;

TEST(NodalPressure, TetVolumeGradientAndHessianMatchFiniteDifferences) {
  auto rng = test::make_rng(41);
  std::uniform_real_distribution<double> du(-0.3, 0.3);
  Mat34 x;
  x << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  for (int i = 0; i < 12; ++i) x.data()[i] += du(rng);
  Vec12 g;
  Mat12 H;
  const double v = tet_volume(x, &g, &H);
  Mat34 X;
  X << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  EXPECT_NEAR(tet_volume(X), 1.0 / 6.0, 1e-15);
  const auto volume = [&](const Eigen::VectorXd& y) { return tet_volume(Eigen::Map<const Mat34>(y.data())); };
  const auto gradient = [&](const Eigen::VectorXd& y) {
    Vec12 out;
    tet_volume(Eigen::Map<const Mat34>(y.data()), &out);
    return Eigen::VectorXd(out);
  };
  const Eigen::VectorXd x0 = Eigen::Map<const Vec12>(x.data());
  EXPECT_NEAR(volume(x0), v, 1e-15);
  EXPECT_TRUE(derivatives_match(g, fd_gradient(volume, x0, 1e-6), 1e-8));
  EXPECT_TRUE(derivatives_match(H, fd_jacobian(gradient, x0, 1e-6), 1e-8));
}

TEST(NodalPressure, DilatationDerivativesMatchFiniteDifferencesForEveryKindOfModel) {
  const std::vector<std::shared_ptr<const material::Material>> models = {
      std::make_shared<material::NeoHookean>(10e3, 0.49),
      std::make_shared<material::Ogden>(std::vector<double>{4e3, -1e3}, std::vector<double>{5.0, -2.0}, 0.45),
      std::make_shared<material::StVenantKirchhoff>(10e3, 0.3)};
  for (const auto& m : models) {
    for (const double J : {0.7, 1.0, 1.3}) {
      const Dilatation d = dilatation(*m, J);
      const double h = 1e-6;
      EXPECT_NEAR(d.du, (dilatation(*m, J + h).u - dilatation(*m, J - h).u) / (2 * h), 1e-6 * std::abs(d.du) + 1e-6)
          << m->model() << " J " << J;
      EXPECT_NEAR(d.d2u, (dilatation(*m, J + h).du - dilatation(*m, J - h).du) / (2 * h), 1e-6 * std::abs(d.d2u) + 1e-3)
          << m->model() << " J " << J;
      EXPECT_GT(d.d2u, 0.0) << m->model();
    }
    EXPECT_NEAR(dilatation(*m, 1.0).u, 0.0, 1e-12);
    EXPECT_NEAR(dilatation(*m, 1.0).du, 0.0, 1e-9);
    // At rest U'' is the bulk modulus.
    EXPECT_NEAR(dilatation(*m, 1.0).d2u, material::small_strain_constants(*m).bulk(),
                1e-6 * material::small_strain_constants(*m).bulk())
        << m->model();
  }
}

ElasticModel box_model(const Eigen::Vector3i& cells, const Eigen::Vector3d& size, double nu,
                       TetElement element = TetElement::Linear) {
  const BoxMesh box = make_box_mesh(Eigen::Vector3d::Zero(), size, cells);
  ElasticModel model(box.mesh, {BodyMaterial{std::make_shared<material::NeoHookean>(20e3, nu), 1000.0}});
  model.set_element(element);
  return model;
}

TEST(NodalPressure, AStabilizationMustBeAShareAndNeedsTheNodalPressureTet) {
  ElasticModel model = box_model(Eigen::Vector3i(1, 1, 1), Eigen::Vector3d(0.01, 0.01, 0.01), 0.45);
  EXPECT_TRUE(palpa::test::throws_error([&] { model.set_element(TetElement::NodalPressure, 1.0); }, ErrorKind::Input,
                                        {"stabilization of 1", "[0, 1)"}));
  EXPECT_TRUE(palpa::test::throws_error([&] { model.set_element(TetElement::Linear, 0.1); }, ErrorKind::Input,
                                        {"nodal-pressure"}));
  EXPECT_EQ(model.element(), TetElement::Linear);
  model.set_element(TetElement::NodalPressure, 0.25);
  EXPECT_EQ(model.stabilization(), 0.25);
}

TEST(NodalPressure, AHomogeneousDeformationGivesTheLinearTetsEnergyAndForces) {
  for (const double beta : {0.0, 0.3}) {
    ElasticModel model = box_model(Eigen::Vector3i(3, 2, 2), Eigen::Vector3d(0.03, 0.02, 0.02), 0.49);
    model.set_element(TetElement::NodalPressure, beta);
    Eigen::Matrix3d F;
    F << 1.1, 0.05, -0.02, 0.03, 0.92, 0.04, -0.01, 0.02, 0.97;
    Eigen::VectorXd u(model.num_dofs());
    for (Eigen::Index v = 0; v < model.num_vertices(); ++v) {
      const Eigen::Vector3d X = model.mesh().V.row(v).transpose();
      u.segment<3>(3 * v) = F * X - X;
    }
    Eigen::VectorXd p(u.size());
    for (Eigen::Index v = 0; v < model.num_vertices(); ++v) p.segment<3>(3 * v) = model.mesh().V.row(v).transpose() + u.segment<3>(3 * v);
    const VertexState s{u, p};
    const ElasticTerm linear(model);
    const DeviatoricTerm deviatoric(model);
    const NodalVolumeTerm nodal(model);
    Eigen::VectorXd g_linear = Eigen::VectorXd::Zero(u.size()), g_averaged = Eigen::VectorXd::Zero(u.size());
    const double e_linear = linear.add_gradient(s, g_linear);
    const double e_averaged = deviatoric.add_gradient(s, g_averaged) + nodal.add_gradient(s, g_averaged);
    EXPECT_GT(e_linear, 0.0);
    EXPECT_NEAR(e_averaged, e_linear, 1e-12 * e_linear);
    EXPECT_LE((g_averaged - g_linear).cwiseAbs().maxCoeff(), 1e-10 * g_linear.cwiseAbs().maxCoeff());
    EXPECT_NEAR(nodal.nodal_jacobians(u).minCoeff(), F.determinant(), 1e-13);
    EXPECT_NEAR(nodal.nodal_jacobians(u).maxCoeff(), F.determinant(), 1e-13);
    // The stress too is the linear tet's.
    ElasticModel plain = model;
    plain.set_element(TetElement::Linear);
    const Eigen::MatrixXd sigma = model.cauchy_stress(u), sigma_linear = plain.cauchy_stress(u);
    EXPECT_LE((sigma - sigma_linear).cwiseAbs().maxCoeff(), 1e-9 * sigma_linear.cwiseAbs().maxCoeff()) << beta;
  }
}

TEST(NodalPressure, StressCarriesThePatchPressureThatTheForcesAre) {
  // A bent block: each tet's stress is σ(F_e) with its own pressure share
  // swapped for its corners' patch pressures: the stress whose divergence
  // the element's forces are, and smoother in pressure than the linear
  // tet's (the scatter of J_e from tet to tet averaged out).
  ElasticModel model = box_model(Eigen::Vector3i(4, 2, 2), Eigen::Vector3d(0.04, 0.02, 0.02), 0.49);
  model.set_element(TetElement::NodalPressure);
  Eigen::VectorXd u(model.num_dofs());
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) {
    const Eigen::Vector3d X = model.mesh().V.row(v).transpose();
    u.segment<3>(3 * v) = Eigen::Vector3d(0.0, 0.0, -2.0 * X.x() * X.x() + 0.3 * X.y() * X.z());
  }
  ElasticModel plain = model;
  plain.set_element(TetElement::Linear);
  const Eigen::MatrixXd sigma = model.cauchy_stress(u), sigma_linear = plain.cauchy_stress(u);
  // Shear is the same; the pressures differ.
  EXPECT_LE((sigma.rightCols(3) - sigma_linear.rightCols(3)).cwiseAbs().maxCoeff(),
            1e-9 * sigma_linear.cwiseAbs().maxCoeff());
  const Eigen::VectorXd p = sigma.leftCols(3).rowwise().sum() / 3.0, p_linear = sigma_linear.leftCols(3).rowwise().sum() / 3.0;
  EXPECT_GT((p - p_linear).cwiseAbs().maxCoeff(), 1e-3 * p_linear.cwiseAbs().maxCoeff());
  const auto spread = [](const Eigen::VectorXd& x) { return (x.array() - x.mean()).square().mean(); };
  EXPECT_LT(spread(p), spread(p_linear));
  // The element's forces are the divergence of this stress: Σ_e σ_e ∂v_e/∂x.
  Eigen::VectorXd x(u.size());
  for (Eigen::Index v = 0; v < model.num_vertices(); ++v) x.segment<3>(3 * v) = model.mesh().V.row(v).transpose() + u.segment<3>(3 * v);
  const VertexState state{u, x};
  Eigen::VectorXd g = Eigen::VectorXd::Zero(u.size()), from_stress = Eigen::VectorXd::Zero(u.size());
  DeviatoricTerm(model).add_gradient(state, g);
  NodalVolumeTerm(model).add_gradient(state, g);
  for (Eigen::Index e = 0; e < model.num_elements(); ++e) {
    Vec12 dv;
    tet_volume(model.element_positions(u, e), &dv);
    Eigen::Matrix3d S;
    S << sigma(e, 0), sigma(e, 5), sigma(e, 4), sigma(e, 5), sigma(e, 1), sigma(e, 3), sigma(e, 4), sigma(e, 3), sigma(e, 2);
    for (int a = 0; a < 4; ++a) from_stress.segment<3>(3 * model.mesh().T(e, a)) += S * dv.segment<3>(3 * a);
  }
  EXPECT_LE((from_stress - g).cwiseAbs().maxCoeff(), 1e-8 * g.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace palpa::tet
